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
import json
import os
import signal
import subprocess
import sys
import time
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

# The plotting modules (matplotlib, numpy) are loaded when a figure is drawn: `--runs-only`
# needs none of them (a machine that computes without drawing, e.g. a lent GPU machine).
plt = np = save = write_csv = None


def load_plotting():
    global plt, np, save, write_csv
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt_  # noqa: E402
    import numpy as np_  # noqa: E402
    from figure_io import save as save_, write_csv as write_csv_  # noqa: E402

    plt, np, save, write_csv = plt_, np_, save_, write_csv_

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# `gfmd study` names itself in GFMD; run from the source tree, the build's binary.
GFMD = os.environ.get("GFMD", os.path.join(ROOT, "build", "gfmd"))
# Case paths in a study are relative to the folder above the study file's (the repository
# root for studies/*.toml); set in main().
CASE_ROOT = ROOT


QUIET = False  # --quiet (gfmd study -q): only errors
FORCE = False  # --force: the runs may write into non-empty directories gfmd did not make


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


class BadInput(Exception):
    """A bad study file, setting or option: exit 2 with `gfmd study: <what>: <reason>`."""


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


def run(cmd, tolerate_not_converged=False, what=""):
    """Runs a gfmd command (argument vector) and waits for it; on SIGINT/SIGTERM it is
    stopped and waited for, then Interrupted is raised. Exit status 2 of the run is bad
    input (a setting of the study or of --set): BadInput naming `what` and the run's reason."""
    check_stop()
    if FORCE and len(cmd) > 1 and cmd[1] in ("run", "sweep", "percolation"):
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
# The study file, checked before anything runs.

# Top-level tables of a case file (src/case/config.cpp: kSections).
CASE_SECTIONS = ("grid", "elastic", "indenter", "load", "friction", "interaction", "solver", "output",
                 "sweep", "stress", "flow")
KINDS = ("sweep", "runs", "percolation", "green")
FIGURES = ("maps", "cross_section", "profiles")


def _type_name(v):
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "an array",
            dict: "a table"}.get(type(v), type(v).__name__)


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _string(d, key, where, required=False):
    if key not in d:
        if required:
            raise BadInput(f"{where}{key}: missing (a string is needed)")
        return
    if not isinstance(d[key], str):
        raise BadInput(f"{where}{key}: must be a string (got {_type_name(d[key])})")


def _number(d, key, where):
    if key in d and not _is_number(d[key]):
        raise BadInput(f"{where}{key}: must be a number (got {_type_name(d[key])})")


def _settings(d, key, where):
    if key not in d:
        return
    v = d[key]
    if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
        raise BadInput(f"{where}{key}: must be a list of strings (\"key=value\")")
    for x in v:
        if "=" not in x:
            raise BadInput(f"{where}{key}: \"{x}\" is not key=value")


def _tables(d, key, where, required=False):
    if key not in d:
        if required:
            raise BadInput(f"{where}no [[{key}]] table")
        return []
    v = d[key]
    if not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
        raise BadInput(f"{where}{key}: must be an array of tables ([[{key}]]), got {_type_name(v)}")
    if required and not v:
        raise BadInput(f"{where}no [[{key}]] table")
    return v


def load_study(path, case_root):
    """The study file as a dict, or BadInput naming the file and the key that is wrong."""
    if not os.path.exists(path):
        raise BadInput("no such file")
    if os.path.isdir(path):
        raise BadInput("is a directory, not a study file (studies/*.toml)")
    try:
        with open(path, "rb") as f:
            study = tomllib.load(f)
    except OSError as e:
        raise BadInput(f"cannot read: {e.strerror}") from None
    except UnicodeDecodeError:
        raise BadInput("not a TOML file (not UTF-8 text)") from None
    except tomllib.TOMLDecodeError as e:
        raise BadInput(f"not valid TOML: {e}") from None
    if "series" not in study:
        found = [k for k in CASE_SECTIONS if isinstance(study.get(k), dict)]
        if found:
            raise BadInput(f"this is a case file ([{found[0]}]), use gfmd run; a study has [[series]] tables "
                           "naming case files (studies/*.toml)")
    series = _tables(study, "series", "", required=True)
    _string(study, "title", "")
    _string(study, "kind", "")
    kind = study.get("kind", "sweep")
    if kind not in KINDS:
        raise BadInput(f"kind: must be one of {', '.join(repr(k) for k in KINDS)} (got {kind!r})")
    for mode in ("quick", "full"):
        if mode in study:
            if not isinstance(study[mode], dict):
                raise BadInput(f"{mode}: must be a table ([{mode}]), got {_type_name(study[mode])}")
            _settings(study[mode], "set", f"{mode}.")
    if kind == "sweep":
        _string(study, "x", "", required=True)
        _string(study, "y", "", required=True)
        for key in ("xlabel", "ylabel", "xscale", "yscale"):
            _string(study, key, "")
        for key in ("x_scale", "y_scale"):
            _number(study, key, "")
        cols = study.get("table_columns", [])
        if not isinstance(cols, list) or not all(isinstance(c, str) for c in cols):
            raise BadInput("table_columns: must be a list of strings")
        if "published" in study:
            pub = study["published"]
            if not isinstance(pub, dict):
                raise BadInput(f"published: must be a table ([published]), got {_type_name(pub)}")
            _string(pub, "divide_by", "published.", required=True)
            for key in ("xlabel", "ylabel", "title", "caption"):
                _string(pub, key, "published.")
    elif kind == "runs":
        _string(study, "figure", "")
        figure = study.get("figure", "maps")
        if figure not in FIGURES:
            raise BadInput(f"figure: must be one of {', '.join(repr(k) for k in FIGURES)} (got {figure!r})")
        _number(study, "crop", "")
        if figure in ("maps", "profiles"):
            for i, spec in enumerate(_tables(study, figure, "", required=True), 1):
                _string(spec, "var", f"{figure}[{i}].", required=True)
                _string(spec, "label", f"{figure}[{i}].")
                _string(spec, "cmap", f"{figure}[{i}].")
                _string(spec, "scale_to", f"{figure}[{i}].")
                for key in ("scale", "vmin", "vmax"):
                    _number(spec, key, f"{figure}[{i}].")
    for i, s in enumerate(series, 1):
        where = f"series[{i}]."
        _string(s, "label", where, required=True)
        for key in ("color", "style"):
            _string(s, key, where)
        _number(s, "x_scale", where)
        for key in ("set", "quick_set", "full_set"):
            _settings(s, key, where)
        if kind == "green":
            p = s.get("poisson")
            if not isinstance(p, list) or not p or not all(_is_number(v) for v in p):
                raise BadInput(f"{where}poisson: must be a non-empty list of numbers")
            continue
        _string(s, "case", where, required=True)
        case = os.path.join(case_root, s["case"])
        if not os.path.isfile(case):
            raise BadInput(f"{where}case: {s['case']}: no such file (case paths are relative to {case_root})")
    return study


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


def series_dir(out, i):
    return os.path.join(out, f"series_{i:02d}")


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
    for i, s in enumerate(study["series"]):
        check_stop()
        what = f"series[{i + 1}] ({s['label']})"
        d = series_dir(out, i)
        case = os.path.join(CASE_ROOT, s.get("case", ""))
        sets = list(s.get("set", [])) + list(mode_sets) + list(s.get("quick_set" if quick else "full_set", []))
        args = []
        for kv in sets:
            args += ["--set", kv]
        t = time.time()
        if study.get("kind") == "percolation":
            res = run_percolation_series(s, sets, d, what)
        elif study.get("kind") == "green":
            csvp = os.path.join(d, "green.csv")
            os.makedirs(d, exist_ok=True)
            run([GFMD, "green", "--poisson", ",".join(str(v) for v in s["poisson"]), "-o", csvp], what=what)
            res = read_table(csvp)
        elif study.get("kind", "sweep") == "sweep":
            p = run([GFMD, "sweep", case, "-o", d, "-q", "--plot", study["y"]] + args, tolerate_not_converged=True,
                    what=what)
            table = os.path.join(d, "sweep.csv")
            if p.returncode != 0:
                why = (p.stderr.strip().splitlines() or ["not converged"])[-1]
                if not os.path.exists(table):
                    fail(f"study: series '{s['label']}' failed with no finished point: {why}", NOT_CONVERGED)
                log(f"study: series '{s['label']}' stopped early: {why}")
                incomplete.append({"series": s["label"], "reason": why})
                s = dict(s, label=s["label"] + " (stopped: not converged)")
            res = read_table(table)
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


def plot_percolation(study, results, out, fig_base):
    import netCDF4

    n = len(results)
    fig, axes = plt.subplots(1, n, figsize=(3.2 * n, 3.3), dpi=150, squeeze=False)
    rows = []
    for i, (s, res) in enumerate(results):
        d = series_dir(out, i)
        masks = []
        for tag in ("static_at_pstar", "sliding_at_pstar"):
            with netCDF4.Dataset(os.path.join(d, tag, "fields.nc")) as nc:
                masks.append(np.array(nc.variables["contact"][:]) > 0.5)
        img = np.ones(masks[0].shape + (3,))
        img[masks[0] & ~masks[1]] = (0.2, 0.4, 0.9)   # frictionless only: blue
        img[~masks[0] & masks[1]] = (1.0, 0.6, 0.1)   # with friction only: orange
        img[masks[0] & masks[1]] = (0.55, 0.3, 0.65)  # both: purple
        ax = axes[0][i]
        ax.imshow(img, origin="lower", extent=[0, 1, 0, 1])
        ax.set_title(s["label"], fontsize=7)
        ax.set_xlabel("x / λ  (sliding →)", fontsize=7)
        ax.tick_params(labelsize=6)
        a0 = res["frictionless"]["critical_relative_contact_area"]
        a1 = res["sliding_at_pstar"]["relative_contact_area"]
        ax.text(0.02, 0.02, f"a_c* = {a0:.3f}\nwith friction at p*: {a1:.3f}", fontsize=6, transform=ax.transAxes,
                va="bottom")
        rows.append([s["label"], a0, res["frictionless"]["critical_pressure"],
                     res["static_at_pstar"]["relative_contact_area"], a1,
                     res["friction_along"]["critical_relative_contact_area"],
                     res["friction_across"]["critical_relative_contact_area"]])
    fig.suptitle(study.get("title", ""), fontsize=8)
    fig.tight_layout()
    save(fig, fig_base)
    write_csv(fig_base + ".csv", ["series", "a_c*_frictionless", "p*", "a_c_static_at_p*", "a_c_sliding_at_p*",
                                  "a_c*_friction_along_sliding", "a_c*_friction_across_sliding"], rows)


def col(rows, key):
    return np.array([float(r[key]) if r.get(key, "") not in ("", "null") else np.nan for r in rows])


def plot_sweeps(study, results, fig_base):
    """One panel of y against x per series. With a [published] table (divide_by = a summary
    column, e.g. the realised rms gradient) a first panel draws x and y divided by that
    column, the way a published panel was drawn, and the plain axes follow as a second panel."""
    x, y = study["x"], study["y"]
    xs = float(study.get("x_scale", 1.0))
    ys = float(study.get("y_scale", 1.0))
    pub = study.get("published")
    panels = ([("published", pub)] if pub else []) + [("plain", None)]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels), 3.4 + (0.4 if pub else 0)), dpi=150,
                             squeeze=False)
    data = {}
    for (kind, spec), ax in zip(panels, axes[0]):
        for s, rows in results:
            xv = col(rows, x) * xs * float(s.get("x_scale", 1.0))
            yv = col(rows, y) * ys
            if spec:
                g = col(rows, spec["divide_by"])
                xv, yv = xv / g, yv / g
            ax.plot(xv, yv, s.get("style", "o-"), label=s["label"], color=s.get("color"))
            extra = [col(rows, c) for c in study.get("table_columns", [])]
            data[(kind, s["label"])] = (xv, yv, extra)
        # Without a label in the study file: the quantity's name and unit (figure_io), and a log
        # axis where the swept values are log-spaced (as gfmd sweep draws them).
        import figure_io
        from plot_sweep import log_spaced
        ax.set_xlabel(spec.get("xlabel", x) if spec else study.get("xlabel", figure_io.quantity_label(x)))
        ax.set_ylabel(spec.get("ylabel", y) if spec else study.get("ylabel", figure_io.quantity_label(y)))
        if study.get("xscale"):
            ax.set_xscale(study["xscale"])
        elif not spec:
            spaced = [log_spaced(list(col(rows, x))) for _, rows in results if len(rows) > 2]
            if spaced and all(spaced):
                ax.set_xscale("log")
        if study.get("yscale"):
            ax.set_yscale(study["yscale"])
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title((spec or {}).get("title", study.get("title", "")), fontsize=8)
    if pub and pub.get("caption"):
        fig.text(0.5, 0.01, pub["caption"], ha="center", va="bottom", fontsize=6.5)
        fig.tight_layout(rect=(0, 0.07, 1, 1))
    else:
        fig.tight_layout()
    save(fig, fig_base)
    # Extra summary columns (e.g. stick_fraction) per point, as listed in table_columns.
    write_csv(fig_base + ".csv", ["panel", "series", "x", "y"] + list(study.get("table_columns", [])),
              [[kind, label, repr(float(a)), repr(float(b))] + [repr(float(e[k])) for e in extra]
               for (kind, label), (xv, yv, extra) in data.items() for k, (a, b) in enumerate(zip(xv, yv))])


def plot_green(study, results, fig_base):
    fig, ax = plt.subplots(figsize=(4.6, 3.4), dpi=150)
    rows_out = []
    for _, rows in results:
        nus = sorted({r["poisson"] for r in rows}, key=float)
        for nu in nus:
            sel = [r for r in rows if r["poisson"] == nu]
            qh = np.array([float(r["qh"]) for r in sel])
            im = np.array([float(r["im_phi13"]) for r in sel])
            ax.plot(qh, im, label=f"ν = {float(nu):g}")
            rows_out += [[nu, a, b] for a, b in zip(qh, im)]
    ax.set_xscale("log")
    ax.set_xlabel("q h")
    ax.set_ylabel("Im Φ_13")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(study.get("title", ""), fontsize=8)
    fig.tight_layout()
    save(fig, fig_base)
    write_csv(fig_base + ".csv", ["poisson", "qh", "im_phi13"], rows_out)



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
    args = ap.parse_args()
    global QUIET, FORCE
    QUIET, FORCE = args.quiet, args.force
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
    load_plotting()
    fig_base = os.path.join(out, name)
    if study.get("kind") == "percolation":
        plot_percolation(study, results, out, fig_base)
    elif study.get("kind") == "green":
        plot_green(study, results, fig_base)
    elif study.get("kind", "sweep") == "sweep":
        plot_sweeps(study, results, fig_base)
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
