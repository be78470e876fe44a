"""Viscoelastic bodies from Python: gfmd.ViscoelasticBody with the solve's velocity= (steady
sliding), against the relaxed elastic solve and the energy balance of the hysteresis."""
import pytest

import gfmd


def sphere(nx=64):
    return gfmd.Topography.hertz(nx=nx, lx=2.0, radius=1.0)


def test_a_sliding_sphere_has_hysteresis_friction_that_vanishes_at_rest():
    body = gfmd.ViscoelasticBody(poisson=0.5, high_frequency_modulus=10.0, relaxation_time=1.0)
    moving = gfmd.solve(sphere(), body, force=0.01, velocity=0.02)
    s = moving.summary
    assert s["converged"]
    assert s["hysteresis_friction"] > 0.01  # about 0.07 at the peak on this grid
    assert s["hysteresis_balance_error"] < 1e-9
    assert s["centroid_shift"] > 0  # the pressure moves to the leading edge
    assert s["hysteresis_power"] == pytest.approx(0.02 * s["hysteresis_force"])
    # At rest: the elastic solve with the relaxed modulus, the same numbers.
    rest = gfmd.solve(sphere(), body, force=0.01)
    elastic = gfmd.solve(sphere(), gfmd.ElasticBody(poisson=0.5), force=0.01)
    assert rest.summary["max_pressure"] == elastic.summary["max_pressure"]
    assert rest.summary["hysteresis_friction"] == pytest.approx(0.0, abs=1e-12)
    # A Prony series of one arm is the same body.
    prony = gfmd.ViscoelasticBody(poisson=0.5, prony_moduli=(9.0,), prony_times=(1.0,))
    same = gfmd.solve(sphere(), prony, force=0.01, velocity=0.02)
    assert same.summary["hysteresis_friction"] == pytest.approx(s["hysteresis_friction"], rel=1e-9)


def test_bad_viscoelastic_input_names_the_key():
    with pytest.raises(gfmd.InputError, match="ViscoelasticBody"):
        gfmd.ViscoelasticBody(poisson=0.5)
    with pytest.raises(gfmd.InputError, match="high_frequency_modulus"):
        gfmd.solve(sphere(), gfmd.ViscoelasticBody(high_frequency_modulus=0.5, relaxation_time=1.0), force=0.01)
    with pytest.raises(gfmd.InputError, match="velocity"):
        gfmd.solve(sphere(), gfmd.ElasticBody(), force=0.01, velocity=1.0)
    with pytest.raises(gfmd.InputError, match="friction.regularization"):
        gfmd.solve(sphere(), gfmd.ViscoelasticBody(high_frequency_modulus=2.0, relaxation_time=1.0), force=0.01,
                   friction=0.3, velocity=1.0)


def test_a_master_curve_file_is_the_body_it_tabulates(tmp_path):
    # A standard linear solid tabulated at 20 rows per decade: the same friction to the
    # interpolation's error; a WLF shift of the reference temperature is no shift.
    path = tmp_path / "sls.csv"
    rows = ["omega,storage,loss"]
    for k in range(161):
        w = 10.0 ** (-4 + k / 20)
        e = 10 - 9 / (1 + 1j * w)
        rows.append(f"{w!r},{e.real!r},{e.imag!r}")
    path.write_text("\n".join(rows) + "\n")
    sls = gfmd.ViscoelasticBody(poisson=0.5, high_frequency_modulus=10.0, relaxation_time=1.0)
    table = gfmd.ViscoelasticBody(poisson=0.5, master_curve=str(path))
    a = gfmd.solve(sphere(), sls, force=0.01, velocity=0.02).summary
    b = gfmd.solve(sphere(), table, force=0.01, velocity=0.02).summary
    assert b["hysteresis_friction"] == pytest.approx(a["hysteresis_friction"], rel=1e-3)
    assert b["input"]["elastic"]["master_curve"] == str(path)
    same = gfmd.ViscoelasticBody(poisson=0.5, master_curve=str(path),
                                 shift={"temperature": 20, "reference_temperature": 20, "wlf_c1": 8.86, "wlf_c2": 101.6})
    c = gfmd.solve(sphere(), same, force=0.01, velocity=0.02).summary
    assert c["hysteresis_friction"] == b["hysteresis_friction"]
    with pytest.raises(gfmd.InputError, match="master_curve"):
        gfmd.ViscoelasticBody(master_curve=str(path), relaxation_time=1.0)


def test_friction_on_a_viscoelastic_body_adds_the_hysteresis():
    # Coulomb friction (regularised near rest) with the body's hysteresis: the total friction is
    # the interface's plus the hysteresis (the work balance), above mu_c.
    body = gfmd.ViscoelasticBody(poisson=0.3, thickness=0.5, high_frequency_modulus=10.0, relaxation_time=1.0)
    s = gfmd.solve(sphere(), body, force=0.01, velocity=0.02, friction=0.3, regularization=0.01).summary
    assert s["converged"]
    assert s["total_friction_coefficient"] == pytest.approx(s["friction_coefficient"] + s["hysteresis_friction"],
                                                            rel=1e-3)
    assert s["total_friction_coefficient"] > 0.3
    assert s["hysteresis_balance_error"] < 1e-9
