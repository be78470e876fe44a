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
    with pytest.raises(gfmd.InputError, match="friction.coefficient"):
        gfmd.solve(sphere(), gfmd.ViscoelasticBody(high_frequency_modulus=2.0, relaxation_time=1.0), force=0.01,
                   friction=0.3, velocity=1.0)
