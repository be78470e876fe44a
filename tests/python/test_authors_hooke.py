"""scripts/authors_hooke.py: the surface stress under the authors' Hooke coefficients and
under the isotropic law, against hand-computed tensors and against gfmd's own sigma_1."""
import json
import math
import os
import subprocess
import sys

import netCDF4
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import authors_hooke  # noqa: E402

GFMD = os.path.join(ROOT, "build", "gfmd")


def write_run(d, ux, uy, p, tx, es, nu, lx=1.0):
    os.makedirs(d, exist_ok=True)
    ny, nx = ux.shape
    with netCDF4.Dataset(os.path.join(d, "fields.nc"), "w") as nc:
        nc.createDimension("y", ny)
        nc.createDimension("x", nx)
        for name, v in (("ux", ux), ("uy", uy), ("pressure", p), ("traction_x", tx)):
            nc.createVariable(name, "f8", ("y", "x"))[:] = v
        nc.setncattr("lx", lx)
        nc.setncattr("ly", lx * ny / nx)
    with open(os.path.join(d, "summary.json"), "w") as f:
        json.dump({"input": {"grid": {"nx": nx}, "elastic": {"contact_modulus": es, "poisson": nu}}}, f)


def test_single_mode_tensor_by_hand(tmp_path):
    # u_x = a sin(2 pi x) + c sin(2 pi y), u_y = b sin(2 pi y) on the unit cell, uniform p and
    # tau_x: at grid point (ix, iy) = (1, 2) of 16 x 16 the strains are
    # e_xx = 2 pi a cos(2 pi x), e_yy = 2 pi b cos(2 pi y), d_y u_x + d_x u_y = 2 pi c cos(2 pi y).
    n, a, b, c, p0, t0, es, nu = 16, 1e-3, -2e-3, 1.5e-3, 0.07, 0.03, 2.0, 0.3
    x = np.arange(n) / n
    X, Y = np.meshgrid(x, x)
    ux = a * np.sin(2 * np.pi * X) + c * np.sin(2 * np.pi * Y)
    uy = b * np.sin(2 * np.pi * Y)
    d = str(tmp_path / "mode")
    write_run(d, ux, uy, np.full_like(ux, p0), np.full_like(ux, t0), es, nu)
    _, f, es_read, nu_read = authors_hooke.load(d)
    assert (es_read, nu_read) == (es, nu)
    ix, iy = 1, 2
    exx = 2 * np.pi * a * math.cos(2 * np.pi * x[ix])
    eyy = 2 * np.pi * b * math.cos(2 * np.pi * x[iy])
    g = 2 * np.pi * c * math.cos(2 * np.pi * x[iy])
    zz = -p0
    expected = {
        "isotropic": (es * (exx + nu * eyy) + nu / (1 - nu) * zz, es * (eyy + nu * exx) + nu / (1 - nu) * zz,
                      es * (1 - nu) / 2 * g),
        "authors": (es * (1 + nu * (1 - 2 * nu)) / 2 * exx + es * nu * (1 - nu) * eyy + 2 * nu * zz,
                    es * (1 + nu * (1 - 2 * nu)) / 2 * eyy + es * nu * (1 - nu) * exx + 2 * nu * zz,
                    es * (1 - nu) / 4 * g),
    }
    for law, (sxx, syy, sxy) in expected.items():
        xx, yy, zzf, xy, xz, yz = authors_hooke.stress(f, es, nu, law)
        assert xx[iy, ix] == pytest.approx(sxx, abs=1e-12)
        assert yy[iy, ix] == pytest.approx(syy, abs=1e-12)
        assert xy[iy, ix] == pytest.approx(sxy, abs=1e-12)
        assert (zzf[iy, ix], xz[iy, ix], yz[iy, ix]) == (zz, t0, 0.0)
        t = np.array([[sxx, sxy, t0], [sxy, syy, 0.0], [t0, 0.0, zz]])
        s1 = authors_hooke.sigma_1(xx, yy, zzf, xy, xz, yz)
        assert s1[iy, ix] == pytest.approx(np.linalg.eigvalsh(t)[-1], abs=1e-12)
    # The two laws differ (nu = 0.3): the script does not silently use one for both.
    assert abs(authors_hooke.stress(f, es, nu, "authors")[0][iy, ix] - expected["isotropic"][0]) > 1e-4


def test_isotropic_law_reproduces_gfmd_sigma_1(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text("[grid]\nnx = 128\nlx = 4.0\n[elastic]\npoisson = 0.25\n[indenter]\ntype = \"hertz\"\n"
                    "radius = 1.0\n[load]\nforce = 0.01\n[friction]\ncoefficient = 1.0\n[output]\npng = false\n")
    out = tmp_path / "out"
    subprocess.run([GFMD, "run", str(case), "-o", str(out), "-q"], check=True)
    r = authors_hooke.analyse(str(out))
    assert r["isotropic"] == pytest.approx(r["gfmd_sigma_1_max"], rel=1e-10)
    assert r["authors"] != pytest.approx(r["isotropic"], rel=1e-3)
    # Command line: the same numbers as JSON.
    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "authors_hooke.py"), str(out), "--json"],
                       check=True, capture_output=True, text=True)
    assert json.loads(p.stdout)["runs"][0]["authors"] == pytest.approx(r["authors"], rel=1e-14)
