#!/usr/bin/env python3
"""Draws analysis.png of a run directory from its analysis tables (written by gfmd run):
the indenter's power spectrum with the Hurst fit (spectrum.csv, summary.json), the contact
patches' area distribution (patches.csv), and the gap and pressure PDFs (distributions.csv).
The gap PDF is over the points out of contact, and its dashed line is their mean gap (the
"mean gap out of contact", summary.json analysis.gap.mean), which is not summary.json's
mean_gap (the mean over the whole cell, contact points counting 0). Exit status 4 when
interrupted (nothing written).

    plot_analysis.py DIR
"""
import csv
import json
import os
import sys

import figure_io  # noqa: E402 (beside this script)

if __name__ == "__main__":
    figure_io.exit_on_interrupt_while_starting()

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return rows


def figure(d):
    """The figure of run directory d's analysis tables (not saved)."""
    with open(os.path.join(d, "summary.json")) as fh:
        summary = json.load(fh)
    unit = figure_io.grid_unit(summary)
    u = figure_io.unit_text(unit)
    lab = figure_io.label
    a = summary.get("analysis", {})
    fig, axes = plt.subplots(2, 2, figsize=(9.5, 7.5), dpi=120)
    # Power spectrum and the Hurst fit.
    ax = axes[0, 0]
    spec = read_csv(os.path.join(d, "spectrum.csv"))
    q = np.array([float(r["q"]) for r in spec])
    c = np.array([float(r["C"]) for r in spec])
    ok = c > 1e-12 * c.max() if len(c) else c > 0  # modes outside a generated band hold round-off only
    ax.loglog(q[ok], c[ok], ".", ms=4, label="isotropic PSD")
    fit = a.get("spectrum")
    if fit:
        qq = np.geomspace(fit["q_min"], fit["q_max"], 50)
        ax.loglog(qq, fit["prefactor"] * qq ** (-2 - 2 * fit["hurst"]), "-", lw=1.5,
                  label=f"fit: H = {fit['hurst']:.3f} ($r^2$ = {fit['r2']:.4f})")
    ax.set_xlabel(f"wave number q (1/{u})")
    ax.set_ylabel(lab("power spectrum C(q)", f"{unit}^4"))
    ax.set_title("indenter power spectrum")
    ax.legend(fontsize=8, loc="best")
    # Contact patch areas: complementary cumulative distribution.
    ax = axes[0, 1]
    patches = read_csv(os.path.join(d, "patches.csv"))
    areas = np.sort(np.array([float(r["area"]) for r in patches]))[::-1]
    if len(areas):
        ax.loglog(areas, np.arange(1, len(areas) + 1), drawstyle="steps-post", marker="o" if len(areas) < 3 else "")
    p = a.get("patches", {})
    ax.set_xlabel(lab("patch area A", f"{unit}^2"))
    ax.set_ylabel(lab("number of patches with area ≥ A", "1"))
    perc = " (percolating)" if p.get("percolating") else ""
    count = p.get("count", len(areas))
    ax.set_title(f"{count} contact patch{'' if count == 1 else 'es'}{perc}")
    # Gap and pressure PDFs.
    dist = read_csv(os.path.join(d, "distributions.csv"))
    for ax, name, xlabel in ((axes[1, 0], "gap", lab("gap g", unit)), (axes[1, 1], "pressure", lab("pressure p", "E*"))):
        rows = [r for r in dist if r["quantity"] == name]
        lo = np.array([float(r["bin_low"]) for r in rows])
        hi = np.array([float(r["bin_high"]) for r in rows])
        pdf = np.array([float(r["pdf"]) for r in rows])
        if len(rows):
            ax.stairs(pdf, np.append(lo, hi[-1:]), fill=True, alpha=0.6)
        stats = a.get(name, {})
        where = "out of contact" if name == "gap" else "in contact"
        title = f"{name} distribution ({where}, {stats.get('samples', 0)} points)"
        if stats.get("samples"):
            # The mean of the drawn points, named for what it is (in the title: no legend on the PDF).
            ax.axvline(stats["mean"], color="k", lw=1, ls="--")
            mean = (f"mean gap out of contact = {stats['mean']:.4g} {u}" if name == "gap"
                    else f"mean pressure in contact = {stats['mean']:.4g} E*")
            title += f"\ndashed: {mean}"
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"PDF (1/{'E*' if name == 'pressure' else u})")
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    return fig


def main(d, batch=None):
    """Draws analysis.png in d; into batch (a figure_io.Batch, published by the caller) or,
    without one, written at once. Returns its path."""
    return figure_io.save_png_or_stage(figure(d), os.path.join(d, "analysis.png"), batch)


def _script():
    print(main(sys.argv[1]))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    figure_io.run_main(_script, "plot_analysis.py")
