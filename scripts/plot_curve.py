#!/usr/bin/python3
"""Draws the load curves of gfmd curve (curve.csv + curve.json): contact area fraction, mean
gap, friction coefficient and leakage against the mean pressure, four panels on a log pressure
axis, with the percolation threshold (where the leakage stops) marked on every panel; for an
approach path (--approaches) the force against the approach and the contact area, loading and
unloading apart, with the pull-off force. The mean
gap is summary.json's mean_gap: the mean over the whole cell, contact points counting 0 (not
analysis.png's mean gap out of contact). Lengths in the case's grid.unit, else L. Exit status 4
when interrupted (nothing written)."""
import argparse
import csv
import json
import math
import os
import sys

import figure_io  # noqa: E402 (beside this script)

if __name__ == "__main__":
    figure_io.exit_on_interrupt_while_starting()

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    """A CSV cell as a float (None when empty)."""
    if text in ("", "null", None):
        return None
    try:
        v = float(text)
    except ValueError:
        return None
    return v if math.isfinite(v) else None


def column(rows, name):
    return [number(r.get(name)) for r in rows]


def pairs(x, y):
    return [(a, b) for a, b in zip(x, y) if a is not None and b is not None]


def mark_threshold(ax, perc, label):
    """The threshold as a vertical line, its bracket (last open, first sealed point) shaded; or a
    note in the panel's title that it was not reached."""
    if perc.get("reached"):
        br = perc["bracket"]
        ax.axvspan(br["open"]["pressure"], br["sealed"]["pressure"], color="C3", alpha=0.12, lw=0)
        ax.axvline(perc["pressure"], color="C3", ls="--", lw=1.2,
                   label=f"percolation threshold p* = {perc['pressure']:.3g}" if label else None)
    else:
        ax.set_title(ax.get_title() + "\n(percolation threshold not reached in the range)", fontsize=8,
                     color="C3")


def figure(table, meta_path=None):
    """The figure of curve.csv (and curve.json, default beside it); not saved. ValueError
    naming the table when it has no point."""
    here = os.path.dirname(table) or "."
    with open(table, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{table}: no finished points to draw")
    meta_path = meta_path or os.path.join(here, "curve.json")
    meta = {}
    if os.path.exists(meta_path):
        with open(meta_path) as f:
            meta = json.load(f)
    perc = meta.get("percolation", {})
    unit = figure_io.grid_unit(meta)
    lab = figure_io.label
    head = list(rows[0].keys())
    tags = [c[len("conductivity_"):] for c in head if c.startswith("conductivity_")]

    if meta.get("parameter") == "load.approach":
        return path_figure(rows, meta, unit)
    p = column(rows, "pressure")
    fig, axes = plt.subplots(2, 2, figsize=(9, 6.6), dpi=150, sharex=True)
    (a_ax, g_ax), (m_ax, k_ax) = axes

    xy = pairs(p, column(rows, "relative_contact_area"))
    a_ax.plot([a for a, _ in xy], [b for _, b in xy], "o-", color="C0")
    a_ax.set_ylabel(lab("contact area fraction A/A$_0$", "1"))
    a_ax.set_title("contact area", fontsize=9)

    xy = pairs(p, column(rows, "mean_gap"))
    g_ax.plot([a for a, _ in xy], [b for _, b in xy], "o-", color="C1")
    gaps = [b for _, b in xy]
    if len(gaps) > 1 and min(gaps) > 0 and max(gaps) / min(gaps) > 50:
        g_ax.set_yscale("log")
    g_ax.set_ylabel(lab(r"$\langle g\rangle$ over the cell", unit))
    g_ax.set_title("mean gap over the whole cell (contact points count 0)", fontsize=9)

    mu = pairs(p, column(rows, "friction_coefficient"))
    mud = pairs(p, column(rows, "friction_coefficient_downhill"))
    if mu:
        m_ax.plot([a for a, _ in mu], [b for _, b in mu], "o-", color="C2", label="from the dissipation")
        if mud:
            m_ax.plot([a for a, _ in mud], [b for _, b in mud], "s--", color="C2", alpha=0.6, ms=3,
                      label=r"$\mu_c F$ + downhill force")
    else:
        m_ax.text(0.5, 0.85, "frictionless case (friction.coefficient = 0)", transform=m_ax.transAxes,
                  ha="center", va="center", fontsize=8, color="0.4",
                  bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8})
    m_ax.set_ylabel(lab(r"friction coefficient $\mu$", "1"))
    m_ax.set_title("friction", fontsize=9)

    positive = []
    for t in tags:
        positive += [b for _, b in pairs(p, column(rows, "conductivity_" + t)) if b > 0]
    floor = min(positive) / 3 if positive else 0.0
    directions = perc.get("directions", {})
    for i, t in enumerate(tags):
        colour = f"C{4 + i}"
        xy = pairs(p, column(rows, "conductivity_" + t))
        pos = [(a, b) for a, b in xy if b > 0]
        k_ax.plot([a for a, _ in pos], [b for _, b in pos], "os^Dv"[i % 5] + ("-" if i == 0 else "--"),
                  color=colour, ms=6 - 1.5 * min(i, 2), label=f"along {t}")
        sealed = [a for a, o in zip(p, column(rows, "percolates_" + t)) if a is not None and o == 0]
        if sealed:
            k_ax.plot(sealed, [floor / 1.6**i] * len(sealed), "v", color=colour, ls="none", alpha=0.8,
                      label=f"sealed along {t} (K = 0)")
        d = directions.get(t, {})
        if len(tags) > 1 and d.get("reached") and d.get("pressure") != perc.get("pressure"):
            k_ax.axvline(d["pressure"], color=colour, ls=":", lw=1.2,
                         label=f"flow along {t} stops, p = {d['pressure']:.3g}")
    if positive:
        k_ax.set_yscale("log")
    k_ax.set_ylabel(lab(r"conductivity $K_\mathrm{eff}$", f"{unit}^3"))
    k_ax.set_title("leakage (Reynolds flow through the gap)", fontsize=9)

    for ax in axes.flat:
        if len([v for v in p if v]) > 1 and min(v for v in p if v) > 0:
            ax.set_xscale("log")
        mark_threshold(ax, perc, ax is a_ax)
        ax.grid(alpha=0.3)
    for ax in axes.flat:  # every panel with its own axis (sharex would leave the upper ones bare)
        ax.set_xlabel(lab("mean pressure p̄", "E*"))
        ax.tick_params(labelbottom=True)
    for ax in axes.flat:
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7, loc="best")

    title = os.path.basename(meta.get("case", "")) or "gfmd curve"
    if perc:
        title += ": " + perc.get("message", "")
    fig.suptitle(title, fontsize=9, wrap=True)
    fig.tight_layout()
    return fig


def path_figure(rows, meta, unit):
    """An approach path (gfmd curve --approaches, --unload): the normal force against the approach
    and against the contact area, loading and unloading apart (adhesion's hysteresis), the
    pull-off force marked."""
    lab = figure_io.label
    fig, (f_ax, a_ax) = plt.subplots(1, 2, figsize=(9, 3.8), dpi=150)
    branch = [r.get("branch", "load").strip('"') for r in rows]
    d, force, area = column(rows, "approach"), column(rows, "normal_force"), column(rows, "relative_contact_area")
    styles = {"load": ("o-", "C0"), "unload": ("s--", "C3")}
    labelled = set()
    start = 0
    for end in range(1, len(rows) + 1):  # each run of one branch, joined to the point before it
        if end < len(rows) and branch[end] == branch[start]:
            continue
        name = branch[start]
        style, colour = styles.get(name, ("o-", "C0"))
        idx = list(range(max(0, start - 1) if start > 0 else 0, end))
        label = None if name in labelled else name + "ing"
        labelled.add(name)
        for ax, x in ((f_ax, d), (a_ax, area)):
            xy = pairs([x[i] for i in idx], [force[i] for i in idx])
            ax.plot([a for a, _ in xy], [b for _, b in xy], style, color=colour, ms=3, label=label)
        start = end
    pull = meta.get("pull_off_force")
    for ax in (f_ax, a_ax):
        ax.axhline(0.0, color="0.5", lw=0.8)
        if pull is not None:
            ax.axhline(pull, color="C2", ls=":", lw=1.2, label=f"pull-off {pull:.4g}")
        ax.set_ylabel(lab("normal force F (negative: tension)", f"E* {unit}^2"))
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7, loc="best")
    f_ax.set_xlabel(lab(r"approach $\delta$", unit))
    f_ax.set_title("force along the approach path", fontsize=9)
    a_ax.set_xlabel(lab("contact area fraction A/A$_0$", "1"))
    a_ax.set_title("force against contact area", fontsize=9)
    fig.suptitle(os.path.basename(meta.get("case", "")) or "gfmd curve", fontsize=9)
    fig.tight_layout()
    return fig


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("table", help="curve.csv written by gfmd curve")
    ap.add_argument("--json", help="curve.json (default: next to the table)")
    ap.add_argument("-o", "--output", help="PNG path (default: curve.png next to the table)")
    ap.add_argument("--pdf", action="store_true", help="also write a PDF beside the PNG (figure_io.save)")
    args = ap.parse_args()
    here = os.path.dirname(args.table) or "."
    try:
        fig = figure(args.table, args.json)
    except ValueError as e:
        sys.exit(str(e))
    out = args.output or os.path.join(here, "curve.png")
    if args.pdf:
        base = out[:-4] if out.endswith(".png") else out
        figure_io.save(fig, base)
        print(base + ".png")
        return
    figure_io.save_png(fig, out)
    print(out)


if __name__ == "__main__":
    figure_io.run_main(main, "plot_curve.py")
