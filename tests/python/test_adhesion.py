"""Adhesion from Python: gfmd.Adhesive as the interaction of gfmd.solve / gfmd.ContactSolver, and
load paths that unload along their branch (gfmd.load_path with approaches)."""
import math

import numpy as np
import pytest

import gfmd

# A paraboloid R = 1 on an incompressible half-space, w = 1e-3, range for Maugis's lambda = 1.
W, RANGE = 1e-3, 0.0113


def sphere(nx=128):
    return gfmd.Topography.hertz(nx=nx, lx=1.5, radius=1.0)


def test_unloading_keeps_the_contact_a_cold_start_does_not_make():
    # Hysteresis: at approach -0.015 (beyond the range at first touch) the path unloading from
    # contact still holds one (Maugis's branch goes on to about -0.0157 here), a cold solve has none.
    body = gfmd.ElasticBody(poisson=0.5)
    solver = gfmd.ContactSolver(sphere(), body, interaction=gfmd.Adhesive(W, RANGE))
    path = list(gfmd.load_path(solver, approaches=[0.01, 0.0, -0.005, -0.01, -0.015]))
    forces = [r.summary["normal_force"] for r in path]
    assert min(forces) < -1.5 * math.pi * W  # the pull-off, about -1.6 pi w R
    assert path[-1].summary["relative_contact_area"] > 0
    assert path[-1].summary["normal_force"] < 0
    cold = gfmd.solve(sphere(), body, approach=-0.015, interaction=gfmd.Adhesive(W, RANGE))
    assert cold.summary["relative_contact_area"] == 0
    # The adhesive figures and fields.
    r = path[2]
    assert r.summary["adhesive_force"] > 0
    assert r.summary["repulsive_force"] == pytest.approx(r.summary["normal_force"] + r.summary["adhesive_force"])
    a = r["adhesive_traction"]
    assert a.shape == (128, 128)
    assert a.max() == pytest.approx(W / RANGE)
    assert np.array_equal(r["attraction"] > 0.5, a > 0)
    assert r.pressure.min() < 0  # tension where the cohesive zone pulls


def test_vanishing_adhesion_is_the_hard_wall_bit_for_bit():
    body = gfmd.ElasticBody(poisson=0.5)
    a = gfmd.solve(sphere(64), body, approach=0.01, interaction=gfmd.Adhesive(0.0, RANGE))
    h = gfmd.solve(sphere(64), body, approach=0.01, interaction="hardwall")
    assert np.array_equal(a.pressure, h.pressure)


@pytest.mark.parametrize("args, message", [
    ((-1e-3, 0.01), "Adhesive.work_of_adhesion: must be zero or positive"),
    ((1e-3, 0.0), "Adhesive.range: must be positive"),
    ((1e-3, math.nan), "Adhesive.range: must be a finite number"),
    ((1e-3, 0.01, "soft"), "Adhesive.repulsion: one of harmonic, hardwall"),
])
def test_bad_adhesion_is_refused(args, message):
    with pytest.raises(gfmd.InputError, match=message):
        gfmd.Adhesive(*args)


def test_sliding_adhesive_sphere_with_a_uniform_shear_keeps_its_frictionless_contact():
    # Menga, Carbone & Dini: a uniform shear tau0 over the contact of an incompressible half-space
    # leaves the adhesive contact as it was (nothing couples it to the normal problem): the net force
    # and the contact of the frictionless solve (to the tolerance), the shear summed over the contact.
    # With Coulomb's law the traction is bounded by mu_c times the repulsion (the compressive part).
    body = gfmd.ElasticBody(poisson=0.5)
    still = gfmd.solve(sphere(64), body, approach=0.0, interaction=gfmd.Adhesive(W, RANGE))
    slid = gfmd.solve(sphere(64), body, approach=0.0, interaction=gfmd.Adhesive(W, RANGE), friction=1e3,
                      law="tresca", shear_strength=0.02)
    assert slid.summary["converged"], slid.summary["status"]
    assert slid.summary["normal_force"] == pytest.approx(still.summary["normal_force"], rel=1e-6)
    assert slid.summary["relative_contact_area"] == still.summary["relative_contact_area"]
    assert slid.summary["normal_force"] < 0
    area = slid.summary["relative_contact_area"] * 1.5 ** 2
    assert slid.summary["tangential_force"] == pytest.approx(0.02 * area, rel=0.1)
    coulomb = gfmd.solve(sphere(64), gfmd.ElasticBody(poisson=0.3), approach=0.0,
                         interaction=gfmd.Adhesive(W, RANGE), friction=0.3)
    s = coulomb.summary
    assert s["converged"], s["status"]
    sum_abs_tau = s["friction_force_downhill"] - s["downhill_force"]
    assert sum_abs_tau == pytest.approx(0.3 * s["repulsive_force"], rel=1e-9)
    with pytest.raises(gfmd.InputError, match="interaction: "):
        gfmd.ContactSolver(sphere(64), interaction=3)


def test_curve_along_an_approach_path_as_the_command_line(tmp_path):
    # gfmd.curve(approaches=..., unload=True) = gfmd curve --approaches ... --unload: the same rows.
    case = tmp_path / "adh.toml"
    case.write_text('[grid]\nnx = 64\nlx = 1.5\n[elastic]\npoisson = 0.5\n[indenter]\ntype = "hertz"\nradius = 1.0\n'
                    '[load]\napproach = 0.0\n[interaction]\nmodel = "adhesive"\nwork_of_adhesion = 1e-3\n'
                    'range = 0.0113\n[output]\npng = false\n')
    j = gfmd.curve(str(case), output=str(tmp_path / "py"), approaches=[-0.01, 0.0, 0.01], unload=True)
    assert j["approaches"] == [-0.01, 0.0, 0.01, 0.0, -0.01]
    assert [p["branch"] for p in j["points"]] == ["load", "load", "load", "unload", "unload"]
    assert j["pull_off_force"] == min(p["normal_force"] for p in j["points"]) < 0
    with pytest.raises(gfmd.InputError, match="unload: only with approaches"):
        gfmd.curve(str(case), [0.01], str(tmp_path / "bad"), unload=True)
    with pytest.raises(gfmd.InputError, match="give one of pressures and approaches"):
        gfmd.curve(str(case), [0.01], str(tmp_path / "bad"), approaches=[0.0])


def test_adhesion_on_a_viscoelastic_body():
    # A sphere (R = 1) on a standard linear solid (E0* = 1, E_inf* = 10, tau = 1), F = 0.01, with
    # Maugis-Dugdale adhesion (w = 1e-3, range 0.01), 256^2 on 4 R.
    top = gfmd.Topography.hertz(nx=256, lx=4.0, radius=1.0)
    visco = gfmd.ViscoelasticBody(poisson=0.5, high_frequency_modulus=10.0, relaxation_time=1.0)
    sticky = gfmd.Adhesive(1e-3, 0.01)
    # At rest every mode is relaxed: the elastic adhesive solve with E0, bit for bit.
    rest = gfmd.solve(top, visco, force=0.01, velocity=0.0, interaction=sticky)
    elastic = gfmd.solve(top, gfmd.ElasticBody(poisson=0.5), force=0.01, interaction=sticky)
    assert np.array_equal(rest.pressure, elastic.pressure)
    assert np.array_equal(rest["adhesive_traction"], elastic["adhesive_traction"])
    # Sliding at v0 = 0.02 R/tau (near the hysteresis peak): the independent residual (the full
    # complex response) holds, the work of the tractions on the body is the spectral hysteresis,
    # and the force on the indenter, sum p dh/dx dA, is that work too: the cohesive law does no
    # net work over a steady pass (measured: 6.6e-4 apart, as without adhesion, 7.6e-4; 2.7e-4 at
    # 512^2). Adhesion triples the hysteresis friction here (0.232 against 0.078).
    slide = gfmd.solve(top, visco, force=0.01, velocity=0.02, interaction=sticky)
    s = slide.summary
    assert s["converged"] and s["adhesive_force"] > 0.02
    assert s["hysteresis_balance_error"] < 1e-9
    h = top.heights
    k = 2 * math.pi * np.fft.fftfreq(256, d=4.0 / 256)
    dh = np.real(np.fft.ifft(1j * k[None, :] * np.fft.fft(h, axis=1), axis=1))
    on_indenter = -float(np.sum(slide.pressure * dh)) * (4.0 / 256) ** 2
    assert on_indenter == pytest.approx(s["hysteresis_dissipation"], rel=2e-3)
    plain = gfmd.solve(top, visco, force=0.01, velocity=0.02).summary
    assert s["hysteresis_friction"] > 2 * plain["hysteresis_friction"]
