#!/usr/bin/python3
"""Draws profiles.csv of a gfmd run (line profiles through the pressure maximum along and
across the sliding direction) as profiles.png next to it: one panel per quantity, each with
its axes labelled "quantity (unit)" (lengths in the case's grid.unit from summary.json beside
the table, else L; pressures and stresses in E*). Exit status 4 when interrupted (nothing
written)."""
import csv
import os
import sys

import figure_io  # noqa: E402 (beside this script)

if __name__ == "__main__":
    figure_io.exit_on_interrupt_while_starting()

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Column (without _longitudinal/_transverse) -> (panel title, axis symbol, units).
QUANTITIES = {
    "uz": ("normal surface displacement", "$u_z$", "length"),
    "pressure": ("contact pressure", "$p$", "E*"),
    "dissipation": ("dissipated power density / v₀", r"$\dot w/v_0$", "E*"),
    "slip_longitudinal": ("longitudinal slip excess", r"$v_\ell^\mathrm{rel}/v_0 - 1$", "1"),
    "slip_transverse": ("transverse slip", r"$v_\perp/v_0$", "1"),
    "sigma_xx": ("surface stress xx", r"$\sigma_{xx}$", "E*"),
    "sigma_yy": ("surface stress yy", r"$\sigma_{yy}$", "E*"),
    "sigma_zz": ("surface stress zz (= −p)", r"$\sigma_{zz}$", "E*"),
    "sigma_xy": ("surface stress xy", r"$\sigma_{xy}$", "E*"),
    "sigma_xz": ("surface stress xz", r"$\sigma_{xz}$", "E*"),
    "sigma_yz": ("surface stress yz", r"$\sigma_{yz}$", "E*"),
    "sigma_1": ("max. principal stress", r"$\sigma_\mathrm{I}$", "E*"),
    "von_mises": ("von Mises stress", r"$\sigma_\mathrm{vM}$", "E*"),
    "e1_x": ("direction of σ_I, x", r"$e_{\mathrm{I},x}$", "1"),
    "e1_y": ("direction of σ_I, y", r"$e_{\mathrm{I},y}$", "1"),
    "e1_z": ("direction of σ_I, z", r"$e_{\mathrm{I},z}$", "1"),
    "ux": ("surface displacement x", "$u_x$", "length"),
    "uy": ("surface displacement y", "$u_y$", "length"),
}
SKIPPED = ("ux", "uy", "e1_y", "sigma_yz", "sigma_xy")


def figure(path):
    """The figure of profiles.csv at path (not saved)."""
    with open(path, newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    if not rows:
        raise ValueError(f"{path}: no rows")
    unit = figure_io.grid_unit_beside(path, "summary.json")
    s = [float(r["s"]) for r in rows]
    names = [k[: -len("_longitudinal")] for k in rows[0] if k.endswith("_longitudinal")]
    names = [n for n in names if n not in SKIPPED]
    cols = 3
    nrows = (len(names) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(3.4 * cols, 2.3 * nrows + 0.5), dpi=120, squeeze=False)
    for k, name in enumerate(names):
        ax = axes[k // cols][k % cols]
        title, symbol, units = QUANTITIES.get(name, (name.replace("_", " "), name, None))
        ax.plot(s, [float(r[name + "_longitudinal"]) for r in rows], "-", lw=1, color="C0",
                label="longitudinal (along the sliding direction)")
        ax.plot(s, [float(r[name + "_transverse"]) for r in rows], "--", lw=1, color="C1",
                label="transverse (across it)")
        ax.set_title(title, fontsize=8)
        ax.set_xlabel(figure_io.label("distance s", unit), fontsize=7)
        ax.set_ylabel(figure_io.label(symbol, units) if units is not None else name, fontsize=7)
        ax.tick_params(labelsize=6)
        ax.axhline(0, color="0.7", lw=0.5)
    for k in range(len(names), nrows * cols):
        axes[k // cols][k % cols].axis("off")
    handles, labels = axes[0][0].get_legend_handles_labels()
    h = fig.get_size_inches()[1]
    fig.suptitle("profiles through the pressure maximum", fontsize=9, y=1 - 0.08 / h, va="top")
    if len(names) < nrows * cols:  # the key in the first empty slot, clear of every panel's data
        spare = axes[len(names) // cols][len(names) % cols]
        fig.tight_layout(rect=(0, 0, 1, 1 - 0.22 / h))
        spare.legend(handles, labels, loc="center", fontsize=7, frameon=False, title="line through the maximum",
                     title_fontsize=7)
    else:  # under the title, above the panels
        fig.tight_layout(rect=(0, 0, 1, 1 - 0.5 / h))
        fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 1 - 0.28 / h), ncol=2, fontsize=7,
                   frameon=False)
    return fig


def main(path, batch=None):
    """Draws profiles.png beside path; into batch (a figure_io.Batch, published by the caller)
    or, without one, written at once. Returns the PNG's path."""
    return figure_io.save_png_or_stage(figure(path), os.path.join(os.path.dirname(path) or ".", "profiles.png"),
                                       batch)


def _script():
    print(main(sys.argv[1]))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    figure_io.run_main(_script, "plot_profiles.py")
