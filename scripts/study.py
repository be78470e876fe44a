#!/usr/bin/python3
"""Runs a study (studies/*.toml): the sweeps or single runs it names, reusing every result
that is already there, then draws its figure (PNG + PDF) and writes the plotted data as
CSV next to it.

    /usr/bin/python3 scripts/study.py studies/fig2d.toml [--quick] [-o out/studies]
    (or: ./build/gfmd study studies/fig2d.toml --quick)
"""
import argparse
import csv
import json
import os
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


def log(msg):
    print(msg, file=sys.stderr, flush=True)


NOT_CONVERGED = 3  # gfmd's exit status when a solve does not converge


def run(cmd, tolerate_not_converged=False):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0 and not (tolerate_not_converged and p.returncode == NOT_CONVERGED):
        sys.exit(f"study: command failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}{p.stderr}")
    return p


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
        d = series_dir(out, i)
        case = os.path.join(CASE_ROOT, s["case"])
        sets = list(s.get("set", [])) + list(mode_sets) + list(s.get("quick_set" if quick else "full_set", []))
        args = []
        for kv in sets:
            args += ["--set", kv]
        t = time.time()
        if study.get("kind") == "percolation":
            res = run_percolation_series(s, sets, d)
        elif study.get("kind") == "green":
            csvp = os.path.join(d, "green.csv")
            os.makedirs(d, exist_ok=True)
            run([GFMD, "green", "--poisson", ",".join(str(v) for v in s["poisson"]), "-o", csvp])
            res = read_table(csvp)
        elif study.get("kind", "sweep") == "sweep":
            p = run([GFMD, "sweep", case, "-o", d, "-q", "--plot", study["y"]] + args, tolerate_not_converged=True)
            table = os.path.join(d, "sweep.csv")
            if p.returncode != 0:
                why = (p.stderr.strip().splitlines() or ["not converged"])[-1]
                if not os.path.exists(table):
                    sys.exit(f"study: series '{s['label']}' failed with no finished point: {why}")
                log(f"study: series '{s['label']}' stopped early: {why}")
                incomplete.append({"series": s["label"], "reason": why})
                s = dict(s, label=s["label"] + " (stopped: not converged)")
            res = read_table(table)
        else:
            summary = os.path.join(d, "summary.json")
            run([GFMD, "run", case, "-o", d, "-q", "--resume"] + args)
            res = json.load(open(summary))
        dt = time.time() - t
        el = time.time() - t0
        left = el / (i + 1) * (total - i - 1)
        log(f"[{i + 1}/{total}] {s['label']}: {dt:.1f} s (elapsed {el:.0f} s, about {left:.0f} s left)")
        results.append((s, res))
    return results


def run_percolation_series(s, sets, d):
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
            run([GFMD, "percolation", case, "--direction", direction, "-o", os.path.join(d, tag), "-q"] + args + extra)
        out[tag] = json.load(open(pj))
    pstar = out["frictionless"]["critical_pressure"]
    for tag, extra in (("static_at_pstar", ["--set", "friction.coefficient=0"]), ("sliding_at_pstar", [])):
        run([GFMD, "run", case, "-o", os.path.join(d, tag), "-q", "--resume", "--set", f"load.pressure={pstar!r}"]
            + args + extra)
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
        ax.set_xlabel(spec.get("xlabel", x) if spec else study.get("xlabel", x))
        ax.set_ylabel(spec.get("ylabel", y) if spec else study.get("ylabel", y))
        if study.get("xscale"):
            ax.set_xscale(study["xscale"])
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
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("study")
    ap.add_argument("--quick", action="store_true", help="reduced resolution that runs in minutes")
    ap.add_argument("-o", "--output", default=os.path.join("out", "studies"))
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a setting for every run of the study, after the study's own (repeatable)")
    ap.add_argument("--runs-only", action="store_true",
                    help="run (or reuse) every series and stop: no figure, no matplotlib needed")
    args = ap.parse_args()
    global CASE_ROOT
    CASE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(args.study)))
    with open(args.study, "rb") as f:
        study = tomllib.load(f)
    name = os.path.splitext(os.path.basename(args.study))[0]
    mode = "quick" if args.quick else "full"
    out = os.path.join(args.output, name, mode)
    os.makedirs(out, exist_ok=True)
    t0 = time.time()
    incomplete = []
    results = run_series(study, list(study.get(mode, {}).get("set", [])) + args.set, out, args.quick, incomplete)
    if args.runs_only:
        print(f"{name} ({mode}): runs in {out}  [{time.time() - t0:.1f} s]")
        if incomplete:
            sys.exit(f"study: {len(incomplete)} series stopped early")
        return
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
    report = {"study": name, "mode": mode, "wall_time_s": time.time() - t0,
              "figure": fig_base + ".png", "series": [s["label"] for s, _ in results],
              "incomplete_series": incomplete}
    with open(os.path.join(out, "study.json.tmp"), "w") as f:
        json.dump(report, f, indent=2)
    os.replace(os.path.join(out, "study.json.tmp"), os.path.join(out, "study.json"))
    print(f"{name} ({mode}): {fig_base}.png, .pdf, .csv  [{report['wall_time_s']:.1f} s]")
    if incomplete:
        sys.exit(f"study: {len(incomplete)} series stopped early (drawn with their finished points): "
                 + "; ".join(f"{x['series']}: {x['reason']}" for x in incomplete))


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    main()
