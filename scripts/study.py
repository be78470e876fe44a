#!/usr/bin/python3
"""Runs a study (studies/*.toml): the sweeps or single runs it names, reusing every result
that is already there, then draws its figure (PNG + PDF) and writes the plotted data as
CSV next to it; the last lines on standard error name the figure and the table.

    /usr/bin/python3 scripts/study.py studies/fig2d.toml [--quick] [-o out/studies]
    (or: ./build/gfmd study studies/fig2d.toml --quick)

The runs are solved in this process through the gfmd Python package that belongs to the gfmd
program calling it (GFMD: <build>/python/gfmd beside <build>/gfmd, or the installed package
that holds gfmd/bin/gfmd); where there is none (a program installed by CMake alone), or with
GFMD_STUDY_RUNS=process, each run starts that program (gfmd run, sweep, curve, percolation,
green) instead. Both make the same files.

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


def input_files(case, settings):
    """The files a gfmd run of `case` reads besides it, as (path, what): the height file of a file
    indenter (indenter.path) and the master curves of a viscoelastic body (elastic.master_curve,
    and that of each elastic.viscoelastic_parts table), relative to the case file's folder as gfmd
    reads them; a setting of the run (KEY=VALUE in settings) replaces the case's value."""
    import tomllib

    try:
        with open(case, "rb") as f:
            data = tomllib.load(f)
    except (OSError, ValueError):
        return []  # gfmd names the problem
    sets = {}
    for kv in settings:
        if "=" in kv:
            k, v = kv.split("=", 1)
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


def check_inputs(case, settings):
    """Before each run of a case: a case file, height file or master curve that changed since
    its first run in this study ends it (check_case_unchanged)."""
    check_stop()
    if os.path.isfile(case):
        check_case_unchanged(case)
        for path, kind in input_files(case, settings):
            check_case_unchanged(path, kind)


def set_args(settings):
    args = []
    for kv in settings:
        args += ["--set", kv]
    return args


def run(cmd, tolerate_not_converged=False, what=""):
    """Runs a gfmd command (argument vector; GFMD_STUDY_RUNS=process or no package) and waits
    for it; on SIGINT/SIGTERM it is stopped and waited for, then Interrupted is raised. Exit
    status 2 of the run is bad input (a setting of the study or of --set): BadInput naming
    `what` and the run's reason."""
    check_stop()
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


def stopped_reason(p):
    """Why a gfmd command that exited 3 stopped: the last line it printed."""
    return (p.stderr.strip().splitlines() or ["not converged"])[-1]


# ---------------------------------------------------------------------------------------
# The runs in this process: the gfmd package of the calling program (find_package), loaded by
# main(); None where the runs start the program instead.
LIB = None


def find_package(program):
    """The folder of the gfmd package that belongs to `program` (<build>/python/gfmd beside
    <build>/gfmd; <site>/gfmd for <site>/gfmd/bin/gfmd), or None."""
    where = os.path.dirname(os.path.realpath(program))
    for pkg in (os.path.join(where, "python", "gfmd"), os.path.dirname(where)):
        try:
            names = os.listdir(pkg)
        except OSError:
            continue
        if "__init__.py" in names and any(n.startswith("_core") and n.endswith(".so") for n in names):
            return pkg
    return None


def load_library():
    """Imports the package of the calling program for the runs (or leaves LIB None: the
    program is started per run); GFMD_STUDY_RUNS=process asks for the latter."""
    global LIB
    mode = os.environ.get("GFMD_STUDY_RUNS") or "library"  # unset or empty: the default
    if mode not in ("library", "process"):
        raise BadInput(f"GFMD_STUDY_RUNS: must be library or process (got {mode!r})")
    pkg = find_package(GFMD) if mode == "library" else None
    if pkg is None:
        return
    sys.path.insert(0, os.path.dirname(pkg))
    import gfmd  # noqa: E402

    if os.path.realpath(os.path.dirname(gfmd.__file__)) != os.path.realpath(pkg):
        log(f"study: warning: another gfmd package ({gfmd.__file__}) is loaded; the runs start {GFMD}")
        return
    LIB = gfmd


def call(what, f, *args, tolerate_not_converged=False, **kwargs):
    """A study of the gfmd package in this process: (its result, None), or where a solve did not
    converge and tolerate_not_converged (None, the reason). Bad input is BadInput naming `what`;
    Ctrl-C or SIGTERM (KeyboardInterrupt: the package stops the solve within an iteration and
    keeps what is finished, as gfmd does) is Interrupted."""
    check_stop()
    try:
        return f(*args, **kwargs), None
    except KeyboardInterrupt:
        raise Interrupted() from None
    except LIB.InputError as e:
        raise BadInput(f"{what}: {e}") from None
    except LIB.SolveError as e:
        if tolerate_not_converged:
            return None, str(e)
        fail(f"study: {what}: {e}", NOT_CONVERGED)
    except OSError as e:
        fail(f"study: {what}: {e}", 1)


# The runs a study makes, each into its directory d, with the settings of the study and its
# series (KEY=VALUE); in this process (LIB) or by starting gfmd.

def run_case(case, d, settings, what):
    """One case (gfmd run --resume: a finished result is reused); returns its summary."""
    check_inputs(case, settings)
    if LIB is not None:
        call(what, LIB.run, case, set=settings, output=d, force=FORCE, resume=True)
    else:
        run([GFMD, "run", case, "-o", d, "-q", "--resume"] + set_args(settings) + (["--force"] if FORCE else []),
            what=what)
    with open(os.path.join(d, "summary.json")) as f:
        return json.load(f)


def sweep_case(case, d, settings, y, what):
    """The case's own [sweep] drawn against y (gfmd sweep --plot y): None, or where a point did
    not converge the reason (the finished points are kept in d)."""
    check_inputs(case, settings)
    if LIB is not None:
        return call(what, LIB.sweep, case, output=d, set=settings, plot=y, force=FORCE,
                    tolerate_not_converged=True)[1]
    p = run([GFMD, "sweep", case, "-o", d, "-q", "--plot", y] + set_args(settings) + (["--force"] if FORCE else []),
            tolerate_not_converged=True, what=what)
    return stopped_reason(p) if p.returncode != 0 else None


def curve_case(case, d, settings, approaches, what):
    """An approach path (gfmd curve --approaches; finished points of the same path are reused):
    None, or the reason it stopped."""
    check_inputs(case, settings)
    if LIB is not None:
        return call(what, LIB.curve, case, approaches=approaches, output=d, set=settings, force=FORCE,
                    tolerate_not_converged=True)[1]
    p = run([GFMD, "curve", case, "--approaches", approaches, "-o", d, "-q"] + set_args(settings)
            + (["--force"] if FORCE else []), tolerate_not_converged=True, what=what)
    return stopped_reason(p) if p.returncode != 0 else None


def percolation_case(case, d, settings, direction, what):
    """The percolation threshold along direction (gfmd percolation) into d."""
    check_inputs(case, settings)
    if LIB is not None:
        call(what, LIB.percolation, case, direction, set=settings, output=d, force=FORCE)
    else:
        run([GFMD, "percolation", case, "--direction", direction, "-o", d, "-q"] + set_args(settings)
            + (["--force"] if FORCE else []), what=what)


def green_table(poisson, csv_path, what):
    """The Green's tensor table for these Poisson ratios (gfmd green) into csv_path."""
    if LIB is not None:
        call(what, LIB.green, poisson=[float(v) for v in poisson], output=csv_path)
    else:
        run([GFMD, "green", "--poisson", ",".join(str(v) for v in poisson), "-o", csv_path], what=what)


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
        t = time.time()
        if DRAW_ONLY and study.get("kind", "sweep") != "sweep":
            raise BadInput(f"--draw-only: draws sweep studies only (this one is kind = \"{study.get('kind')}\")")
        if study.get("kind") == "percolation":
            res = run_percolation_series(s, sets, d, what)
        elif study.get("kind") == "green":
            csvp = os.path.join(d, "green.csv")
            os.makedirs(d, exist_ok=True)
            green_table(s["poisson"], csvp, what)
            res = read_table(csvp)
        elif study.get("kind") == "pull_off":
            res, why = run_pull_off_series(study, case, d, sets, what)
            if why:
                incomplete.append({"series": s["label"], "reason": why})
                s = dict(s, label=s["label"] + " (some paths stopped: not converged)")
        elif study.get("kind", "sweep") == "sweep" and "seeds" in s:
            # One sweep per seed (indenter.seed last, after every other setting); drawn as the
            # mean with bands, every seed in the table.
            res = {"seeds": {}}
            stopped = []
            for k, seed in enumerate(s["seeds"]):
                rows, why = run_sweep(case, seed_dir(out, i, seed), study, sets + [f"indenter.seed={seed}"],
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
            res, why = run_sweep(case, d, study, sets, what, s["label"])
            if res is None:  # --draw-only: this series was not run
                log(f"study: {what}: no runs in {d}: not drawn")
                continue
            if why:
                incomplete.append({"series": s["label"], "reason": why})
                s = dict(s, label=s["label"] + " (stopped: not converged)")
        else:
            res = run_case(case, d, sets, what)
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


def run_sweep(case, d, study, settings, what, label):
    """One gfmd sweep into d: (its rows, None) or, where it stopped at a point that did not
    converge, (its finished rows, the reason); no finished point at all ends the study.
    --draw-only: the sweep on disk, run nothing ((None, None) where there is none)."""
    if DRAW_ONLY:
        return finished_sweep(d)
    why = sweep_case(case, d, settings, study["y"], what)
    table = os.path.join(d, "sweep.csv")
    if why is not None:
        if not os.path.exists(table):
            fail(f"study: series '{label}' failed with no finished point: {why}", NOT_CONVERGED)
        log(f"study: series '{label}' stopped early: {why}")
    return read_table(table), why


def run_pull_off_series(study, case, d, settings, what):
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
        why = curve_case(case, pd, settings + [f"{study['x']}={v!r}"], study["approaches"],
                         f"{what} {study['x']} = {v!r}")
        if why is not None:
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
    out = {}
    for tag, extra, direction in (("frictionless", ["friction.coefficient=0"], "x"),
                                  ("friction_along", [], "x"), ("friction_across", [], "y")):
        pj = os.path.join(d, tag, "percolation.json")
        if not os.path.exists(pj):
            percolation_case(case, os.path.join(d, tag), list(sets) + extra, direction, what)
        out[tag] = json.load(open(pj))
    pstar = out["frictionless"]["critical_pressure"]
    for tag, extra in (("static_at_pstar", ["friction.coefficient=0"]), ("sliding_at_pstar", [])):
        out[tag] = run_case(case, os.path.join(d, tag), [f"load.pressure={pstar!r}"] + list(sets) + extra, what)
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
            if not args.draw_only:
                load_library()
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
