#!/usr/bin/python3
"""Maximum tensile stress sigma_I^max of solved runs under two surface Hooke laws.

Reads DIR/fields.nc and DIR/summary.json of `gfmd run` directories and recomputes the
surface stress tensor from the surface displacements ux, uy (spectral derivatives, the
Nyquist derivative dropped as in the solver), sigma_zz = -p and sigma_az = tractions:

  isotropic (SPEC §5, what gfmd writes as sigma_1):
      sigma_xx = E* (e_xx + nu e_yy) + nu/(1-nu) sigma_zz,  sigma_xy = E* (1-nu)/2 (d_y u_x + d_x u_y)
  authors (the coefficients of the paper authors' analysis script):
      sigma_xx = E* (1 + nu (1-2nu))/2 e_xx + E* nu (1-nu) e_yy + 2 nu sigma_zz
      sigma_xy = E* (1-nu)/4 (d_y u_x + d_x u_y)
  (sigma_yy alike with x and y exchanged), E* = elastic.contact_modulus.

    /usr/bin/python3 scripts/authors_hooke.py DIR [DIR ...] [--json]

With two directories of the same case at different resolutions it also extrapolates the
grid maxima in sqrt(dx) (the trailing-edge cusp makes them converge like sqrt(dx)).
"""
import argparse
import json
import math
import os
import sys

import netCDF4
import numpy as np


def load(d):
    with open(os.path.join(d, "summary.json")) as f:
        s = json.load(f)
    with netCDF4.Dataset(os.path.join(d, "fields.nc")) as nc:
        get = lambda k: np.array(nc.variables[k][:], dtype=float) if k in nc.variables else None  # noqa: E731
        f = {k: get(k) for k in ("ux", "uy", "pressure", "traction_x", "traction_y", "sigma_1")}
        f["lx"], f["ly"] = float(nc.getncattr("lx")), float(nc.getncattr("ly"))
    el = s["input"]["elastic"]
    return s, f, float(el["contact_modulus"]), float(el["poisson"])


def derivatives(u, lx, ly):
    """(d/dx u, d/dy u) by FFT, the Nyquist wave numbers' derivative dropped."""
    ny, nx = u.shape
    qx = 2 * np.pi * np.fft.fftfreq(nx, d=lx / nx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, d=ly / ny)
    if nx % 2 == 0:
        qx[nx // 2] = 0.0
    if ny % 2 == 0:
        qy[ny // 2] = 0.0
    U = np.fft.fft2(u)
    dx = np.real(np.fft.ifft2(U * (1j * qx)[None, :]))
    dy = np.real(np.fft.ifft2(U * (1j * qy)[:, None]))
    return dx, dy


def stress(f, es, nu, law):
    """The six components (xx, yy, zz, xy, xz, yz) of the surface stress under `law`."""
    uxx, uxy = derivatives(f["ux"], f["lx"], f["ly"])
    uyx, uyy = derivatives(f["uy"], f["lx"], f["ly"])
    zz = -f["pressure"]
    zero = np.zeros_like(zz)
    xz = f["traction_x"] if f["traction_x"] is not None else zero
    yz = f["traction_y"] if f["traction_y"] is not None else zero
    shear = uxy + uyx
    if law == "isotropic":
        xx = es * (uxx + nu * uyy) + nu / (1 - nu) * zz
        yy = es * (uyy + nu * uxx) + nu / (1 - nu) * zz
        xy = es * (1 - nu) / 2 * shear
    elif law == "authors":
        xx = es * (1 + nu * (1 - 2 * nu)) / 2 * uxx + es * nu * (1 - nu) * uyy + 2 * nu * zz
        yy = es * (1 + nu * (1 - 2 * nu)) / 2 * uyy + es * nu * (1 - nu) * uxx + 2 * nu * zz
        xy = es * (1 - nu) / 4 * shear
    else:
        raise ValueError(law)
    return xx, yy, zz, xy, xz, yz


def sigma_1(xx, yy, zz, xy, xz, yz):
    """Largest principal stress per point."""
    t = np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1), np.stack([xz, yz, zz], -1)], -2)
    return np.linalg.eigvalsh(t)[..., -1]


def analyse(d):
    s, f, es, nu = load(d)
    out = {"dir": d, "nx": int(s["input"]["grid"]["nx"]), "dx": f["lx"] / f["ux"].shape[1], "poisson": nu,
           "coupling": bool(s["input"]["elastic"].get("coupling", True))}
    for law in ("isotropic", "authors"):
        out[law] = float(sigma_1(*stress(f, es, nu, law)).max())
    if f["sigma_1"] is not None:  # what gfmd wrote, for the check that "isotropic" is its law
        out["gfmd_sigma_1_max"] = float(f["sigma_1"].max())
    return out


def extrapolate(a, b):
    """sigma(dx) = sigma_0 + c sqrt(dx) through two resolutions."""
    ra, rb = math.sqrt(a["dx"]), math.sqrt(b["dx"])
    return {law: (b[law] * ra - a[law] * rb) / (ra - rb) for law in ("isotropic", "authors")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--json", action="store_true", help="print the results as JSON")
    args = ap.parse_args()
    rows = [analyse(d) for d in args.dirs]
    res = {"runs": rows}
    if len(rows) == 2 and rows[0]["dx"] != rows[1]["dx"]:
        res["extrapolated"] = extrapolate(rows[0], rows[1])
    if args.json:
        print(json.dumps(res, indent=2))
        return
    for r in rows:
        print(f"{r['dir']}: nx = {r['nx']}, sigma_I^max / E* = {r['isotropic']:.5f} (isotropic Hooke), "
              f"{r['authors']:.5f} (authors' coefficients)")
    if "extrapolated" in res:
        e = res["extrapolated"]
        print(f"extrapolated in sqrt(dx): {e['isotropic']:.5f} (isotropic), {e['authors']:.5f} (authors)")


if __name__ == "__main__":
    sys.exit(main())
