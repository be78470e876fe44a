#!/usr/bin/env python3
"""gfmd.load_path over a list of loads against one cold gfmd.solve per load: CG iterations,
friction steps and wall time, frictionless and sliding (mu_c = 0.5), in one process.

Rough self-affine surface (H = 0.8, lambda_long = L/2, lambda_short = 4 dx, rms gradient 0.1) on
a nu = 0.3 half-space, mean pressures 0.002 ... 0.02 E* (10 loads). Each side runs twice,
alternating; the faster of the two counts.

    /usr/bin/python3 scripts/bench_load_path.py --nx 512 [--build build] [--threads 2]
"""
import argparse
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nx", type=int, default=512)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--loads", type=int, default=10)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    a = ap.parse_args()
    sys.path.insert(0, os.path.join(a.build, "python"))
    import gfmd

    top = gfmd.Topography.self_affine(a.nx, 1.0, hurst=0.8, lambda_short=4.0 / a.nx, rms_gradient=0.1, seed=0)
    body = gfmd.ElasticBody(poisson=0.3)
    loads = [0.02 * (k + 1) / a.loads for k in range(a.loads)]
    print(f"nx = {a.nx}, threads = {a.threads}, {a.loads} mean pressures {loads[0]:.3g} ... {loads[-1]:.3g} E*")
    print("| friction | side | CG iterations | outer (friction) steps | wall s | max rel. diff. of mu or area |")
    print("|---|---|---|---|---|---|")
    for mu in (0.0, 0.5):
        opts = dict(friction=mu, threads=a.threads, tolerance=1e-8)
        best = {}
        for _ in range(2):
            for side in ("cold", "load_path"):
                t0 = time.perf_counter()
                if side == "cold":
                    res = [gfmd.solve(top, body, pressure=p, **opts) for p in loads]
                else:
                    res = list(gfmd.load_path(gfmd.ContactSolver(top, body, **opts), pressures=loads))
                t = time.perf_counter() - t0
                if side not in best or t < best[side][0]:
                    best[side] = (t, res)
        key = "friction_coefficient" if mu > 0 else "relative_contact_area"
        diff = max(abs(w.summary[key] - c.summary[key]) / abs(c.summary[key])
                   for w, c in zip(best["load_path"][1], best["cold"][1]))
        for side in ("cold", "load_path"):
            t, res = best[side]
            its = sum(r.summary["iterations"] for r in res)
            steps = sum(r.summary.get("outer_iterations", 0) for r in res)
            print(f"| {mu} | {side} | {its} | {steps} | {t:.2f} | {diff:.1e} |")
        tc, tw = best["cold"][0], best["load_path"][0]
        print(f"| {mu} | load_path / cold | | | {tw / tc:.3f} | |")


if __name__ == "__main__":
    main()
