#!/usr/bin/python3
"""A rigid sphere pressed without friction on a coating bonded to an elastic half-space: the
exact axisymmetric solution, by a method independent of gfmd's (a reference for its tests).

    scripts/coated_hertz_reference.py --ratio 0.1 --nu 0.3 0.3 --a 0.3 1 3

Units: coating thickness t = 1, the coating's E1* = E1/(1 - nu1^2) = 1, sphere radius R (it
scales out). Printed per contact radius a/t: the approach delta R/a^2, the load P R/(E1* a^3) and
the central pressure p0 R/(E1* a) (a homogeneous body: 1, 4/3 and 2/pi, Hertz).

Method (the formulation of Perriot & Barthel, J. Mater. Res. 19 (2004) 600, for a coating):
the surface displacement of a pressure p is, in Hankel space, u(k) = 2 C(k t) p(k) / (E1* k),
where C(x) = (1 + 4 b x e^-2x - a b e^-4x) / (1 - (a + b + 4 b x^2) e^-2x + a b e^-4x) with
g = G1/G2, k_i = 3 - 4 nu_i, a = (g k2 - k1)/(1 + g k2), b = (g - 1)/(g + k1) (the bonded layer).
Writing the pressure through Sneddon's function g(s), p(r) = -int_r^a g'(s)/sqrt(s^2 - r^2) ds,
the contact condition becomes the Fredholm equation of the second kind
    g(s) + int_0^a [F(s - u) + F(s + u)] g(u) du = (delta - s^2/R) / pi,
    F(y) = (1/pi) int_0^inf (C(k) - 1) cos(k y) dk,
with g(a) = 0 (no edge singularity) fixing delta, P = 2 pi int_0^a g and p0 = -int_0^a g'(s)/s ds.
It is solved by Gauss-Legendre quadrature (Nystrom); F by Gauss-Legendre panels over k in [0, 40]
(C - 1 falls like k^2 e^-2k). For C = 1 it is Hertz's solution exactly.
"""
import argparse

import numpy as np


def bonded_layer_factor(x, ratio, nu1, nu2):
    """C(x), x = k t, for a substrate of E2*/E1* = ratio (the compliance over the coating's)."""
    g1 = (1 - nu1) / 2.0  # shear moduli in units of E1* (G = E* (1 - nu)/2)
    g2 = ratio * (1 - nu2) / 2.0
    g = g1 / g2
    k1, k2 = 3 - 4 * nu1, 3 - 4 * nu2
    a = (g * k2 - k1) / (1 + g * k2)
    b = (g - 1) / (g + k1)
    e2 = np.exp(-2 * x)
    e4 = e2 * e2
    return (1 + 4 * b * x * e2 - a * b * e4) / (1 - (a + b + 4 * b * x * x) * e2 + a * b * e4)


def _k_nodes(kmax=40.0, panel=0.125, order=16):
    x, w = np.polynomial.legendre.leggauss(order)
    starts = np.arange(0.0, kmax, panel)
    k = (starts[:, None] + 0.5 * panel * (x[None, :] + 1)).ravel()
    wk = np.tile(0.5 * panel * w, len(starts))
    return k, wk


def sphere_on_coating(a, ratio, nu1, nu2, n=48):
    """(delta R/a^2, P R/(E1* a^3), p0 R/(E1* a)) at contact radius a (units of the thickness)."""
    k, wk = _k_nodes()
    c1 = (bonded_layer_factor(k, ratio, nu1, nu2) - 1.0) * wk / np.pi

    def F(y):  # (1/pi) int (C - 1) cos(k y) dk, any shape of y
        y = np.asarray(y, dtype=float)
        flat = y.ravel()
        out = np.empty_like(flat)
        for i in range(0, flat.size, 512):
            out[i:i + 512] = np.cos(np.outer(flat[i:i + 512], k)) @ c1
        return out.reshape(y.shape)

    def dF(y):  # F'(y)
        y = np.asarray(y, dtype=float)
        flat = y.ravel()
        out = np.empty_like(flat)
        for i in range(0, flat.size, 512):
            out[i:i + 512] = -np.sin(np.outer(flat[i:i + 512], k)) @ (c1 * k)
        return out.reshape(y.shape)

    x, w = np.polynomial.legendre.leggauss(n)
    s = 0.5 * a * (x + 1)
    w = 0.5 * a * w
    S, U = np.meshgrid(s, s, indexing="ij")
    A = np.eye(n) + (F(S - U) + F(S + U)) * w[None, :]
    g1 = np.linalg.solve(A, np.ones(n) / np.pi)  # the approach's part (delta = 1)
    g2 = np.linalg.solve(A, s ** 2 / np.pi)  # the sphere's part (R = 1)
    # g(a) = 0: the equation at s = a by Nystrom interpolation.
    Ka = F(a - s) + F(a + s)
    g1a = 1 / np.pi - np.sum(w * Ka * g1)
    g2a = a * a / np.pi - np.sum(w * Ka * g2)
    delta = g2a / g1a
    g = delta * g1 - g2
    load = 2 * np.pi * np.sum(w * g)
    dK = dF(S - U) + dF(S + U)  # d/ds of F(s - u) + F(s + u)
    gp = -2 * s / np.pi - (dK * w[None, :]) @ g
    p0 = -np.sum(w * gp / s)
    return delta / a ** 2, load / a ** 3, p0 / a


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ratio", type=float, required=True, help="substrate E2* / coating E1*")
    ap.add_argument("--nu", type=float, nargs=2, default=(0.3, 0.3), metavar=("NU1", "NU2"))
    ap.add_argument("--a", type=float, nargs="+", default=[0.1, 0.3, 1.0, 3.0, 10.0], help="contact radii a/t")
    args = ap.parse_args()
    print(f"# E2*/E1* = {args.ratio}, nu1 = {args.nu[0]}, nu2 = {args.nu[1]}")
    print("#    a/t   delta R/a^2   P R/(E1* a^3)   p0 R/(E1* a)")
    for a in args.a:
        d, p, p0 = sphere_on_coating(a, args.ratio, *args.nu)
        print(f"{a:8.4g}  {d:12.6f}  {p:14.6f}  {p0:13.6f}")


if __name__ == "__main__":
    main()
