"""gfmd.ContactSolver and gfmd.load_path: a problem set up once and solved load after load,
each solve warm-started from the previous solution; gfmd.indenter_types and
Topography.indenter / flatpunch (the indenter registry seen from Python)."""
import math
import re

import numpy as np
import pytest

import gfmd
from visco_tables import write_sls_master_curve


def rough():
    return gfmd.Topography.self_affine(64, 1.0, hurst=0.8, lambda_short=1 / 16, rms_gradient=0.1, seed=3)


LOADS = [0.002, 0.004, 0.006, 0.008, 0.01, 0.012, 0.014, 0.016, 0.018, 0.02]


def test_load_path_warm_starts_and_matches_cold_solves():
    top, body = rough(), gfmd.ElasticBody(poisson=0.3)
    solver = gfmd.ContactSolver(top, body, tolerance=1e-10)
    warm = list(gfmd.load_path(solver, pressures=LOADS))
    assert len(warm) == len(LOADS)
    cold = [gfmd.solve(top, body, pressure=p, tolerance=1e-10) for p in LOADS]
    for p, w, c in zip(LOADS, warm, cold):
        assert w.summary["mean_pressure"] == pytest.approx(p, rel=1e-12)
        # Both converged to the same solution of a convex problem: equal within the tolerance.
        assert w.summary["relative_contact_area"] == pytest.approx(c.summary["relative_contact_area"], abs=2e-3)
        assert w.summary["mean_gap"] == pytest.approx(c.summary["mean_gap"], rel=1e-6)
        assert np.max(np.abs(w.pressure - c.pressure)) < 1e-6 * np.max(c.pressure)
    # The first load starts from nothing, as gfmd.solve does: the same iterations, the same bits.
    assert warm[0].summary["iterations"] == cold[0].summary["iterations"]
    assert np.array_equal(warm[0].pressure, cold[0].pressure)
    # Every later load starts from the previous solution: fewer CG iterations in all (frictionless
    # Polonsky-Keer gains little from a warm start, here about 8 %; see the benchmark).
    w_its = sum(r.summary["iterations"] for r in warm[1:])
    c_its = sum(r.summary["iterations"] for r in cold[1:])
    assert w_its < c_its, (w_its, c_its)


def test_a_solve_repeated_warm_is_nearly_free_and_warm_false_starts_cold():
    top = rough()
    solver = gfmd.ContactSolver(top, friction=0.3, tolerance=1e-9)
    first = solver.solve(pressure=0.01)
    again = solver.solve(pressure=0.01)
    assert again.summary["iterations"] < first.summary["iterations"] / 3, (
        again.summary["iterations"], first.summary["iterations"])
    assert again.summary["friction_coefficient"] == pytest.approx(first.summary["friction_coefficient"], rel=1e-6)
    cold = solver.solve(pressure=0.01, warm=False)
    assert cold.summary["iterations"] == first.summary["iterations"]
    assert np.array_equal(cold.pressure, first.pressure)
    solver.reset()
    assert solver.last is None and "cold" in repr(solver)
    assert np.array_equal(solver.solve(pressure=0.01).pressure, first.pressure)
    # Results stay valid after later solves (each owns its fields).
    assert np.array_equal(first.pressure, cold.pressure)


def test_contact_solver_checks_its_arguments_once_and_each_load():
    top = rough()
    with pytest.raises(gfmd.InputError, match="frobnicate"):
        gfmd.ContactSolver(top, frobnicate=1)
    with pytest.raises(gfmd.InputError, match="interaction"):
        gfmd.ContactSolver(top, interaction="glue")
    solver = gfmd.ContactSolver(top)
    for kw, what in [(dict(), "exactly one"), (dict(pressure=0.1, force=0.1), "exactly one"),
                     (dict(pressure=-0.1), "load.pressure: must be positive"),
                     (dict(pressure=float("nan")), "load.pressure: must be a finite number"),
                     (dict(pressure=5e3), "load.pressure: exceeds 1000 E"),
                     (dict(approach=-1.0), "load.approach"), (dict(force="big"), "load.force: must be a number")]:
        with pytest.raises(gfmd.InputError, match=what):
            solver.solve(**kw)
    assert solver.last is None  # nothing was solved
    with pytest.raises(gfmd.InputError, match="exactly one of pressures"):
        next(gfmd.load_path(solver, pressures=[0.01], forces=[0.01]))
    with pytest.raises(gfmd.InputError, match="ContactSolver"):
        next(gfmd.load_path("solver", pressures=[0.01]))
    # The loads are a list: a string was walked character by character, a number gave a TypeError.
    for loads in ("0.01", 0.01):
        with pytest.raises(gfmd.InputError, match=r"approaches: a list of numbers"):
            next(gfmd.load_path(solver, approaches=loads))
    # The adhesive model by name lacks its keys: the message names the object that carries them.
    with pytest.raises(gfmd.InputError, match=r"work_of_adhesion, range.*gfmd.Adhesive"):
        gfmd.ContactSolver(top, interaction="adhesive")


def test_indenter_types_come_from_the_registry():
    types = {t["name"]: t for t in gfmd.indenter_types()}
    assert {"hertz", "flatpunch", "eggcrate", "selfaffine", "file"} <= set(types)
    assert "array" not in types
    assert types["flatpunch"]["keys"] == ["radius", "depth"] and types["flatpunch"]["purpose"]
    # Topography.indenter reads the keys as a case file's [indenter] is read.
    h = gfmd.Topography.indenter("hertz", 64, 2.0, radius=1.5)
    assert np.array_equal(h.heights, gfmd.Topography.hertz(64, 2.0, radius=1.5).heights)
    with pytest.raises(gfmd.InputError, match="did you mean 'radius'"):
        gfmd.Topography.indenter("hertz", 64, 2.0, radiu=1.0)
    with pytest.raises(gfmd.InputError, match="unknown indenter type \"cone\".*one of hertz, flatpunch"):
        gfmd.Topography.indenter("cone", 64, 2.0)
    with pytest.raises(gfmd.InputError, match="indenter.radius: must be a finite"):
        gfmd.Topography.flatpunch(64, 2.0, radius=math.inf)


def test_flat_punch_from_python_presses_its_face():
    t = gfmd.Topography.flatpunch(128, 8.0, radius=0.5, depth=0.2)
    assert t.kind == "flatpunch" and t.heights.max() == 0.0 and t.heights.min() == -0.2
    face = t.heights == 0.0
    assert face.sum() * (8.0 / 128) ** 2 == pytest.approx(math.pi * 0.25, rel=0.03)
    r = gfmd.solve(t, force=0.01, interaction="hardwall", tolerance=1e-10)
    assert np.all(r.pressure[~face] == 0.0) and np.all(r.pressure[face] > 0.0)
    # Boussinesq's stiffness 2 a E* within the periodic cell's correction (c F / (E* L), below 20 %)
    # and the staircase edge: tested to 1 % after extrapolation in tests/test_indenters.cpp.
    assert r.summary["approach"] == pytest.approx(0.01 / (2 * 0.5), rel=0.2)
    with pytest.raises(gfmd.InputError, match="indenter.radius: the punch radius .* fewer than 2 grid"):
        gfmd.Topography.flatpunch(128, 8.0, radius=0.1)


def test_interaction_models_from_python():
    models = {m["name"]: m for m in gfmd.interaction_models()}
    assert list(models) == ["harmonic", "hardwall", "adhesive"]
    assert models["adhesive"]["keys"] == ["work_of_adhesion", "range", "repulsion"]
    assert models["adhesive"]["repulsion_key"] and models["adhesive"]["on_device"]
    t = gfmd.Topography.hertz(64, 1.6, radius=1.0)
    for name in ("harmonic", "hardwall"):
        assert models[name]["keys"] == [] and models[name]["on_device"]
        assert gfmd.solve(t, force=0.01, interaction=name).summary["converged"]
    with pytest.raises(gfmd.InputError, match="interaction.model: unknown model \"hardwal\" .*one of harmonic, "
                                              "hardwall, adhesive"):
        gfmd.solve(t, force=0.01, interaction="hardwal")
    with pytest.raises(gfmd.InputError, match="Adhesive.repulsion: one of harmonic, hardwall"):
        gfmd.Adhesive(1e-3, 0.01, repulsion="adhesive")


def test_friction_laws_from_python():
    laws = {law["name"]: law for law in gfmd.friction_laws()}
    assert laws["coulomb"]["set_valued_stick"] and laws["coulomb"]["keys"] == []
    assert laws["velocity"]["keys"] == ["static_coefficient", "velocity_scale"]
    assert laws["tresca"]["keys"] == ["shear_strength"] and laws["tresca"]["set_valued_stick"]
    assert laws["rate"]["keys"] == ["rate_coefficient", "velocity_scale"] and laws["rate"]["set_valued_stick"]
    assert laws["velocity"]["set_valued_stick"] and all(law["on_device"] for law in laws.values())
    t = gfmd.Topography.hertz(64, 1.6, radius=1.0)
    base = dict(force=0.01, friction=0.4, regularization=0.01, tolerance=1e-10)
    c = gfmd.solve(t, **base)
    same = gfmd.solve(t, **base, law="velocity", static_coefficient=0.4, velocity_scale=0.1)
    assert np.array_equal(c.pressure, same.pressure) and np.array_equal(c["traction_x"], same["traction_x"])
    v = gfmd.solve(t, **base, law="velocity", static_coefficient=0.8, velocity_scale=0.5)
    assert v.summary["friction_law"] == "velocity" and "exp(-|v|/v_c)" in v.summary["friction_law_traction"]
    assert 0.4 < v.summary["friction_coefficient"] < 0.8
    capped = gfmd.solve(t, **base, law="tresca", shear_strength=0.005)
    assert capped.summary["friction_law"] == "tresca" and capped.summary["friction_coefficient"] < 0.4
    assert np.max(np.hypot(capped["traction_x"], capped["traction_y"])) <= 0.005 * (1 + 1e-12)
    # The exact law with stick (rolling): stuck points carry up to mu_s p, more than mu_k p.
    rolled = gfmd.solve(t, force=0.01, friction=0.4, creepage=0.002, law="velocity", static_coefficient=0.6,
                        velocity_scale=0.05, tolerance=1e-10)
    assert 0 < rolled.summary["stick_fraction"] < 1
    ratio = np.hypot(rolled["traction_x"], rolled["traction_y"])[rolled.pressure > 0] / rolled.pressure[rolled.pressure > 0]
    assert 0.45 < ratio.max() <= 0.6 * (1 + 1e-12)
    with pytest.raises(gfmd.InputError, match="friction.velocity_scale: must be a positive number"):
        gfmd.solve(t, force=0.01, friction=0.4, law="velocity", static_coefficient=0.8)
    with pytest.raises(gfmd.InputError, match="did you mean 'velocity'"):
        gfmd.solve(t, **base, law="velocty")


def test_hardness_caps_the_pressure_from_python():
    t = gfmd.Topography.hertz(64, 1.6, radius=1.0)
    e = gfmd.solve(t, force=0.01, interaction="hardwall", tolerance=1e-10)
    h = 0.6 * e.summary["max_pressure"]
    r = gfmd.solve(t, force=0.01, interaction="hardwall", hardness=h, tolerance=1e-10)
    assert r.summary["max_pressure"] <= h and r.summary["plastic_area_fraction"] > 0
    assert r["plastic_displacement"].max() == pytest.approx(r.summary["max_plastic_displacement"], rel=1e-12)
    assert r.summary["relative_contact_area"] > e.summary["relative_contact_area"]
    assert "plastic_area_fraction" not in e.summary
    with pytest.raises(gfmd.InputError, match="interaction.hardness: must be positive"):
        gfmd.solve(t, force=0.01, hardness=-1.0)


def test_a_case_reaches_the_solver_as_tables_not_text(tmp_path):
    # The solver gets the case as tables (no TOML text in between): a file whose directory name
    # holds a quote, a backslash, a newline and a TOML line is read as the path it is, and a
    # problem names its key without line numbers of a text the caller never wrote.
    odd = tmp_path / 'a"b\\c\n[solver]\ntolerance = 0.5 #'
    odd.mkdir()
    path = write_sls_master_curve(odd / "sls.csv", rows_per_decade=10)
    top = gfmd.Topography.hertz(32, 1.0, 1.0)
    body = gfmd.ViscoelasticBody(poisson=0.5, master_curve=str(path))
    s = gfmd.solve(top, body, force=0.01, velocity=0.02, tolerance=1e-8).summary
    assert s["converged"]
    assert s["input"]["elastic"]["master_curve"] == str(path)
    assert s["input"]["solver"]["tolerance"] == 1e-8
    # A contact_modulus other than the table's first E' is refused (it was replaced without a word).
    with pytest.raises(gfmd.InputError, match="contact_modulus: is set by the master curve"):
        gfmd.ViscoelasticBody(contact_modulus=2.0, poisson=0.5, master_curve=str(path))
    with pytest.raises(gfmd.InputError) as e:
        gfmd.solve(top, approach=0.01, tolerance=-1.0)
    assert "solver.tolerance" in str(e.value) and "gfmd.solve" in str(e.value)
    assert not re.search(r":\d+\]", str(e.value))
    with pytest.raises(gfmd.InputError, match="tolerance: must not be NaN"):
        gfmd.ContactSolver(top, tolerance=math.nan)


def test_body_kinds_from_python():
    # The registry of body kinds (elastic/body.hpp), as the friction laws' and interactions' are.
    kinds = {b["name"]: b for b in gfmd.body_types()}
    assert {"homogeneous", "layered"} <= set(kinds)
    assert all(b["purpose"] for b in kinds.values())
    assert len(kinds) == len(gfmd.body_types())
    # Each kind's own keys, which gfmd.ElasticBody takes by the same names.
    assert kinds["homogeneous"]["keys"] == []
    assert kinds["layered"]["keys"] == ["substrate_contact_modulus", "substrate_poisson", "layers"]
    # gfmd.ElasticBody takes every registered key (a new kind's key must reach Python too).
    import dataclasses
    fields = {f.name for f in dataclasses.fields(gfmd.ElasticBody)}
    assert {k for b in kinds.values() for k in b["keys"]} <= fields, fields
    body = gfmd.ElasticBody(thickness=0.1, substrate_contact_modulus=5.0, substrate_poisson=0.3,
                            layers=[(2.0, 0.3, 0.05)])
    r = gfmd.solve(gfmd.Topography.hertz(64, 4.0, radius=1.0), body, force=0.01)
    assert r.summary["input"]["elastic"]["substrate_poisson"] == 0.3
    import tomllib
    # Result.toml is TOML (a layer as an inline table) and reads back to the same body.
    assert tomllib.loads(r.toml)["elastic"]["layers"] == [{"contact_modulus": 2.0, "poisson": 0.3, "thickness": 0.05}]


def test_indenter_keys_reach_the_reader_as_values():
    # Topography.indenter's keys go to the case file's [indenter] reader as values (the JSON to
    # TOML conversion the tables of gfmd.solve use): each problem names its key.
    for value, why in ((math.nan, "finite"), (math.inf, "finite"), (None, "unsupported"), ({"a": 1}, "table")):
        with pytest.raises(gfmd.InputError, match=f"indenter.radius.*{why}"):
            gfmd.Topography.indenter("hertz", 32, 1.0, radius=value)
    assert gfmd.Topography.indenter("hertz", 32, 1.0, radius=2).nx == 32  # an int is a number
