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
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_file import PULL_OFF_COLUMNS, BadInput, load_study, seed_dir, series_dir  # noqa: E402
import study_runs  # noqa: E402
from study_runs import (BAD_INPUT, INTERRUPTED, INTERRUPTED_MESSAGE, NOT_CONVERGED, Interrupted, _child,  # noqa: E402
                        check_stop, curve_case, fail, green_table, install_signal_handlers, load_library, log,
                        percolation_case, run_case, sweep_case)


# The plotting modules (matplotlib, numpy) are loaded when a figure is drawn: `--runs-only`
# needs none of them (a machine that computes without drawing, e.g. a lent GPU machine).
def load_plotting():
    """The sweep, percolation and Green's-function figures (study_plots.py), drawn with Agg on
    figures of their own (figure_io.subplots: the process's pyplot backend is not touched)."""
    import study_plots  # noqa: E402

    return study_plots


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Case paths in a study are relative to the folder above the study file's (the repository
# root for studies/*.toml); set in main().
CASE_ROOT = ROOT

QUIET = False  # --quiet (gfmd study -q): only errors
DRAW_ONLY = False  # --draw-only: draw from the runs on disk, run nothing


def info(msg):
    """Progress and where the results went: not with --quiet."""
    if not QUIET:
        log(msg)


# ---------------------------------------------------------------------------------------
# Temporary files: everything this study writes goes to a temporary name first (gfmd's
# "<file>.tmp.<pid>", figure_io's "<base>.tmp.png" and "<table>.tmp"). An interrupted study
# removes the ones that appeared while it ran. The maps' staging file ".maps.tmp.nc" is not one:
# a run stopped while its maps were drawn keeps it, to draw them from later.
MAPS_STAGING = ".maps.tmp.nc"


def is_temporary(name):
    return name != MAPS_STAGING and (".tmp." in name or name.endswith(".tmp"))


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
        if curve.get("pull_off_at_path_end"):
            log(f"study: {what}: {study['x']} = {v!r}: the most tensile force is at the path's end or turning "
                f"point ({row['pull_off_approach']}): the pull-off may lie beyond it; extend approaches")
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


def main(argv=None, library=None, program=None):
    """The study of argv (sys.argv's by default); returns its exit status. `library`: the gfmd
    package that calls it in its own process (gfmd.study), which then solves the runs; `program`:
    the gfmd program for what starts it (GFMD_STUDY_RUNS=process)."""
    study_runs.reset(library, program)
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
    args = ap.parse_args(argv)
    global QUIET, DRAW_ONLY
    QUIET, DRAW_ONLY = args.quiet, args.draw_only
    study_runs.FORCE = args.force
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
            if args.draw_only and not os.path.isdir(out):
                # Nothing to draw from (a mistyped -o, or a study not run yet): not an empty figure.
                raise BadInput(f"--draw-only: no runs of this study in {out} (run it first, or check -o)")
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
    if DRAW_ONLY and not results:
        raise BadInput(f"--draw-only: no series of this study has runs in {out} (run it first, or check -o)")
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
