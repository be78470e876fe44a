"""A coating bonded to an elastic substrate (gfmd.ElasticBody(substrate_contact_modulus=...)): a
sphere's contact radius against the exact axisymmetric solution for a coated half-space, computed
by an independent method (scripts/coated_hertz_reference.py: Perriot & Barthel's integral
equation with the bonded layer's kernel)."""
import math
import os
import sys

import pytest

import gfmd

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
from coated_hertz_reference import sphere_on_coating  # noqa: E402

R, T, NU = 1.0, 0.04, 0.3  # sphere radius, coating thickness, both Poisson ratios
NX, LX = 256, 1.0


def reference_load(a, ratio):
    """The exact solution's load at contact radius a (E1* = 1; the script's lengths are in t)."""
    return sphere_on_coating(a / T, ratio, NU, NU)[1] * a ** 3 / R


def reference_radius(force, ratio):
    """The contact radius a of the exact solution at this force: secant steps on ln P(ln a)."""
    x0, x1 = math.log(T), math.log(2 * T)
    f0, f1 = (math.log(reference_load(math.exp(x), ratio) / force) for x in (x0, x1))
    for _ in range(30):
        if abs(f1) < 1e-12:
            break
        x0, x1 = x1, x1 - f1 * (x1 - x0) / (f1 - f0)
        f0, f1 = f1, math.log(reference_load(math.exp(x1), ratio) / force)
    assert abs(f1) < 1e-9
    return math.exp(x1)


@pytest.mark.parametrize("ratio", [0.1, 10.0])
def test_a_sphere_on_a_coating_has_the_exact_contact_radius(ratio):
    # The load of Hertz's a = 1.5 t on the coating's half-space: the substrate carries a large
    # share, so the exact radius is 51 % larger on the soft substrate and 10 % smaller on the
    # stiff one; the grid's radius (about 14-23 cells) is within 1 % of it (measured 0.10 % and
    # 0.27 % at 256^2, 0.07 % and 0.38 % at 512^2; 1.5 % and 0.14 % at 128^2).
    force = 4 * (1.5 * T) ** 3 / (3 * R)  # Hertz's load for a = 1.5 t on the coating's material
    top = gfmd.Topography.hertz(nx=NX, lx=LX, radius=R)
    body = gfmd.ElasticBody(contact_modulus=1.0, poisson=NU, thickness=T, substrate_contact_modulus=ratio,
                            substrate_poisson=NU)
    r = gfmd.solve(top, body, force=force, interaction="hardwall")
    assert r.summary["converged"]
    a = math.sqrt(r.summary["relative_contact_area"] * LX * LX / math.pi)
    exact = reference_radius(force, ratio)
    hertz = 1.5 * T
    assert abs(exact / hertz - 1) > 0.1  # the coating matters here
    assert a == pytest.approx(exact, rel=0.01)


def test_the_reference_is_hertz_for_one_material():
    # The reference method itself: a coating of the substrate's material is Hertz's sphere.
    d, p, p0 = sphere_on_coating(0.7, 1.0, NU, NU)
    assert d == pytest.approx(1.0, rel=1e-12)
    assert p == pytest.approx(4 / 3, rel=1e-12)
    assert p0 == pytest.approx(2 / math.pi, rel=1e-10)


def test_coated_bodies_are_checked_and_written():
    with pytest.raises(gfmd.InputError, match="thickness"):
        gfmd.ElasticBody(substrate_contact_modulus=2.0)
    with pytest.raises(gfmd.InputError, match=r"layers\[0\]"):
        gfmd.ElasticBody(thickness=0.1, layers=((1.0, 0.3),))
    with pytest.raises(gfmd.InputError, match=r"layers\[0\].poisson"):
        gfmd.ElasticBody(thickness=0.1, layers=((1.0, 0.7, 0.1),))
    # Two layers of one material on a rigid base are one layer of their total thickness.
    top = gfmd.Topography.hertz(nx=64, lx=1.0, radius=1.0)
    one = gfmd.solve(top, gfmd.ElasticBody(poisson=0.3, thickness=0.3), force=1e-3)
    two = gfmd.solve(top, gfmd.ElasticBody(poisson=0.3, thickness=0.1, layers=((1.0, 0.3, 0.2),)), force=1e-3)
    assert two.summary["max_pressure"] == pytest.approx(one.summary["max_pressure"], rel=1e-8)
    assert two.summary["input"]["elastic"]["layers"][0]["thickness"] == 0.2
