#!/usr/bin/python3
"""Draws profiles.csv of a gfmd run (line profiles through the pressure maximum along and
across the sliding direction) as profiles.png next to it."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(path):
    with open(path, newline="") as f:
        lines = [l for l in f if not l.startswith("#")]
    rows = list(csv.DictReader(lines))
    s = [float(r["s"]) for r in rows]
    names = [k[: -len("_longitudinal")] for k in rows[0] if k.endswith("_longitudinal")]
    names = [n for n in names if n not in ("ux", "uy", "e1_y", "sigma_yz", "sigma_xy")]
    cols = 3
    nrows = (len(names) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(3.2 * cols, 2.0 * nrows), dpi=120, squeeze=False)
    for k, name in enumerate(names):
        ax = axes[k // cols][k % cols]
        ax.plot(s, [float(r[name + "_longitudinal"]) for r in rows], "-", lw=1, label="longitudinal")
        ax.plot(s, [float(r[name + "_transverse"]) for r in rows], "--", lw=1, label="transverse")
        ax.set_title(name, fontsize=8)
        ax.tick_params(labelsize=6)
        ax.axhline(0, color="0.7", lw=0.5)
    for k in range(len(names), nrows * cols):
        axes[k // cols][k % cols].axis("off")
    axes[0][0].legend(fontsize=6)
    fig.tight_layout()
    out = os.path.join(os.path.dirname(path), "profiles.png")
    fig.savefig(out + ".tmp.png")
    os.replace(out + ".tmp.png", out)


if __name__ == "__main__":
    main(sys.argv[1])
