#!/usr/bin/python3
"""The paper's figures from Python: each study of studies/ (Fig. 2 a-e, Fig. 3 a-d, e-h, j-m,
supplement Figs. 1-2) run through gfmd.study, which reuses every finished result.

    /usr/bin/python3 examples/python/paper_figures.py                 # all, quick resolution
    /usr/bin/python3 examples/python/paper_figures.py fig2d fig3jm    # some
    /usr/bin/python3 examples/python/paper_figures.py fig2e --full    # the paper's resolution

Figures (PNG, PDF) and their data (CSV) land in out/studies/<name>/<quick|full>/.
"""
import argparse
import glob
import os
import sys

import gfmd

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STUDIES = sorted(os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(ROOT, "studies", "*.toml")))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("figures", nargs="*", choices=STUDIES + [[]], help="studies to run (default: all)")
    ap.add_argument("--full", action="store_true", help="the paper's resolution (hours for some figures)")
    ap.add_argument("-o", "--output", default=os.path.join("out", "studies"))
    args = ap.parse_args()
    failed = []
    for name in args.figures or STUDIES:
        try:
            rep = gfmd.study(os.path.join(ROOT, "studies", name + ".toml"), quick=not args.full, output=args.output)
            print(f"{name}: {rep['figure']}  ({rep['wall_time_s']:.0f} s)")
        except gfmd.SolveError as e:
            failed.append(name)
            print(f"{name}: {e}", file=sys.stderr)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
