"""Persson's theory of hysteretic friction (scripts/persson_reference.py, written from J. Chem.
Phys. 115, 3840 (2001)) against its exact limit and against gfmd on a rough viscoelastic
half-space over six decades of speed (issue 45; docs/solver.md, "Persson's theory")."""
import csv
import math
import os
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import persson_reference as pr  # noqa: E402


def test_in_full_contact_the_sum_is_the_small_slope_result():
    # A wave h0 cos kx under a pressure far above what flattens it: P = 1 on its modes, and the
    # theory is the exact small-slope hysteresis (k h0)^2 E''(k v) / (4 p) (the limit gfmd matches
    # to 1e-6): to 1e-12 at three speeds.
    nx, lx, h0 = 64, 1.0, 0.002
    k = 2 * math.pi * 3 / lx
    x = np.arange(nx) * lx / nx
    heights = np.tile(h0 * np.cos(k * x), (8, 1))
    modulus = pr.contact_modulus({"contact_modulus": 1.0, "viscoelastic": "sls", "high_frequency_modulus": 10.0,
                                  "relaxation_time": 1.0, "thickness": "inf"})
    for v in (0.01, 0.05, 0.3):
        mu, _ = pr.persson_mu(heights, lx, lx / 8, modulus, 100.0, v)
        exact = (k * h0) ** 2 * modulus(np.array([k * v]))[0].imag / (4 * 100.0)
        assert mu == pytest.approx(exact, rel=1e-12)


def test_gfmd_and_persson_over_six_decades(tmp_path):
    # examples/visco_rough_layer.toml's surface (H = 0.8, lambda_l = L/2, lambda_s = L/32, rms
    # gradient 0.1) on a standard-linear-solid half-space (E_inf = 10 E0, tau = 1, nu = 0.5),
    # frictionless, hard wall, p = 0.01 E0, 128^2, v0 from 1e-5 to 10 L/tau (13 speeds). As
    # measured (512^2 alike, docs/solver.md): gfmd's peak lies one half-decade below Persson's
    # (its area falls at lower speeds), between the 2001 theory and the S = 1/2 + P^2/2 correction
    # there; at the slow end gfmd is above the 2001 theory (its contact area is larger: Persson's
    # P(q) is known to underestimate it), at the fast end below it.
    table = tmp_path / "p.csv"
    cmd = [sys.executable, os.path.join(ROOT, "scripts", "persson_reference.py"),
           os.path.join(ROOT, "examples", "visco_rough_layer.toml"), "--velocities", "1e-5:10:13", "--gfmd",
           "--csv", str(table)]
    for kv in ("elastic.thickness=inf", "friction.coefficient=0", "friction.regularization=0", "grid.nx=128",
               "indenter.lambda_short=0.03125", "elastic.poisson=0.5", 'interaction.model="hardwall"'):
        cmd += ["--set", kv]
    subprocess.run(cmd, check=True, capture_output=True, timeout=300)
    rows = list(csv.DictReader(open(table)))
    assert len(rows) == 13 and all(r["converged"] == "True" for r in rows)
    v = [float(r["velocity"]) for r in rows]
    g = [float(r["gfmd_mu"]) for r in rows]
    p = [float(r["persson_mu"]) for r in rows]
    c = [float(r["persson_mu_corrected"]) for r in rows]
    ig, ip = int(np.argmax(g)), int(np.argmax(p))
    assert 1e-3 <= v[ig] <= 3e-2 and ip - ig in (0, 1), (v[ig], v[ip])
    assert c[ig] < g[ig] < p[ig]
    assert 1.0 < g[0] / p[0] < 1.5
    assert 0.25 < g[-1] / p[-1] < 0.6
