#!/usr/bin/python3
"""Rough adhesive contact: the repulsive contact area against the load on a self-affine surface,
with and without adhesion, at adhesion strengths set by the stickiness parameter Q of Pastewka &
Robbins (PNAS 2014, Eq. 10, in the form ContactEngineering/Adhesion codes it: kappa_rep = 2,
d_rep = 4 h'/h''):

    Q = h' E* rho / (2 w) * (h'^2 / (h'' rho))^(2/3)     (sticky for Q < 1)

with h' the rms gradient, h'' the rms of half the Laplacian (both spectral), w the work of
adhesion and rho the range (Maugis-Dugdale: sigma0 = w / rho). Their DMT-regime theory reads
F / A_rep = (h' E* / kappa_rep) (1 - 1/Q) at small areas, so the area per load grows by Q/(Q-1)
over the repulsive one. Printed: per Q, the area at each mean pressure, the secant slope A/p, the
least-squares line A = s p + c, the slope's ratio to the repulsive one and Q/(Q-1), and a Maugis
parameter lambda = 2 sigma0 (R/(pi w K^2))^(1/3) for a summit of radius R = 1/h'' (K = 4E*/3).

    scripts/rough_adhesion.py [--nx 512] [--lambda-short 0.0625] [--range 1e-3] [--q inf,8,4,2] [--dmt]

--dmt prints instead the first-order (DMT) estimate from the non-adhesive solutions: the pull is
sigma0 times the area where the gap is below rho, so F/A_rep = sigma_rep (1 - c/Q) with
c = sigma0 Q kappa (A_{g<rho} / A_rep) / h' (kappa = A_rep h' E* / F measured).

Units: L = 1, E* = 1, incompressible half-space (no coupling), lambda_long = L/2, H = 0.8,
h' = 0.1, seed 1; loads solved under load control along the pressures, warm-started (the
ContactSolver of the Python package)."""
import argparse
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.environ.get("GFMD_PYTHON_DIR", os.path.join(HERE, "..", "build", "python")))
import gfmd  # noqa: E402


def work_of_adhesion(q, hp, hpp, rho):
    """The w that makes the stickiness parameter Q for rms gradient hp, curvature hpp, range rho."""
    return hp * rho / (2 * q) * (hp * hp / (hpp * rho)) ** (2 / 3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--nx", type=int, default=512)
    ap.add_argument("--lambda-short", type=float, default=0.0625)
    ap.add_argument("--range", type=float, default=1e-3)
    ap.add_argument("--q", default="inf,8,4,2")
    ap.add_argument("--pressures", default="0.0005,0.001,0.002,0.004")
    ap.add_argument("--dmt", action="store_true", help="the first-order estimate of c from the non-adhesive gaps")
    a = ap.parse_args()
    top = gfmd.Topography.self_affine(a.nx, 1.0, hurst=0.8, lambda_long=0.5, lambda_short=a.lambda_short,
                                      rms_gradient=0.1, seed=1)
    hp, hpp, rho = top.rms_gradient(), top.rms_curvature(), a.range
    ps = np.array([float(v) for v in a.pressures.split(",")])
    print(f"nx {a.nx}, lambda_s {a.lambda_short:g} L, h' {hp:.4g}, h'' {hpp:.4g}/L, d_rep {4 * hp / hpp:.4g} L, "
          f"range {rho:g} L, rho/g0 {rho / (16 / 3 * hp * hp / hpp):.3g}")
    if a.dmt:
        dmt(top, hp, hpp, ps)
        return
    print("| Q | w / (E* L) | lambda (summit) | A_rep at p = " + ", ".join(f"{p:g}" for p in ps)
          + " | A/p (secant) | line s, c | s / s_rep | Q/(Q-1) |")
    print("|---" * 8 + "|")
    s_rep = None
    for q in (float(v) for v in a.q.split(",")):
        w = 0.0 if math.isinf(q) else work_of_adhesion(q, hp, hpp, rho)
        solver = gfmd.ContactSolver(top, interaction="hardwall" if w == 0 else gfmd.Adhesive(w, rho))
        area = np.array([r.summary["relative_contact_area"] for r in gfmd.load_path(solver, pressures=ps)])
        secant = float(area @ ps / (ps @ ps))
        s, c = np.polyfit(ps, area, 1)
        if s_rep is None:
            s_rep = secant
        lam = "-" if w == 0 else f"{2 * (w / rho) * ((1 / hpp) / (math.pi * w * (4 / 3) ** 2)) ** (1 / 3):.2f}"
        pred = "1" if math.isinf(q) else f"{q / (q - 1):.3g}"
        print(f"| {q:g} | {w:.3g} | {lam} | " + ", ".join(f"{v:.4f}" for v in area)
              + f" | {secant:.1f} | {s:.1f}, {c:.3f} | {secant / s_rep:.2f} | {pred} |")


def dmt(top, hp, hpp, ps):
    ranges = (5e-4, 1e-3, 2e-3, 4e-3)
    print("| p / E* | A_rep | " + " | ".join(f"A_g<rho / A_rep, c (rho = {r:g})" for r in ranges) + " |")
    print("|---" * (2 + len(ranges)) + "|")
    solver = gfmd.ContactSolver(top, interaction="hardwall")
    for r in gfmd.load_path(solver, pressures=ps):
        p, area, gap = r.summary["mean_pressure"], r.summary["relative_contact_area"], np.asarray(r["gap"])
        kappa = area * hp / p
        cells = []
        for rho in ranges:
            ratio = float(np.mean(gap < rho)) / area
            sigma0_q = work_of_adhesion(1.0, hp, hpp, rho) / rho  # sigma0 Q (sigma0 = w / rho)
            cells.append(f"{ratio:.2f}, {sigma0_q * ratio * kappa / hp:.1f}")
        print(f"| {p:g} | {area:.4f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
