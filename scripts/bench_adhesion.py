#!/usr/bin/env python3
"""A rough adhesive contact against the same contact with the hard wall alone: one cold solve
and one warm (the next load from that solution), CG iterations, adhesive steps and wall time,
in one process (BENCHMARKS.md, "Adhesion").

examples/adhesive_rough.toml's surface and law at any size: self-affine H = 0.8, lambda_long =
L/2, rms gradient 0.1, seed 1, an incompressible half-space, Maugis-Dugdale work 2e-5 E* L and
range 1e-3 L; mean pressure 0.002 E*, then 0.0022 E* warm.

    /usr/bin/python3 scripts/bench_adhesion.py --nx 2048 [--lambda-short 0.015625] [--threads 2]
"""
import argparse
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nx", type=int, default=512)
    ap.add_argument("--lambda-short", type=float, default=1 / 64, help="the short cut-off (L; 1/64 = 32 cells at 2048²)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    a = ap.parse_args()
    sys.path.insert(0, os.path.join(a.build, "python"))
    import gfmd

    top = gfmd.Topography.self_affine(a.nx, 1.0, hurst=0.8, lambda_long=0.5, lambda_short=a.lambda_short,
                                      rms_gradient=0.1, seed=1)
    body = gfmd.ElasticBody(poisson=0.5)
    print("| interaction | cold: CG iterations, adhesive steps, s | warm: CG iterations, adhesive steps, s | "
          "contact area (warm) |")
    print("|---|---|---|---|")
    for name, inter in (("hard wall", "hardwall"), ("adhesive", gfmd.Adhesive(2e-5, 1e-3))):
        solver = gfmd.ContactSolver(top, body, interaction=inter, threads=a.threads)
        row = []
        for p in (0.002, 0.0022):
            t = time.perf_counter()
            s = solver.solve(pressure=p).summary
            dt = time.perf_counter() - t
            if not s["converged"]:
                sys.exit(f"{name} at p = {p}: {s['status']}")
            row.append(f"{s['iterations']}, {s.get('adhesion_steps') or '-'}, {dt:.2f}")
        print(f"| {name} | {row[0]} | {row[1]} | {s['relative_contact_area']:.4f} |")


if __name__ == "__main__":
    main()
