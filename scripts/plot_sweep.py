#!/usr/bin/python3
"""Draws one column of a gfmd sweep table against the swept parameter (PNG)."""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("table", help="sweep.csv written by gfmd sweep")
    ap.add_argument("--y", default="friction_coefficient", help="column to draw")
    ap.add_argument("-o", "--output", help="PNG path (default: next to the table)")
    args = ap.parse_args()
    with open(args.table, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        sys.exit(f"{args.table}: no finished points to draw")
    head, data = rows[0], rows[1:]
    if args.y not in head:
        sys.exit(f"{args.table}: no column '{args.y}'; columns: {', '.join(head)}")
    xi, yi = 0, head.index(args.y)
    x = [float(r[xi]) for r in data if r[yi] not in ("", "null")]
    y = [float(r[yi]) for r in data if r[yi] not in ("", "null")]
    fig, ax = plt.subplots(figsize=(5, 3.6), dpi=150)
    ax.plot(x, y, "o-", color="C0")
    if len(x) > 1 and min(x) > 0 and max(x) / min(x) > 20:
        ax.set_xscale("log")
    if len(y) > 1 and min(y) > 0 and max(y) / min(y) > 50 and all(math.isfinite(v) for v in y):
        ax.set_yscale("log")
    ax.set_xlabel(head[xi])
    ax.set_ylabel(args.y)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    out = args.output or os.path.join(os.path.dirname(args.table) or ".", f"sweep_{args.y}.png")
    tmp = out + ".tmp.png"
    fig.savefig(tmp)
    os.replace(tmp, out)
    print(out)


if __name__ == "__main__":
    main()
