"""Two deformable bodies from Python: gfmd.solve(..., indenter_body=gfmd.ElasticBody(...))."""
import math

import pytest

import gfmd


def sphere(nx=64):
    return gfmd.Topography.hertz(nx=nx, lx=2.0, radius=1.0)


def test_an_elastic_indenter_of_the_bodys_material_halves_the_contact_modulus():
    # Frictionless Hertz: two equal half-spaces press as one of E*/2 (contact radius 2^(1/3) times
    # the rigid one's, within the grid's resolution), and both bodies carry the same surface stress.
    rigid = gfmd.solve(sphere(), gfmd.ElasticBody(), force=0.01, interaction="hardwall")
    pair = gfmd.solve(sphere(), gfmd.ElasticBody(), force=0.01, interaction="hardwall",
                      indenter_body=gfmd.ElasticBody())
    ratio = math.sqrt(pair.summary["relative_contact_area"] / rigid.summary["relative_contact_area"])
    assert ratio == pytest.approx(2 ** (1 / 3), rel=0.05)
    ind = pair.summary["indenter_stress"]
    assert ind["max_von_mises"] == pytest.approx(pair.summary["max_von_mises"], rel=1e-9)
    assert "indenter_stress" not in rigid.summary
    assert pair.summary["input"]["indenter"]["contact_modulus"] == 1.0


def test_sliding_under_an_elastic_indenter_balances_its_work():
    r = gfmd.solve(sphere(), gfmd.ElasticBody(poisson=0.25), force=0.01, friction=0.5,
                   indenter_body=gfmd.ElasticBody(contact_modulus=2.0, poisson=0.4, thickness=0.5))
    s = r.summary
    assert s["converged"]
    assert s["friction_coefficient"] < 0.5  # the body's compressed surface passes the contact
    assert s["energy_balance_error_exact"] < 1e-3


def test_bad_indenter_bodies_are_named():
    with pytest.raises(gfmd.InputError, match="indenter_body: must be a gfmd.ElasticBody"):
        gfmd.solve(sphere(), force=0.01, indenter_body=gfmd.ViscoelasticBody(high_frequency_modulus=10.0,
                                                                             relaxation_time=1.0))
    with pytest.raises(gfmd.InputError, match="indenter_body.coupling"):
        gfmd.solve(sphere(), force=0.01, indenter_body=gfmd.ElasticBody(coupling=False))


def test_a_coated_indenter_mirrors_the_coated_body():
    # Frictionless, only the sum of the normal compliances matters: a coated indenter on a
    # half-space presses as that half-space indenting the coated body (to the solve's tolerance).
    coat = gfmd.ElasticBody(contact_modulus=3.0, poisson=0.3, thickness=0.1, substrate_contact_modulus=0.5,
                            substrate_poisson=0.2)
    half = gfmd.ElasticBody(contact_modulus=2.0, poisson=0.3)
    a = gfmd.solve(sphere(), half, force=0.01, interaction="hardwall", indenter_body=coat, tolerance=1e-10)
    b = gfmd.solve(sphere(), coat, force=0.01, interaction="hardwall", indenter_body=half, tolerance=1e-10)
    assert a.summary["max_pressure"] == pytest.approx(b.summary["max_pressure"], rel=1e-8)
    assert a.summary["relative_contact_area"] == b.summary["relative_contact_area"]
    assert a.summary["input"]["indenter"]["substrate_contact_modulus"] == 0.5
    rigid_base = gfmd.solve(sphere(), half, force=0.01, interaction="hardwall", tolerance=1e-10,
                            indenter_body=gfmd.ElasticBody(contact_modulus=3.0, poisson=0.3, thickness=0.1))
    assert rigid_base.summary["max_pressure"] > 1.05 * a.summary["max_pressure"]


def test_two_bodies_roll():
    # Tractive rolling of a sphere of the body's material: quasi-identical bodies, most of the
    # contact sticks and the creep force follows the creepage (twice the creepage, twice the force
    # in Kalker's linear range).
    one = gfmd.solve(sphere(), gfmd.ElasticBody(poisson=0.5), force=0.005, friction=0.3, creepage=1e-4,
                     indenter_body=gfmd.ElasticBody(poisson=0.5), reference=False)
    two = gfmd.solve(sphere(), gfmd.ElasticBody(poisson=0.5), force=0.005, friction=0.3, creepage=2e-4,
                     indenter_body=gfmd.ElasticBody(poisson=0.5), reference=False)
    assert one.summary["stick_fraction"] > 0.9
    assert two.summary["tangential_force_x"] / one.summary["tangential_force_x"] == pytest.approx(2.0, rel=0.02)
