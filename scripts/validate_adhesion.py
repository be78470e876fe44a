#!/usr/bin/python3
"""The adhesive sphere against Maugis's theory: the pull-off force (the most tensile force on an
approach-controlled unloading path) and the contact radius at that force, for Maugis parameters
from the DMT to the JKR end and grids of growing resolution. Runs `gfmd curve --approaches`
(argument vectors, no shell) and prints a markdown table; --json writes the rows.

    scripts/validate_adhesion.py [--gfmd build/gfmd] [--quick] [--json out.json] [--work DIR]

Units: sphere radius R = 1, E* = 1, work of adhesion w = 1e-3, incompressible half-space, hard
wall; lambda = 2 sigma0 (R/(pi w K^2))^(1/3), K = 4E*/3, sigma0 = w/range (Johnson & Greenwood
1997). Maugis's curve is evaluated here from the same equations the C++ test uses."""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

W = 1e-3
K = 4.0 / 3.0


def maugis_curve(lam, n=200000):
    """(m, A, P) along Maugis's curve for the parameter lam, m = c/a from 1+ to 1e3."""
    m = 1 + np.logspace(-8, 3, n)
    s = np.sqrt(m * m - 1)
    at = np.arctan(s)
    al = lam / 2 * (s + (m * m - 2) * at)
    be = 4 * lam ** 2 / 3 * (s * at - m + 1)
    A = (-be + np.sqrt(be * be + 4 * al)) / (2 * al)
    return m, A, A ** 3 - lam * A * A * (s + m * m * at)


def maugis_pull_off(lam):
    m, A, P = maugis_curve(lam)
    k = int(np.argmin(P))
    return float(P[k]), float(A[k]), float(m[k])


def case_text(nx, lx, lam):
    sigma0 = lam / 2 * (math.pi * W * K * K) ** (1 / 3)
    return (f"[grid]\nnx = {nx}\nlx = {lx}\n[elastic]\npoisson = 0.5\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n"
            f"[load]\napproach = 0.0\n[interaction]\nmodel = \"adhesive\"\nwork_of_adhesion = {W}\n"
            f"range = {W / sigma0:.17g}\n[output]\nfields = false\npng = false\nanalysis = false\n")


def run(gfmd, work, nx, lx, lam, approaches):
    name = f"lam{lam:g}_n{nx}_l{lx:g}"
    case = os.path.join(work, name + ".toml")
    with open(case, "w") as f:
        f.write(case_text(nx, lx, lam))
    out = os.path.join(work, name)
    subprocess.run([gfmd, "curve", case, "--approaches", approaches, "-o", out, "--force", "-q", "--no-png"],
                   check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "curve.json")) as f:
        j = json.load(f)
    pts = j["points"]
    k = min(range(len(pts)), key=lambda i: pts[i]["normal_force"])
    unit = (math.pi * W / K) ** (1 / 3)  # Maugis's radius unit (pi w R^2/K)^(1/3)
    a = math.sqrt(pts[k]["relative_contact_area"] * lx * lx / math.pi)
    return {"lambda": lam, "nx": nx, "lx": lx, "pull_off": j["pull_off_force"] / (math.pi * W),
            "radius_cells": a / (lx / nx), "radius": a / unit,
            "iterations": sum(p["iterations"] for p in pts), "points": len(pts)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--gfmd", default=os.path.join(here, "..", "build", "gfmd"))
    ap.add_argument("--quick", action="store_true", help="the coarse grids only")
    ap.add_argument("--json", help="write the rows here")
    ap.add_argument("--work", help="keep the runs here (default: a temporary directory)")
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="gfmd_adhesion_")
    os.makedirs(work, exist_ok=True)
    cases = [(0.1, 4.0, [128, 256]), (1.0, 1.5, [128, 256, 512]), (2.5, 1.5, [256, 512])]
    if args.quick:
        cases = [(lam, lx, grids[:1]) for lam, lx, grids in cases]
    rows = []
    print("| lambda | cell | grid | radius at pull-off (cells) | pull-off / (pi w R) | Maugis | error | CG iterations |")
    print("|---|---|---|---|---|---|---|---|")
    for lam, lx, grids in cases:
        ref, a_ref, _ = maugis_pull_off(lam)
        # Unloading from contact through the force minimum (DMT: a longer, coarser path).
        path = "0.01,0:-0.04:21" if lam < 0.5 else "0.01,0,-0.002:-0.008:13"
        for nx in grids:
            r = run(args.gfmd, work, nx, lx, lam, path)
            r.update({"maugis": ref, "error": r["pull_off"] / ref - 1})
            rows.append(r)
            print(f"| {lam:g} | {lx:g} R | {nx}^2 | {r['radius_cells']:.1f} | {r['pull_off']:.4f} | {ref:.4f} | "
                  f"{100 * r['error']:+.2f} % | {r['iterations']} |", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
