#!/usr/bin/python3
"""Persson's theory of hysteretic rubber friction (J. Chem. Phys. 115, 3840 (2001): the paper's
ref [2]) for a gfmd case, on the case's own surface spectrum and modulus, beside gfmd's
hysteresis friction over sliding speed (issue 45).

    /usr/bin/python3 scripts/persson_reference.py CASE --velocities 1e-5:10:13 [--set k=v ...]
        [--gfmd] [--csv out.csv] [--plot out.png]

The case: a viscoelastic half-space (elastic.viscoelastic, any model), a rough indenter, a mean
pressure (load.pressure), frictionless or not (gfmd's hysteresis_friction is compared). The
theory, as its discrete sums over the case's own Fourier modes h_q of the heights (so that
C(q) d^2q = |h_q|^2 exactly, no radial binning; v along x, E*(w) = E(w)/(1 - nu^2) the contact
modulus at w = q_x v, p the mean pressure):

    mu(v) = 1/(2 p) sum_q |q| q_x Im E*(q_x v) |h_q|^2 S(q) P(|q|)
    P(q)  = erf(1 / (2 sqrt(G(q)))),  G(q) = 1/(8 p^2) sum_{|q'| <= q} |q'|^2 |E*(q'_x v)|^2 |h_q'|^2

P(q) is the relative contact area seen at magnification q (full contact: P = 1, where mu is the
exact small-slope result: a wave h0 cos kx gives (k h0)^2 E''(k v)/(4 p), the limit gfmd matches
to 1e-6, docs/solver.md). S(q) = 1 is the 2001 theory (persson_mu); persson_mu_corrected uses Persson's later
correction S = g + (1 - g) P^2 (--gamma g, 0.5 by default) for the reduced deformation of
contact regions smaller than the magnification's wavelength. The modulus is gfmd's own (gfmd._core.modulus_ratio through the
case's viscoelastic keys).
"""
import argparse
import os
import sys

import numpy as np
from scipy.special import erf

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
sys.path.insert(0, os.path.join(BUILD, "python"))
import gfmd  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figure_io  # noqa: E402  (atomic figure and table writes)


def speeds(spec):
    """'a:b:n' (log-spaced, inclusive) or a comma list."""
    if ":" in spec:
        a, b, n = spec.split(":")
        return list(np.geomspace(float(a), float(b), int(n)))
    return [float(v) for v in spec.split(",")]


def contact_modulus(el):
    """E*(w) of the case's [elastic] (as read: summary.json's input), written here from the model's
    definition (include/gfmd/elastic/viscoelastic.hpp), not taken from gfmd: a standard linear
    solid or a Prony series, E0 + sum E_i i w t_i / (1 + i w t_i)."""
    e0 = float(el["contact_modulus"])
    model = el.get("viscoelastic", "none")
    if model == "sls":
        arms = [(float(el["high_frequency_modulus"]) - e0, float(el["relaxation_time"]))]
    elif model == "prony":
        arms = list(zip(map(float, el["prony_moduli"]), map(float, el["prony_times"])))
    else:
        sys.exit(f"persson_reference: elastic.viscoelastic = {model!r}: give \"sls\" or \"prony\"")
    if el.get("viscoelastic_part", "top") != "top" or el.get("viscoelastic_parts") or str(
            el.get("thickness")) != "inf":
        sys.exit("persson_reference: the theory is for a homogeneous viscoelastic half-space")

    def e(w):
        iwt = [1j * w * t for _, t in arms]
        return e0 + sum(ei * x / (1 + x) for (ei, _), x in zip(arms, iwt))

    return e


def persson_mu(heights, lx, ly, modulus, pressure, v, gamma=None):
    """Persson's hysteretic friction of heights (ny x nx, cell lx x ly) sliding along x at v over
    a body of contact modulus modulus(w) (complex, E'' > 0 for w > 0) under mean pressure p."""
    ny, nx = heights.shape
    hq = np.fft.fft2(heights) / heights.size
    qx = 2 * np.pi * np.fft.fftfreq(nx, d=lx / nx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, d=ly / ny)
    QX, QY = np.meshgrid(qx, qy)
    q = np.hypot(QX, QY).ravel()
    c = (np.abs(hq) ** 2).ravel()
    e = modulus(QX.ravel() * v)
    keep = q > 0
    q, c, e, qxs = q[keep], c[keep], e[keep], QX.ravel()[keep]
    order = np.argsort(q, kind="stable")
    q, c, e, qxs = q[order], c[order], e[order], qxs[order]
    # G(q): the cumulative sum over |q'| <= q (modes of one |q| counted together).
    g_terms = q ** 2 * np.abs(e) ** 2 * c / (8 * pressure ** 2)
    g = np.cumsum(g_terms)
    last = np.searchsorted(q, q, side="right") - 1  # the last mode with the same |q|
    g = g[last]
    p = erf(1.0 / (2.0 * np.sqrt(g)))
    s = np.ones_like(p) if gamma is None else gamma + (1 - gamma) * p ** 2
    return float(np.sum(q * qxs * e.imag * c * s * p) / (2 * pressure)), float(p[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("--velocities", required=True, help="'a:b:n' log-spaced (inclusive) or a comma list")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--gamma", type=float, default=0.5,
                    help="persson_mu_corrected's S = g + (1 - g) P^2 (default 0.5; persson_mu has S = 1)")
    ap.add_argument("--gfmd", action="store_true", help="solve the case at each speed too (hysteresis_friction)")
    ap.add_argument("--csv", default="")
    ap.add_argument("--plot", default="")
    args = ap.parse_args()
    vs = speeds(args.velocities)
    # One solve gives the heights and the case as read (at rest when --gfmd is not given).
    first = gfmd.run(args.case, set=args.set + [f"friction.velocity={vs[0]!r}"])
    cfg = first["summary"]["input"]
    if "pressure" not in cfg["load"]:
        sys.exit("persson_reference: the case needs load.pressure (the mean pressure p)")
    pressure = float(cfg["load"]["pressure"])
    grid = cfg["grid"]
    heights = np.asarray(first["fields"]["topography"], dtype=float)
    modulus = contact_modulus(cfg["elastic"])

    rows = []
    for i, v in enumerate(vs):
        mu_p, p_full = persson_mu(heights, grid["lx"], grid["ly"], modulus, pressure, v)
        mu_c, _ = persson_mu(heights, grid["lx"], grid["ly"], modulus, pressure, v, args.gamma)
        row = {"velocity": v, "persson_mu": mu_p, "persson_mu_corrected": mu_c, "persson_area": p_full}
        if args.gfmd:
            s = first["summary"] if i == 0 else gfmd.run(args.case, set=args.set + [f"friction.velocity={v!r}"])[
                "summary"]
            row.update(gfmd_mu=s["hysteresis_friction"], gfmd_area=s["relative_contact_area"],
                       converged=s["converged"])
        rows.append(row)
        print(", ".join(f"{k} {x:.5g}" if isinstance(x, float) else f"{k} {x}" for k, x in row.items()), flush=True)
    if args.csv:
        figure_io.write_csv(args.csv, list(rows[0]), [list(r.values()) for r in rows])
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
        a1.loglog(vs, [r["persson_mu"] for r in rows], "-", label="Persson (2001), this spectrum")
        a1.loglog(vs, [r["persson_mu_corrected"] for r in rows], "--",
                  label=f"Persson, S = {args.gamma:g} + {1 - args.gamma:g} P²")
        a2.loglog(vs, [r["persson_area"] for r in rows], "-", label="Persson P(q_s)")
        if args.gfmd:
            a1.loglog(vs, [r["gfmd_mu"] for r in rows], "o", label="gfmd hysteresis_friction")
            a2.loglog(vs, [r["gfmd_area"] for r in rows], "o", label="gfmd relative_contact_area")
        for a in (a1, a2):
            a.set_xlabel("sliding speed v0 (L / τ)")
            a.legend()
        a1.set_ylabel("hysteresis friction μ_h")
        a2.set_ylabel("relative contact area")
        fig.tight_layout()
        figure_io.save_png(fig, args.plot, dpi=120)


if __name__ == "__main__":
    main()
