"""Viscoelastic bodies from Python: gfmd.ViscoelasticBody with the solve's velocity= (steady
sliding), against the relaxed elastic solve and the energy balance of the hysteresis."""
import pytest

import gfmd
from visco_tables import write_sls_master_curve


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
    # At rest: the elastic solve with the relaxed modulus, the same numbers. Without velocity=
    # the solve warns (usually a forgotten speed).
    with pytest.warns(UserWarning, match="friction.velocity is not"):
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
    # Checked on construction, by the case files' rules, as ElasticBody is (not at the first solve).
    for kw, key in [(dict(high_frequency_modulus=0.5, relaxation_time=1.0), "elastic.high_frequency_modulus"),
                    (dict(high_frequency_modulus=5.0, relaxation_time=-1.0), "elastic.relaxation_time"),
                    (dict(high_frequency_modulus=5.0), "relaxation_time: is needed")]:
        with pytest.raises(gfmd.InputError, match=key):
            gfmd.ViscoelasticBody(**kw)
    with pytest.raises(gfmd.InputError, match="velocity"):
        gfmd.solve(sphere(), gfmd.ElasticBody(), force=0.01, velocity=1.0)


def test_a_master_curve_file_is_the_body_it_tabulates(tmp_path):
    # A standard linear solid tabulated at 20 rows per decade: the same friction to the
    # interpolation's error; a WLF shift of the reference temperature is no shift.
    path = write_sls_master_curve(tmp_path / "sls.csv")
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


def test_a_rubber_sphere_rolls_with_stick():
    # Tractive rolling (creepage 1e-3) of a sphere over a standard linear solid with Coulomb's
    # set-valued law: much of the contact sticks; slowly rolled it is the elastic body's rolling
    # with E0 (to the tolerance); near the loss peak it adds the hysteresis, and the driving work
    # balances the interface's and the body's dissipation (1.7e-3 measured at 64^2; the sphere's
    # balance converges with the grid: docs/solver.md).
    top = gfmd.Topography.hertz(nx=64, lx=1.0, radius=1.0)
    body = gfmd.ViscoelasticBody(poisson=0.3, high_frequency_modulus=10.0, relaxation_time=1.0)
    slow = gfmd.solve(top, body, force=0.0026, velocity=1e-9, friction=0.3, creepage=1e-3).summary
    elastic = gfmd.solve(top, gfmd.ElasticBody(poisson=0.3), force=0.0026, friction=0.3, creepage=1e-3).summary
    assert slow["converged"] and elastic["converged"]
    assert 0.3 < elastic["stick_fraction"] < 1.0
    assert slow["stick_fraction"] == elastic["stick_fraction"]
    assert slow["tangential_force"] == pytest.approx(elastic["tangential_force"], rel=1e-6)
    peak = gfmd.solve(top, body, force=0.0026, velocity=0.03, friction=0.3, creepage=1e-3).summary
    assert peak["converged"], peak["status"]
    assert peak["stick_fraction"] > 0.3
    assert peak["hysteresis_friction"] > 1e-3
    assert peak["energy_balance_error_exact"] < 0.01


def test_plastic_saturation_on_a_viscoelastic_body():
    # A sphere (R = 1) on a standard linear solid (E0* = 1, E_inf* = 10, tau = 1), F = 0.01,
    # sliding at v0 = 0.02 R/tau (near the hysteresis peak; p_max = 0.32 E0 without a cap), with
    # the pressure capped at H (interaction.hardness), 256^2 on 4 R.
    import math
    import numpy as np
    top = gfmd.Topography.hertz(nx=256, lx=4.0, radius=1.0)
    visco = gfmd.ViscoelasticBody(poisson=0.5, high_frequency_modulus=10.0, relaxation_time=1.0)
    run = dict(force=0.01, velocity=0.02, interaction="hardwall", tolerance=1e-10)
    # At rest: the elastic-plastic solve with E0, bit for bit.
    rest = gfmd.solve(top, visco, force=0.01, velocity=0.0, interaction="hardwall", hardness=0.1)
    elastic = gfmd.solve(top, gfmd.ElasticBody(poisson=0.5), force=0.01, interaction="hardwall", hardness=0.1)
    assert np.array_equal(rest.pressure, elastic.pressure)
    free = gfmd.solve(top, visco, **run)
    # A cap above every pressure changes nothing but the solve's path (measured 8.7e-10).
    high = gfmd.solve(top, visco, hardness=0.5, **run)
    assert np.max(np.abs(high.pressure - free.pressure)) < 1e-8 * np.max(free.pressure)
    capped = gfmd.solve(top, visco, hardness=0.1, **run)
    s = capped.summary
    assert s["converged"] and s["max_pressure"] <= 0.1 * (1 + 1e-12)
    assert s["plastic_area_fraction"] > 0.003 and s["max_plastic_displacement"] > 0
    # The energy balance: the force on the indenter, -sum p dh/dx dA, is the body's hysteresis (the
    # plastic overlap vanishes at the plastic zone's edges, so the cap does no net work over a pass):
    # measured 7.0e-3 apart here, 3.2e-3 at 128^2, 5.5e-4 at 512^2 (7.6e-4 here without the cap).
    k = 2 * math.pi * np.fft.fftfreq(256, d=4.0 / 256)
    dh = np.real(np.fft.ifft(1j * k[None, :] * np.fft.fft(top.heights, axis=1), axis=1))
    on_indenter = -float(np.sum(capped.pressure * dh)) * (4.0 / 256) ** 2
    assert on_indenter == pytest.approx(s["hysteresis_dissipation"], rel=1e-2)
    assert s["hysteresis_balance_error"] < 1e-9
    # Capping the peak pressure takes away much of the asymmetry (0.044 against 0.078).
    assert s["hysteresis_friction"] < 0.7 * free.summary["hysteresis_friction"]
    # Load and approach control give the same state (measured 1.1e-9 of H).
    same = gfmd.solve(top, visco, approach=s["approach"], velocity=0.02, interaction="hardwall", hardness=0.1,
                      tolerance=1e-10)
    assert np.max(np.abs(same.pressure - capped.pressure)) < 1e-8
    # With adhesion too (w = 1e-3, range 0.02: sigma0 = 0.05 against H = 0.15): converged, and the
    # balance within 2e-2 (measured 1.2e-2; 2.2e-2 at 128^2, 6e-3 at 512^2).
    sticky = gfmd.solve(top, visco, hardness=0.15, **dict(run, interaction=gfmd.Adhesive(1e-3, 0.02)))
    t = sticky.summary
    assert t["converged"] and t["plastic_area_fraction"] > 0 and t["adhesive_force"] > 0
    on_indenter = -float(np.sum(sticky.pressure * dh)) * (4.0 / 256) ** 2
    assert on_indenter == pytest.approx(t["hysteresis_dissipation"], rel=2e-2)


def test_a_viscoelastic_body_under_an_elastic_indenter():
    # Frictionless, an elastic half-space indenter (E_i* = 2) on a standard linear solid (E0* = 1,
    # E_inf* = 10, tau = 1; the same nu) acts as a spring in series: the rigid sphere on the
    # standard linear solid E0' = 2/3, E_inf' = 5/3, tau' = 4 (tests/test_viscoelastic_pair.cpp
    # derives it). With the hard wall the hysteresis friction is that solid's to 1e-6.
    top = gfmd.Topography.hertz(nx=64, lx=2.0, radius=1.0)
    run = dict(force=0.01, velocity=0.1, interaction="hardwall", tolerance=1e-10)
    pair = gfmd.solve(top, gfmd.ViscoelasticBody(poisson=0.3, high_frequency_modulus=10.0, relaxation_time=1.0),
                      indenter_body=gfmd.ElasticBody(contact_modulus=2.0, poisson=0.3), **run).summary
    one = gfmd.solve(top, gfmd.ViscoelasticBody(contact_modulus=2.0 / 3.0, poisson=0.3,
                                                 high_frequency_modulus=5.0 / 3.0, relaxation_time=4.0), **run).summary
    assert pair["converged"] and one["converged"]
    assert one["hysteresis_friction"] > 1e-3
    assert pair["hysteresis_friction"] == pytest.approx(one["hysteresis_friction"], rel=1e-6)
    assert pair["hysteresis_balance_error"] < 1e-9


def test_a_viscoelastic_coating_on_an_elastic_substrate():
    # The top layer a standard linear solid (h = 0.05 R) on an elastic substrate: it slides with
    # hysteresis that its pressure's asymmetry drives (the two sums agree), at rest it is the
    # elastic coating, and its planes below the surface are given in motion too.
    top = gfmd.Topography.hertz(nx=64, lx=2.0, radius=1.0)
    coat = dict(poisson=0.3, thickness=0.05, substrate_contact_modulus=2.0, substrate_poisson=0.25)
    visco = gfmd.ViscoelasticBody(high_frequency_modulus=10.0, relaxation_time=1.0, **coat)
    run = dict(force=0.005, interaction="hardwall", tolerance=1e-10)
    moving = gfmd.solve(top, visco, velocity=0.1, **run).summary
    assert moving["converged"] and moving["hysteresis_friction"] > 1e-3
    assert moving["hysteresis_balance_error"] < 1e-9
    rest = gfmd.solve(top, visco, velocity=0.0, **run).summary
    elastic = gfmd.solve(top, gfmd.ElasticBody(**coat), **run).summary
    assert rest["relative_contact_area"] == elastic["relative_contact_area"]
    assert rest["max_pressure"] == elastic["max_pressure"]
    planes = gfmd.solve(top, visco, velocity=0.1, stress_depths=[0.02, 0.05], **run).summary
    assert [p["depth"] for p in planes["subsurface"]] == [0.02, 0.05]


def test_a_hard_film_on_a_viscoelastic_substrate():
    # part="substrate": an elastic film (E* = 5, h = 0.05 R) on a standard-linear-solid substrate
    # (E0* = 1, E_inf* = 10, tau = 1): the hysteresis comes from the substrate, and a film thicker
    # than the cell hides it.
    top = gfmd.Topography.hertz(nx=64, lx=2.0, radius=1.0)
    film = dict(contact_modulus=5.0, poisson=0.3, substrate_contact_modulus=1.0, substrate_poisson=0.45,
                high_frequency_modulus=10.0, relaxation_time=1.0, part="substrate")
    run = dict(force=0.005, velocity=0.1, interaction="hardwall", tolerance=1e-10)
    r = gfmd.solve(top, gfmd.ViscoelasticBody(thickness=0.05, **film), **run).summary
    assert r["converged"] and r["hysteresis_friction"] > 1e-3 and r["hysteresis_balance_error"] < 1e-9
    hidden = gfmd.solve(top, gfmd.ViscoelasticBody(thickness=15.0, **film), **run).summary
    assert abs(hidden["hysteresis_friction"]) < 1e-12
    with pytest.raises(gfmd.InputError, match="viscoelastic_part"):
        gfmd.solve(top, gfmd.ViscoelasticBody(poisson=0.3, high_frequency_modulus=10.0, relaxation_time=1.0,
                                              part="substrate"), **run)


def test_a_viscoelastic_interlayer():
    # part="layers[0]": a viscoelastic interlayer (E0* = 1, h = 0.05 R) under an elastic film
    # (E* = 5, h = 0.01 R) on an elastic substrate: the hysteresis is the interlayer's.
    top = gfmd.Topography.hertz(nx=64, lx=2.0, radius=1.0)
    body = gfmd.ViscoelasticBody(contact_modulus=5.0, poisson=0.3, thickness=0.01, layers=((1.0, 0.3, 0.05),),
                                 substrate_contact_modulus=2.0, substrate_poisson=0.25,
                                 high_frequency_modulus=10.0, relaxation_time=1.0, part="layers[0]")
    r = gfmd.solve(top, body, force=0.005, velocity=0.1, interaction="hardwall", tolerance=1e-10).summary
    assert r["converged"] and r["hysteresis_friction"] > 1e-3 and r["hysteresis_balance_error"] < 1e-9


def test_two_viscoelastic_parts_of_different_models():
    # parts=: an elastic film (E* = 5, h = 0.01 R) over a standard-linear-solid interlayer
    # (E0* = 1, tau = 1) on a substrate of another relaxation (E0* = 0.5, E_inf* = 5, tau = 30):
    # the case file's elastic.viscoelastic_parts, the same numbers; the substrate's relaxation
    # changes the hysteresis, which balances; a part's bad key is named.
    top = gfmd.Topography.hertz(nx=64, lx=2.0, radius=1.0)
    stack = dict(contact_modulus=5.0, poisson=0.3, thickness=0.01, layers=((1.0, 0.3, 0.05),),
                 substrate_contact_modulus=0.5, substrate_poisson=0.45)
    layer = dict(high_frequency_modulus=10.0, relaxation_time=1.0, part="layers[0]")
    substrate = gfmd.ViscoelasticPart("substrate", high_frequency_modulus=5.0, relaxation_time=30.0)
    run = dict(force=0.005, velocity=0.1, interaction="hardwall", tolerance=1e-10)
    both = gfmd.solve(top, gfmd.ViscoelasticBody(parts=(substrate,), **stack, **layer), **run).summary
    assert both["converged"] and both["hysteresis_balance_error"] < 1e-9
    assert both["input"]["elastic"]["viscoelastic_parts"] == [
        {"viscoelastic": "sls", "viscoelastic_part": "substrate", "high_frequency_modulus": 5.0, "relaxation_time": 30.0}]
    alone = gfmd.solve(top, gfmd.ViscoelasticBody(**stack, **layer), **run).summary
    assert alone["hysteresis_friction"] > 1e-4
    assert abs(both["hysteresis_friction"] / alone["hysteresis_friction"] - 1) > 1e-2  # the substrate's share
    toml = f"""
[grid]
nx = 64
lx = 2.0
[elastic]
contact_modulus = 5.0
poisson = 0.3
thickness = 0.01
layers = [{{contact_modulus = 1.0, poisson = 0.3, thickness = 0.05}}]
substrate_contact_modulus = 0.5
substrate_poisson = 0.45
viscoelastic = "sls"
viscoelastic_part = "layers[0]"
high_frequency_modulus = 10.0
relaxation_time = 1.0
[[elastic.viscoelastic_parts]]
viscoelastic = "sls"
viscoelastic_part = "substrate"
high_frequency_modulus = 5.0
relaxation_time = 30.0
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.005
[interaction]
model = "hardwall"
[friction]
velocity = 0.1
[solver]
tolerance = 1e-10
"""
    from_file = gfmd.run_toml(toml)["summary"]
    assert from_file["hysteresis_friction"] == pytest.approx(both["hysteresis_friction"], rel=1e-12)
    bad = gfmd.ViscoelasticPart("substrate", high_frequency_modulus=0.1, relaxation_time=30.0)
    with pytest.raises(gfmd.InputError, match=r"viscoelastic_parts\[0\]\.high_frequency_modulus"):
        gfmd.solve(top, gfmd.ViscoelasticBody(parts=(bad,), **stack, **layer), **run)
    with pytest.raises(gfmd.InputError, match="ViscoelasticPart: give"):
        gfmd.ViscoelasticPart("substrate")
    with pytest.raises(gfmd.InputError, match=r"parts\[0\]"):
        gfmd.ViscoelasticBody(parts=("substrate",), **stack, **layer)


def test_the_normal_solver_is_a_keyword_and_both_give_one_solution():
    # solver.viscoelastic_method from Python: the active set and the splitting solve the same
    # problem (a glassy modulus 1000 E0 near the loss peak, hard wall) to the tolerance; the active
    # set in fewer FFT pairs (its `iterations`) than the splitting's CG iterations; a bad name is
    # refused with the key.
    t = gfmd.Topography.hertz(nx=64, lx=4.0, radius=1.0)
    body = gfmd.ViscoelasticBody(poisson=0.5, high_frequency_modulus=1000.0, relaxation_time=1.0)
    r = {m: gfmd.solve(t, body, force=0.01, velocity=3e-3, interaction="hardwall", viscoelastic_method=m)
         for m in ("splitting", "active_set", "auto")}
    assert r["active_set"].summary["hysteresis_friction"] == pytest.approx(
        r["splitting"].summary["hysteresis_friction"], rel=1e-7)
    assert r["active_set"].summary["iterations"] < r["splitting"].summary["iterations"]
    assert r["auto"].summary["hysteresis_friction"] == r["active_set"].summary["hysteresis_friction"]
    with pytest.raises(gfmd.InputError, match="viscoelastic_method"):
        gfmd.solve(t, body, force=0.01, velocity=3e-3, viscoelastic_method="gmres")
