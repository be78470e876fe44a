#!/usr/bin/python3
"""Hunter's problem solved in real space: a rigid parabolic cylinder (radius R, force F per
length) rolling or sliding frictionless at speed V over a standard-linear-solid half-space in
plane strain (E*(omega) = E0 + (E_inf - E0) i omega tau / (1 + i omega tau), gfmd's
elastic.viscoelastic = "sls"), in steady state. An independent check of gfmd's spectral,
periodic viscoelastic solve (docs/solver.md, "Hunter's cylinder").

Method (no FFT, no periodic cell): the creep compliance of the solid is
J(t) = 1/E_inf + (1/E0 - 1/E_inf)(1 - exp(-t/tau_c)), tau_c = tau E_inf/E0. A material point
of the half-space moves at -V under the indenter (which slides towards +x), so Boltzmann's
superposition of the line-load displacement -(2/pi) ln|x - s| over the point's past gives the
steady kernel

    u(x) = -(2/pi) int p(s) [ ln|x - s| / E_inf
                              + (1/E0 - 1/E_inf) int_0^inf exp(-eta/lambda)/lambda ln|x - s + eta| d eta ] ds

with lambda = V tau_c; the inner integral is ln|a| + exp(a) E1(a) (a = (x - s)/lambda > 0) or
ln|a| - exp(a) Ei(-a) (a < 0), plus ln(lambda). The pressure is piecewise constant on cells of
width h (the logarithm integrated exactly over each cell, the memory term by 8-point
Gauss-Legendre), the contact found by an active set: the gap x^2/(2R) - delta + u vanishes where
p > 0 and is open elsewhere, with int p = F. The rolling-resistance (hysteresis friction)
coefficient is the horizontal force on the indenter over F, int p x dx / (F R): the pressure's
centroid over R. Its limits are Hertz's line contact, half-width sqrt(4 F R/(pi E)) with E = E0
(slow) and E_inf (fast), and mu = 0 at both.

    /usr/bin/python3 scripts/hunter_reference.py                  # the reference over speeds
    /usr/bin/python3 scripts/hunter_reference.py --gfmd --nx 8192,16384,32768 --cell 8
    /usr/bin/python3 scripts/hunter_reference.py --gfmd --nx 32768 --plot docs/figures/hunter_cylinder.png
"""
import argparse
import math
import os
import sys

import numpy as np
from scipy.special import exp1, expi


def memory_kernel(xi, lam):
    """int_0^inf exp(-eta/lam)/lam ln|xi + eta| d eta, elementwise."""
    a = np.asarray(xi, dtype=float) / lam
    out = np.full(a.shape, -np.euler_gamma)
    big = np.abs(a) > 40  # exp(a) E1(a) and exp(a) Ei(-a) by their asymptotic series (1e-9)
    pos, neg = (a > 0) & ~big, (a < 0) & ~big
    out[pos] = np.log(a[pos]) + np.exp(a[pos]) * exp1(a[pos])
    out[neg] = np.log(-a[neg]) - np.exp(a[neg]) * expi(-a[neg])
    ab = a[big]
    series = sum(math.factorial(k) * (-1.0 / ab) ** k for k in range(8)) / ab  # both signs
    out[big] = np.log(np.abs(ab)) + series
    return out + math.log(lam)


def hunter_reference(force, radius, e0, e_inf, tau, velocity, cell, window=None):
    """The steady contact: {'mu', 'trailing', 'leading' (contact edges, x towards the motion),
    'delta', 'x', 'p'}. cell: the collocation width h; window: the half-width of the solved
    interval (default 2.5 relaxed half-widths)."""
    j_inf, j0 = 1.0 / e_inf, 1.0 / e0
    lam = velocity * tau * e_inf / e0
    a0 = math.sqrt(4 * force * radius / (math.pi * e0))
    half = window if window is not None else 2.5 * a0
    x = np.arange(-half, half + 0.5 * cell, cell)
    n = len(x)
    d = x[:, None] - x[None, :]

    def log_antiderivative(t):
        safe = np.where(t == 0, 1.0, np.abs(t))
        return np.where(t == 0, 0.0, t * np.log(safe) - t)

    elastic = log_antiderivative(d + cell / 2) - log_antiderivative(d - cell / 2)
    if lam > 0:
        memory = np.zeros((n, n))
        nodes, weights = np.polynomial.legendre.leggauss(8)
        for g, w in zip(nodes, weights):
            memory += w * cell / 2 * memory_kernel(d - g * cell / 2, lam)
    else:
        memory = elastic  # at rest every material point has relaxed: J0
    kernel = -(2 / math.pi) * (j_inf * elastic + (j0 - j_inf) * memory)
    height = x ** 2 / (2 * radius)
    active = np.abs(x) < 0.5 * a0
    for _ in range(500):
        idx = np.flatnonzero(active)
        m = len(idx)
        system = np.zeros((m + 1, m + 1))
        system[:m, :m] = kernel[np.ix_(idx, idx)]
        system[:m, m] = -1.0
        system[m, :m] = cell
        sol = np.linalg.solve(system, np.concatenate([-height[idx], [force]]))
        p = np.zeros(n)
        p[idx] = sol[:m]
        delta = sol[m]
        gap = height - delta + kernel @ p
        negative = active & (p < 0)
        penetrating = ~active & (gap < -1e-13 * abs(delta))
        if not negative.any() and not penetrating.any():
            break
        active = (active & ~negative) | penetrating
    else:
        raise RuntimeError("hunter_reference: the active set did not settle")
    inside = np.flatnonzero(p > 0)
    if inside[0] == 0 or inside[-1] == n - 1:
        raise RuntimeError("hunter_reference: the contact reaches the window's edge; widen it")
    return {"mu": float(np.sum(p * x) * cell / (force * radius)), "trailing": x[inside[0]] - cell / 2,
            "leading": x[inside[-1]] + cell / 2, "delta": float(delta), "x": x, "p": p}


def gfmd_cylinder(force, radius, e0, e_inf, tau, velocity, nx, cell_length, ny=4):
    """The same contact through gfmd: a cylinder along y on a periodic cell cell_length wide, nx
    points along x (ny along the cylinder, square cells), the SLS half-space, force control."""
    import gfmd

    ly = cell_length * ny / nx
    top = gfmd.Topography.indenter("cylinder", nx, cell_length, ny=ny, ly=ly, radius=radius)
    body = gfmd.ViscoelasticBody(contact_modulus=e0, poisson=0.5, high_frequency_modulus=e_inf,
                                 relaxation_time=tau)
    r = gfmd.solve(top, body, force=force * ly, velocity=velocity, tolerance=1e-10)
    if not r.summary["converged"]:
        raise RuntimeError(r.summary["status"])
    p = np.asarray(r.fields["pressure"])[0]
    x = (np.arange(nx) - nx // 2) * cell_length / nx
    inside = np.flatnonzero(p > 1e-9 * p.max())
    return {"mu": r.summary["hysteresis_friction"], "trailing": x[inside[0]], "leading": x[inside[-1]]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--speeds", default="0.0005,0.002,0.005,0.01,0.02,0.05",
                    help="V in units of R/tau (comma-separated)")
    ap.add_argument("--gfmd", action="store_true", help="also solve each speed with gfmd")
    ap.add_argument("--nx", default="8192,16384", help="gfmd's points along x (comma-separated)")
    ap.add_argument("--cell", type=float, default=8.0, help="gfmd's periodic cell length (R)")
    ap.add_argument("--plot", metavar="PNG", help="draw the resistance and the contact edges against the speed "
                    "(the reference as lines, gfmd's finest --nx as points with --gfmd)")
    ap.add_argument("--build", default=os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                                    "build"))
    a = ap.parse_args()
    sys.path.insert(0, os.path.join(a.build, "python"))
    r_, e0, e_inf, tau, a0 = 1.0, 1.0, 10.0, 1.0, 0.05
    force = math.pi * a0 ** 2 * e0 / (4 * r_)
    tau_c = tau * e_inf / e0
    print(f"R = 1, E0 = 1, E_inf = 10, tau = 1 (tau_c = 10), F = {force:.6g} per length (relaxed half-width "
          f"a0 = {a0}); reference cell a0/100")
    head = "| V tau_c / a0 | reference mu | contact (reference) |"
    if a.gfmd:
        head += "".join(f" gfmd {n}: mu (error) |" for n in a.nx.split(","))
    print(head)
    print("|" + "---|" * (head.count("|") - 1))
    drawn = []  # (V tau_c / a0, reference, gfmd at the finest nx or None)
    for v in (float(s) for s in a.speeds.split(",")):
        ref = hunter_reference(force, r_, e0, e_inf, tau, v, a0 / 100, window=3 * a0)
        row = f"| {v * tau_c / a0:.4g} | {ref['mu']:.5f} | [{ref['trailing'] / a0:.3f}, {ref['leading'] / a0:.3f}] a0 |"
        g = None
        if a.gfmd:
            for n in (int(s) for s in a.nx.split(",")):
                g = gfmd_cylinder(force, r_, e0, e_inf, tau, v, n, a.cell)
                row += f" {g['mu']:.5f} ({g['mu'] / ref['mu'] - 1:+.2%}) |"
        drawn.append((v * tau_c / a0, ref, g))
        print(row, flush=True)
    if a.plot:
        plot(drawn, a0, a.plot, a.nx.split(",")[-1] if a.gfmd else None, a.cell)


def plot(drawn, a0, path, nx, cell):
    """Two panels against V tau_c / a0 on a log axis: the rolling resistance, and the contact's
    edges in units of a0 (the reference's lines, gfmd's points)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from figure_io import save_png

    x = [d[0] for d in drawn]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(5.5, 6.0), sharex=True)
    top.plot(x, [d[1]["mu"] for d in drawn], "-", color="k", label="real-space reference (cells a0/100)")
    bottom.plot(x, [d[1]["leading"] / a0 for d in drawn], "-", color="k", label="reference: leading edge")
    bottom.plot(x, [d[1]["trailing"] / a0 for d in drawn], "--", color="k", label="reference: trailing edge")
    if nx is not None:
        label = f"gfmd, {nx} points on a cell of {cell:g} R"
        top.plot(x, [d[2]["mu"] for d in drawn], "o", color="C0", label=label)
        bottom.plot(x, [d[2]["leading"] / a0 for d in drawn], "o", color="C0", label=label)
        bottom.plot(x, [d[2]["trailing"] / a0 for d in drawn], "o", color="C0", mfc="none")
    top.set_ylabel("rolling resistance F_x / F_z")
    top.set_title("Rigid cylinder on a standard linear solid (E_inf = 10 E0)")
    bottom.set_ylabel("contact edge x / a0 (x: direction of motion)")
    bottom.set_xlabel("V tau_c / a0 (tau_c = tau E_inf / E0; a0: relaxed half-width)")
    bottom.set_xscale("log")
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    save_png(fig, path, dpi=120)
    print(f"figure: {path}", file=sys.stderr)


if __name__ == "__main__":
    main()
