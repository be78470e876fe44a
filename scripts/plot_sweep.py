#!/usr/bin/python3
"""Draws one column of a gfmd sweep table against the swept parameter (PNG). The axes are
named as in the README with their units ("mean pressure p̄ (E*)", lengths in the case's
grid.unit from sweep.json beside the table, else L); a swept parameter whose values are
log-spaced gets a log axis. Exit status 4 when interrupted (nothing written)."""
import argparse
import csv
import math
import os
import sys

import figure_io  # noqa: E402 (beside this script)

if __name__ == "__main__":
    figure_io.exit_on_interrupt_while_starting()

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def figure(table, column):
    """The figure of one column of sweep.csv against the swept parameter (not saved); raises
    ValueError naming the table when there is nothing to draw."""
    with open(table, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        raise ValueError(f"{table}: no finished points to draw")
    head, data = rows[0], rows[1:]
    if column not in head:
        raise ValueError(f"{table}: no column '{column}'; columns: {', '.join(head)}")
    xi, yi = 0, head.index(column)
    x = [float(r[xi]) for r in data if r[yi] not in ("", "null")]
    y = [float(r[yi]) for r in data if r[yi] not in ("", "null")]
    unit = figure_io.grid_unit_beside(table, "sweep.json")
    fig, ax = plt.subplots(figsize=(5, 3.6), dpi=150)
    ax.plot(x, y, "o-", color="C0")
    if figure_io.log_spaced(x):
        ax.set_xscale("log")
        if len(set(x)) <= 8 and max(x) / min(x) < 100:  # within two decades: ticks at the swept values
            ax.set_xticks(sorted(set(x)), [f"{v:g}" for v in sorted(set(x))])
            ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    if len(y) > 1 and min(y) > 0 and max(y) / min(y) > 50 and all(math.isfinite(v) for v in y):
        ax.set_yscale("log")
    ax.set_xlabel(figure_io.quantity_label(head[xi], unit))
    ax.set_ylabel(figure_io.quantity_label(column, unit))
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("table", help="sweep.csv written by gfmd sweep")
    ap.add_argument("--y", default="friction_coefficient", help="column to draw")
    ap.add_argument("-o", "--output", help="PNG path (default: next to the table)")
    args = ap.parse_args()
    try:
        fig = figure(args.table, args.y)
    except ValueError as e:
        sys.exit(str(e))
    out = args.output or os.path.join(os.path.dirname(args.table) or ".", f"sweep_{args.y}.png")
    figure_io.save_png(fig, out)
    print(out)


if __name__ == "__main__":
    figure_io.run_main(main, "plot_sweep.py")
