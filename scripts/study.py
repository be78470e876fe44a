#!/usr/bin/python3
"""Runs a study (studies/*.toml): the sweeps or single runs it names, reusing every result
that is already there, then draws its figure (PNG + PDF) and writes the plotted data as
CSV next to it; the last lines on standard error name the figure and the table.

    /usr/bin/python3 scripts/study.py studies/fig2d.toml [--quick] [-o out/studies]
    (or: ./build/gfmd study studies/fig2d.toml --quick)

Exit status: 0 done, 2 bad input (the study file, a --set, or a setting a run refused: one
line `gfmd study: FILE: reason` naming the key; series are counted from 1), 4 interrupted
(SIGINT/SIGTERM: the running gfmd is stopped and waited for, the temporary files of this
study are removed and finished runs are reused by the next call), 3 a run did not converge
or a sweep series stopped early (its finished points are drawn), 1 anything else.
"""
import argparse
import csv
import hashlib
import json
import math
import os
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_file import PULL_OFF_COLUMNS, BadInput, load_study, seed_dir, series_dir  # noqa: E402


# The plotting modules (matplotlib, numpy) are loaded when a figure is drawn: `--runs-only`
# needs none of them (a machine that computes without drawing, e.g. a lent GPU machine).
def load_plotting():
    """The sweep, percolation and Green's-function figures (study_plots.py), drawn with Agg."""
    import matplotlib

    matplotlib.use("Agg")
    import study_plots  # noqa: E402

    return study_plots


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# `gfmd study` names itself in GFMD; run from the source tree, the build's binary.
GFMD = os.environ.get("GFMD", os.path.join(ROOT, "build", "gfmd"))
# Case paths in a study are relative to the folder above the study file's (the repository
# root for studies/*.toml); set in main().
CASE_ROOT = ROOT


QUIET = False  # --quiet (gfmd study -q): only errors
FORCE = False  # --force: the runs may write into non-empty directories gfmd did not make
DRAW_ONLY = False  # --draw-only: draw from the runs on disk, run nothing


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def info(msg):
    """Progress and where the results went: not with --quiet."""
    if not QUIET:
        log(msg)


NOT_CONVERGED = 3  # gfmd's exit status when a solve does not converge
BAD_INPUT = 2      # ... for bad input (the study's exit status too)
INTERRUPTED = 4    # ... when stopped by SIGINT/SIGTERM (the study's exit status too)
INTERRUPTED_MESSAGE = "gfmd: study interrupted; run the same command again to continue"  # as gfmd study's


def fail(msg, status):
    """Ends the study with msg on standard error and an exit status (3: a run did not
    converge, 1: anything else)."""
    log(msg)
    sys.exit(status)


class Interrupted(Exception):
    """SIGINT/SIGTERM (or a run that was stopped by one): exit 4."""


# Signals. SIGINT and SIGTERM set STOP. While a gfmd run is being waited for, the signal is
# passed on to it (a Ctrl-C reaches it anyway; a SIGTERM sent to this process alone does
# not) and the run is waited for: gfmd stops at its next check, writes nothing half-done and
# exits 4. While this script computes or draws itself, the signal raises KeyboardInterrupt
# at once. Either way main() ends with one line and exit status 4.
STOP = []
_child = {"waiting": False, "proc": None, "exiting": False}


def _on_signal(signum, _frame):
    STOP.append(signum)
    if _child["exiting"]:
        return
    if _child["waiting"]:
        if _child["proc"] is not None:
            try:
                _child["proc"].send_signal(signum)  # nothing if it has ended
            except OSError:
                pass
        return
    _child["exiting"] = True  # once: the clean-up that follows is not interrupted again
    raise KeyboardInterrupt


def install_signal_handlers():
    signal.signal(signal.SIGINT, _on_signal)
    signal.signal(signal.SIGTERM, _on_signal)


def check_stop():
    if STOP:
        raise Interrupted()


# Each run reads its case file once (gfmd sweep, curve and run make every point from that
# text, and the surface of a height file once); a study runs gfmd once per series, so a case
# file, a height file or a master curve edited between two of its runs would mix two cases in
# one figure. The content each had at its first run, by path.
_CASE_DIGESTS = {}


def check_case_unchanged(path, what="case file"):
    """Records the file's content at its first run in this study; at a later run a changed
    content ends the study (exit status 1) instead of drawing series of two different cases."""
    with open(path, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    if _CASE_DIGESTS.setdefault(os.path.realpath(path), digest) != digest:
        fail(f"study: {path}: the {what} changed while the study ran (its earlier runs were solved "
             "from the previous content); run the study again (runs of the new content are solved again, "
             "finished ones of the old content are not reused for it)", 1)


def input_files(case, cmd):
    """The files a gfmd run of `case` reads besides it, as (path, what): the height file of a file
    indenter (indenter.path) and the master curves of a viscoelastic body (elastic.master_curve,
    and that of each elastic.viscoelastic_parts table), relative to the case file's folder as gfmd
    reads them; a --set of the run (in cmd) replaces the case's value."""
    import tomllib

    try:
        with open(case, "rb") as f:
            data = tomllib.load(f)
    except (OSError, ValueError):
        return []  # gfmd names the problem
    sets = {}
    for a, b in zip(cmd, cmd[1:]):
        if a == "--set" and "=" in b:
            k, v = b.split("=", 1)
            sets[k.strip()] = v.strip()

    def value(section, key):
        if f"{section}.{key}" in sets:
            try:
                return tomllib.loads("x = " + sets[f"{section}.{key}"])["x"]
            except ValueError:
                return None
        table = data.get(section)
        return table.get(key) if isinstance(table, dict) else None

    found = [(value("indenter", "path"), "height file"), (value("elastic", "master_curve"), "master curve file")]
    parts = value("elastic", "viscoelastic_parts")
    for part in parts if isinstance(parts, list) else []:
        if isinstance(part, dict):
            found.append((part.get("master_curve"), "master curve file"))
    base = os.path.dirname(os.path.abspath(case))
    return [(os.path.join(base, p), what) for p, what in found
            if isinstance(p, str) and p and os.path.isfile(os.path.join(base, p))]


# The gfmd commands that solve a case file (their second argument): its inputs are checked, and
# --force applies to them.
CASE_COMMANDS = ("run", "sweep", "percolation", "curve")


def run(cmd, tolerate_not_converged=False, what=""):
    """Runs a gfmd command (argument vector) and waits for it; on SIGINT/SIGTERM it is
    stopped and waited for, then Interrupted is raised. Exit status 2 of the run is bad
    input (a setting of the study or of --set): BadInput naming `what` and the run's reason."""
    check_stop()
    if len(cmd) > 2 and cmd[1] in CASE_COMMANDS and os.path.isfile(cmd[2]):
        check_case_unchanged(cmd[2])
        for path, kind in input_files(cmd[2], cmd):
            check_case_unchanged(path, kind)
    if FORCE and len(cmd) > 1 and cmd[1] in CASE_COMMANDS:
        cmd = cmd + ["--force"]
    _child["waiting"] = True
    try:
        try:
            p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, encoding="utf-8",
                                 errors="replace")
        except OSError as e:
            fail(f"study: cannot start {cmd[0]}: {e.strerror} (GFMD names the gfmd program)", 1)
        _child["proc"] = p
        if STOP:  # a signal came between Popen and the line above: pass it on now
            p.send_signal(STOP[-1])
        out, err = p.communicate()
    finally:
        _child["waiting"] = False
        _child["proc"] = None
    p = subprocess.CompletedProcess(cmd, p.returncode, out, err)
    if STOP or p.returncode == INTERRUPTED:
        raise Interrupted()
    if p.returncode == BAD_INPUT:
        why = " ".join(ln.strip() for ln in p.stderr.splitlines() if ln.strip())
        raise BadInput(f"{what}: {why or 'gfmd ' + cmd[1] + ' refused its input'}")
    if p.returncode != 0 and not (tolerate_not_converged and p.returncode == NOT_CONVERGED):
        fail(f"study: command failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}{p.stderr}",
             NOT_CONVERGED if p.returncode == NOT_CONVERGED else 1)
    return p


# ---------------------------------------------------------------------------------------
# Temporary files: everything this study writes goes to a temporary name first (gfmd's
# "<file>.tmp.<pid>", the maps' staging file ".maps.tmp.nc", figure_io's "<base>.tmp.png" and
# "<table>.tmp"). An interrupted study removes the ones that appeared while it ran.

def is_temporary(name):
    return ".tmp." in name or name.endswith(".tmp")


def temporary_files(top):
    found = set()
    for d, _, files in os.walk(top):
        found.update(os.path.join(d, f) for f in files if is_temporary(f))
    return found


def remove_new_temporary_files(top, before):
    for p in temporary_files(top) - before:
        try:
            os.remove(p)
        except OSError:
            pass


def read_table(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def run_series(study, mode_sets, out, quick, incomplete):
    """Runs every series; returns a list of (series, result) with result the sweep rows or
    the single run's summary. A sweep that stops at a point that does not converge keeps its
    finished points (drawn, labelled as stopped) and is listed in `incomplete`."""
    results = []
    total = len(study["series"])
    t0 = time.time()
    mode_seeds = study.get("quick" if quick else "full", {}).get("seeds")
    for i, s in enumerate(study["series"]):
        check_stop()
        if "seeds" in s and mode_seeds is not None:  # [quick] / [full] seeds: for every seeded series
            s = dict(s, seeds=mode_seeds)
        what = f"series[{i + 1}] ({s['label']})"
        d = series_dir(out, i)
        case = os.path.join(CASE_ROOT, s.get("case", ""))
        sets = list(s.get("set", [])) + list(mode_sets) + list(s.get("quick_set" if quick else "full_set", []))
        args = []
        for kv in sets:
            args += ["--set", kv]
        t = time.time()
        if DRAW_ONLY and study.get("kind", "sweep") != "sweep":
            raise BadInput(f"--draw-only: draws sweep studies only (this one is kind = \"{study.get('kind')}\")")
        if study.get("kind") == "percolation":
            res = run_percolation_series(s, sets, d, what)
        elif study.get("kind") == "green":
            csvp = os.path.join(d, "green.csv")
            os.makedirs(d, exist_ok=True)
            run([GFMD, "green", "--poisson", ",".join(str(v) for v in s["poisson"]), "-o", csvp], what=what)
            res = read_table(csvp)
        elif study.get("kind") == "pull_off":
            res, why = run_pull_off_series(study, case, d, args, what)
            if why:
                incomplete.append({"series": s["label"], "reason": why})
                s = dict(s, label=s["label"] + " (some paths stopped: not converged)")
        elif study.get("kind", "sweep") == "sweep" and "seeds" in s:
            # One sweep per seed (indenter.seed last, after every other setting); drawn as the
            # mean with bands, every seed in the table.
            res = {"seeds": {}}
            stopped = []
            for k, seed in enumerate(s["seeds"]):
                rows, why = run_sweep(case, seed_dir(out, i, seed), study, args + ["--set", f"indenter.seed={seed}"],
                                      f"{what} seed {seed}", s["label"])
                if rows is None:  # --draw-only: this seed was not run
                    log(f"study: {what}: seed {seed} has no runs in {seed_dir(out, i, seed)}: not drawn")
                    continue
                res["seeds"][seed] = rows
                if why:
                    stopped.append(f"seed {seed}: {why}")
                info(f"  {s['label']}: seed {seed} ({k + 1}/{len(s['seeds'])}) done, {time.time() - t:.0f} s")
            if stopped:
                incomplete.append({"series": s["label"], "reason": "; ".join(stopped)})
                s = dict(s, label=s["label"] + " (stopped: not converged)")
            if not res["seeds"]:
                log(f"study: {what}: no runs in {d}: not drawn")
                continue
        elif study.get("kind", "sweep") == "sweep":
            res, why = run_sweep(case, d, study, args, what, s["label"])
            if res is None:  # --draw-only: this series was not run
                log(f"study: {what}: no runs in {d}: not drawn")
                continue
            if why:
                incomplete.append({"series": s["label"], "reason": why})
                s = dict(s, label=s["label"] + " (stopped: not converged)")
        else:
            summary = os.path.join(d, "summary.json")
            run([GFMD, "run", case, "-o", d, "-q", "--resume"] + args, what=what)
            res = json.load(open(summary))
        dt = time.time() - t
        el = time.time() - t0
        left = el / (i + 1) * (total - i - 1)
        info(f"[{i + 1}/{total}] {s['label']}: {dt:.1f} s (elapsed {el:.0f} s, about {left:.0f} s left)")
        results.append((s, res))
    return results


def finished_sweep(d):
    """--draw-only: the rows of the sweep in d as it is on disk and, where it stopped at a point
    that did not converge, its reason (status.json); (None, None) where d holds no sweep."""
    table = os.path.join(d, "sweep.csv")
    if not os.path.exists(table):
        return None, None
    why = None
    try:
        status = json.load(open(os.path.join(d, "status.json")))
        if status.get("status") != "converged":
            why = status.get("reason") or status.get("status")
    except (OSError, ValueError):
        pass
    rows = read_table(table)
    return (rows, why) if rows else (None, None)


def run_sweep(case, d, study, args, what, label):
    """One gfmd sweep into d: (its rows, None) or, where it stopped at a point that did not
    converge, (its finished rows, the reason); no finished point at all ends the study.
    --draw-only: the sweep on disk, run nothing ((None, None) where there is none)."""
    if DRAW_ONLY:
        return finished_sweep(d)
    p = run([GFMD, "sweep", case, "-o", d, "-q", "--plot", study["y"]] + args, tolerate_not_converged=True, what=what)
    table = os.path.join(d, "sweep.csv")
    why = None
    if p.returncode != 0:
        why = (p.stderr.strip().splitlines() or ["not converged"])[-1]
        if not os.path.exists(table):
            fail(f"study: series '{label}' failed with no finished point: {why}", NOT_CONVERGED)
        log(f"study: series '{label}' stopped early: {why}")
    return read_table(table), why


def run_pull_off_series(study, case, d, args, what):
    """One unloading path per value of study["x"] (gfmd curve --approaches, warm-started point to
    point): a row per value with the path's pull-off (its most tensile force), the approach there,
    the jump-off, and at that point the equivalent contact radius sqrt(A/pi), the contact's extents
    along and across sliding and the tangential force. A path that stops at a point that does not
    converge leaves its row empty; returns (rows, the reasons or None)."""
    rows, stopped = [], []
    for k, v in enumerate(study["values"]):
        check_stop()
        pd = os.path.join(d, f"value_{k:02d}")
        cj = os.path.join(pd, "curve.json")
        row = {study["x"]: repr(float(v))}
        for c in PULL_OFF_COLUMNS:
            row[c] = ""
        rows.append(row)
        # gfmd curve reuses the finished points of the same path itself (and solves them again where
        # the case or a setting changed).
        p = run([GFMD, "curve", case, "--approaches", study["approaches"], "-o", pd, "-q"] + args
                + ["--set", f"{study['x']}={v!r}"], tolerate_not_converged=True, what=f"{what} {study['x']} = {v!r}")
        if p.returncode != 0:
            why = (p.stderr.strip().splitlines() or ["not converged"])[-1]
            stopped.append(f"{study['x']} = {v!r}: {why}")
            log(f"study: {what}: {study['x']} = {v!r} stopped: {why}")
            continue
        curve = json.load(open(cj))
        for c in ("pull_off_force", "pull_off_approach", "jump_off_approach"):
            if curve.get(c) is not None:
                row[c] = repr(float(curve[c]))
        points = sorted(p for p in os.listdir(os.path.join(pd, "points")) if p.startswith("point_"))
        summaries = [json.load(open(os.path.join(pd, "points", p, "summary.json"))) for p in points]
        if curve.get("pull_off_force") is not None and summaries:
            s = min(summaries, key=lambda x: x["normal_force"])
            grid = s["input"]["grid"]
            row["pull_off_contact_radius"] = repr(math.sqrt(s["relative_contact_area"] * grid["lx"] * grid["ly"]
                                                            / math.pi))
            row["pull_off_extent_longitudinal"] = repr(s["contact_extent_longitudinal"])
            row["pull_off_extent_transverse"] = repr(s["contact_extent_transverse"])
            row["pull_off_tangential_force"] = repr(s.get("tangential_force", 0.0))
        info(f"  {what}: {study['x']} = {v!r} ({k + 1}/{len(study['values'])}): pull-off {row['pull_off_force']}")
    return rows, "; ".join(stopped) or None


def run_percolation_series(s, sets, d, what):
    """Egg-crate constriction (paper Fig. 3 i-m): the frictionless threshold a_c* along x, the
    contact with and without friction at that pressure, and the thresholds with friction
    along and across sliding."""
    case = os.path.join(CASE_ROOT, s["case"])
    args = []
    for kv in sets:
        args += ["--set", kv]
    out = {}
    for tag, extra, direction in (("frictionless", ["--set", "friction.coefficient=0"], "x"),
                                  ("friction_along", [], "x"), ("friction_across", [], "y")):
        pj = os.path.join(d, tag, "percolation.json")
        if not os.path.exists(pj):
            run([GFMD, "percolation", case, "--direction", direction, "-o", os.path.join(d, tag), "-q"] + args + extra,
                what=what)
        out[tag] = json.load(open(pj))
    pstar = out["frictionless"]["critical_pressure"]
    for tag, extra in (("static_at_pstar", ["--set", "friction.coefficient=0"]), ("sliding_at_pstar", [])):
        run([GFMD, "run", case, "-o", os.path.join(d, tag), "-q", "--resume", "--set", f"load.pressure={pstar!r}"]
            + args + extra, what=what)
        out[tag] = json.load(open(os.path.join(d, tag, "summary.json")))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study")
    ap.add_argument("--quick", action="store_true", help="reduced resolution that runs in minutes")
    ap.add_argument("-o", "--output", default=os.path.join("out", "studies"))
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a setting for every run of the study, after the study's own (repeatable)")
    ap.add_argument("-q", "--quiet", action="store_true", help="print only errors")
    ap.add_argument("--force", action="store_true",
                    help="let the runs write into non-empty directories that gfmd did not make")
    ap.add_argument("--runs-only", action="store_true",
                    help="run (or reuse) every series and stop: no figure, no matplotlib needed")
    ap.add_argument("--draw-only", action="store_true",
                    help="draw from the runs on disk and run nothing (a point that did not converge is not "
                         "retried; a series or seed without runs is left out): sweep studies")
    args = ap.parse_args()
    global QUIET, FORCE, DRAW_ONLY
    QUIET, FORCE, DRAW_ONLY = args.quiet, args.force, args.draw_only
    if args.draw_only and args.runs_only:
        log(f"gfmd study: {args.study}: --draw-only and --runs-only exclude each other")
        return BAD_INPUT
    out = None
    before = set()
    try:
        try:
            global CASE_ROOT
            CASE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(args.study)))
            study = load_study(args.study, CASE_ROOT)
            for kv in args.set:
                if "=" not in kv:
                    raise BadInput(f"--set {kv}: must be KEY=VALUE")
            name = os.path.splitext(os.path.basename(args.study))[0]
            mode = "quick" if args.quick else "full"
            out = os.path.join(args.output, name, mode)
            try:
                os.makedirs(out, exist_ok=True)
            except OSError as e:
                raise BadInput(f"-o {args.output}: cannot create {out}: {e.strerror}") from None
            before = temporary_files(out)
            check_stop()
            return run_study(study, args, name, mode, out)
        except KeyboardInterrupt:
            raise Interrupted() from None
    except BadInput as e:
        log(f"gfmd study: {args.study}: {e}")
        return BAD_INPUT
    except Interrupted:
        _child["exiting"] = True  # a further signal now only waits for the clean-up
        if out is not None:
            remove_new_temporary_files(out, before)
        log(INTERRUPTED_MESSAGE)
        return INTERRUPTED


def run_study(study, args, name, mode, out):
    t0 = time.time()
    incomplete = []
    results = run_series(study, list(study.get(mode, {}).get("set", [])) + args.set, out, args.quick, incomplete)
    check_stop()
    if args.runs_only:
        info(f"{name} ({mode}): runs in {out}  [{time.time() - t0:.1f} s]")
        if incomplete:
            fail(f"study: {len(incomplete)} series stopped early", NOT_CONVERGED)
        return 0
    plots = load_plotting()
    fig_base = os.path.join(out, name)
    if study.get("kind") == "percolation":
        plots.plot_percolation(study, results, out, fig_base)
    elif study.get("kind") == "green":
        plots.plot_green(study, results, fig_base)
    elif study.get("kind", "sweep") in ("sweep", "pull_off"):
        plots.plot_sweeps(study, results, fig_base)
    else:
        import study_figures  # noqa: E402  (field maps and profiles; needs python3-netcdf4)

        study_figures.draw(study, results, out, fig_base)
    check_stop()
    tables = [p for p in (fig_base + ".csv", fig_base + "_ratios.csv") if os.path.isfile(p)]
    report = {"study": name, "mode": mode, "wall_time_s": time.time() - t0,
              "figure": fig_base + ".png", "figure_pdf": fig_base + ".pdf", "tables": tables,
              "series": [s["label"] for s, _ in results], "incomplete_series": incomplete}
    with open(os.path.join(out, "study.json.tmp"), "w") as f:
        json.dump(report, f, indent=2)
    os.replace(os.path.join(out, "study.json.tmp"), os.path.join(out, "study.json"))
    # Where it went (standard error: `gfmd study` does not pass this script's standard output on).
    info(f"{name} ({mode}) done in {report['wall_time_s']:.1f} s")
    info(f"  figure: {fig_base}.png (and .pdf)")
    info(f"  table:  {', '.join(tables)}")
    if incomplete:
        fail(f"study: {len(incomplete)} series stopped early (drawn with their finished points): "
             + "; ".join(f"{x['series']}: {x['reason']}" for x in incomplete), NOT_CONVERGED)
    return 0


if __name__ == "__main__":
    # Before anything else can take long, so that a Ctrl-C is never a traceback.
    install_signal_handlers()
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        log(INTERRUPTED_MESSAGE)
        sys.exit(INTERRUPTED)
