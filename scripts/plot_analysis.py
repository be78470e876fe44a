#!/usr/bin/env python3
"""Draws analysis.png of a run directory from its analysis tables (written by gfmd run):
the indenter's power spectrum with the Hurst fit (spectrum.csv, summary.json), the contact
patches' area distribution (patches.csv), and the gap and pressure PDFs (distributions.csv).

    plot_analysis.py DIR
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import figure_io  # noqa: E402 (beside this script)


def read_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return rows


def main(d):
    with open(os.path.join(d, "summary.json")) as fh:
        summary = json.load(fh)
    unit = summary.get("input", {}).get("grid", {}).get("unit", "") or "length"
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
    ax.set_xlabel(f"wave number q (1/{unit})")
    ax.set_ylabel(f"C(q) ({unit}$^4$)")
    ax.set_title("indenter power spectrum")
    ax.legend(fontsize=8)
    # Contact patch areas: complementary cumulative distribution.
    ax = axes[0, 1]
    patches = read_csv(os.path.join(d, "patches.csv"))
    areas = np.sort(np.array([float(r["area"]) for r in patches]))[::-1]
    if len(areas):
        ax.loglog(areas, np.arange(1, len(areas) + 1), drawstyle="steps-post")
    p = a.get("patches", {})
    ax.set_xlabel(f"patch area A ({unit}$^2$)")
    ax.set_ylabel("number of patches with area ≥ A")
    perc = " (percolating)" if p.get("percolating") else ""
    ax.set_title(f"{p.get('count', len(areas))} contact patches{perc}")
    # Gap and pressure PDFs.
    dist = read_csv(os.path.join(d, "distributions.csv"))
    for ax, name, xlabel in ((axes[1, 0], "gap", f"gap g ({unit})"), (axes[1, 1], "pressure", "pressure p (E*)")):
        rows = [r for r in dist if r["quantity"] == name]
        lo = np.array([float(r["bin_low"]) for r in rows])
        hi = np.array([float(r["bin_high"]) for r in rows])
        pdf = np.array([float(r["pdf"]) for r in rows])
        if len(rows):
            ax.stairs(pdf, np.append(lo, hi[-1:]), fill=True, alpha=0.6)
        stats = a.get(name, {})
        if stats.get("samples"):
            ax.axvline(stats["mean"], color="k", lw=1, ls="--", label=f"mean {stats['mean']:.4g}")
            ax.legend(fontsize=8)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"PDF (1/{'E*' if name == 'pressure' else unit})")
        where = "out of contact" if name == "gap" else "in contact"
        ax.set_title(f"{name} distribution ({where}, {stats.get('samples', 0)} points)")
    fig.tight_layout()
    out = os.path.join(d, "analysis.png")
    figure_io.save_png(fig, out)
    return out


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    print(main(sys.argv[1]))
