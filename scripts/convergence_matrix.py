#!/usr/bin/python3
"""The stick-slip convergence matrix of the steady sliding solver (issue: stick-slip).

Self-affine indenter (examples/fig2e_rough_layer_sweep.toml) at a reduced resolution, over
bodies (nu = 0.25 half-space, nu = 0.49 layers of h = 0.05 and 0.1 lambda_l), friction
coefficients, loads p = 0.001 ... 1 E* (a warm-started sweep per body and mu_c), coupled and
uncoupled. Prints a Markdown table (converged points, CG iterations, friction steps,
splitting steps, largest stick fraction, time) and writes every point's row to DIR/matrix.csv.

    /usr/bin/python3 scripts/convergence_matrix.py -o out/matrix [--nx 256] [--mu 0.3 1 2]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GFMD = os.environ.get("GFMD", os.path.join(ROOT, "build", "gfmd"))
CASE = os.path.join(ROOT, "examples", "fig2e_rough_layer_sweep.toml")
BODIES = [("nu=0.25, h=inf", ["elastic.poisson=0.25", "elastic.thickness=inf"]),
          ("nu=0.49, h=0.05", ["elastic.poisson=0.49", "elastic.thickness=0.05"]),
          ("nu=0.49, h=0.1", ["elastic.poisson=0.49", "elastic.thickness=0.1"])]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--output", default=os.path.join("out", "matrix"))
    ap.add_argument("--nx", type=int, default=256)
    ap.add_argument("--mu", type=float, nargs="+", default=[0.3, 1.0, 2.0])
    ap.add_argument("--points", type=int, default=7)
    args = ap.parse_args()
    ls = 1.0 / (args.nx / 16)  # lambda_s = lambda_l/(nx/16): 8 grid points per lambda_s on L = 2 lambda_l
    rows = []
    table = []
    for coupling in (True, False):
        for body, bsets in BODIES:
            for mu in args.mu:
                d = os.path.join(args.output, f"{'coupled' if coupling else 'uncoupled'}_{body}_{mu:g}"
                                 .replace(" ", "").replace(",", "_").replace("=", ""))
                sets = bsets + [f"grid.nx={args.nx}", f"indenter.lambda_short={ls!r}", f"friction.coefficient={mu!r}",
                                f"elastic.coupling={'true' if coupling else 'false'}", "sweep.from=0.001",
                                "sweep.to=1.0", f"sweep.points={args.points}", "output.png=false",
                                "output.fields=false", "stress.profiles=false"]
                cmd = [GFMD, "sweep", CASE, "-o", d, "-q", "--plot", "stick_fraction"]
                for s in sets:
                    cmd += ["--set", s]
                t0 = time.time()
                p = subprocess.run(cmd, capture_output=True, text=True)
                wall = time.time() - t0
                done = []
                sj = os.path.join(d, "sweep.json")
                if os.path.exists(sj):
                    with open(sj) as f:
                        done = json.load(f)["points"]
                for pt in done:
                    rows.append({"coupling": coupling, "body": body, "mu_c": mu, "pressure": pt["load.pressure"],
                                 "converged": pt.get("converged"), "iterations": pt.get("iterations"),
                                 "outer_iterations": pt.get("outer_iterations"),
                                 "tangential_iterations": pt.get("tangential_iterations"),
                                 "stick_fraction": pt.get("stick_fraction"),
                                 "delta_mu_over_mu_c": pt.get("delta_mu_over_mu_c"), "wall_time_s": pt.get("wall_time_s")})
                failed = "" if p.returncode == 0 else p.stderr.strip().splitlines()[-1][:160]
                table.append([("coupled" if coupling else "uncoupled"), body, f"{mu:g}",
                              f"{len(done)}/{args.points}",
                              str(max((pt.get("iterations") or 0) for pt in done) if done else "-"),
                              str(max((pt.get("outer_iterations") or 0) for pt in done) if done else "-"),
                              str(max((pt.get("tangential_iterations") or 0) for pt in done) if done else "-"),
                              f"{max((pt.get('stick_fraction') or 0) for pt in done):.4f}" if done else "-",
                              f"{wall:.0f} s", failed])
                print(" | ".join(table[-1]), flush=True)
    os.makedirs(args.output, exist_ok=True)
    with open(os.path.join(args.output, "matrix.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["coupling"])
        w.writeheader()
        w.writerows(rows)
    print("\n| body | coupling | μ_c | converged | max CG iterations | max friction steps | max splitting steps "
          "| max stick fraction | wall | failure |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in table:
        print(f"| {r[1]} | {r[0]} | {r[2]} | {r[3]} | {r[4]} | {r[5]} | {r[6]} | {r[7]} | {r[8]} | {r[9]} |")
    return 0 if all(r[3].split("/")[0] == r[3].split("/")[1] for r in table) else 1


if __name__ == "__main__":
    sys.exit(main())
