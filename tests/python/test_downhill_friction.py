"""summary.json downhill_friction: the downhill-slope force per normal force, -<p dh/dx>/<p>
(Eq. (8) of the paper's supplement, the quantity its Fig. 2(e) plots), checked against an
independent numpy evaluation from the result's own fields."""
import numpy as np

import gfmd


def _downhill_from_fields(r, lx):
    h, p = r["topography"], r["pressure"]
    k = 2 * np.pi * np.fft.fftfreq(h.shape[1], d=lx / h.shape[1])
    dhdx = np.fft.ifft(1j * k[None, :] * np.fft.fft(h, axis=1), axis=1).real  # x along axis 1
    return -(p * dhdx).sum() / p.sum()


def test_downhill_friction_is_the_slope_force_per_load():
    t = gfmd.Topography.eggcrate(64, 1.0)
    r = gfmd.solve(t, gfmd.ElasticBody(poisson=0.25), pressure=0.05, friction=0.5)
    s = r.summary
    ref = _downhill_from_fields(r, 1.0)
    assert abs(ref) > 1e-3  # coupling tilts the pressure: a force to measure
    assert s["downhill_friction"] == np.float64(s["downhill_force"] / s["normal_force"])
    assert abs(s["downhill_friction"] - ref) < 1e-9 * abs(ref)
    # Where every point slips, Σ|τ| = μ_c F_z: the downhill coefficient is μ_c + ΔF/F_z (README).
    assert s["stick_fraction"] == 0
    assert abs(s["friction_coefficient_downhill"] - (0.5 + s["downhill_friction"])) < 1e-9


def test_downhill_friction_vanishes_without_coupling():
    # ν = 0.5 half-space: no normal/in-plane coupling, the pressure stays symmetric, ΔF = 0.
    t = gfmd.Topography.eggcrate(64, 1.0)
    r = gfmd.solve(t, gfmd.ElasticBody(poisson=0.5), pressure=0.05, friction=0.5)
    assert abs(r.summary["downhill_friction"]) < 1e-6
    assert abs(_downhill_from_fields(r, 1.0)) < 1e-6
