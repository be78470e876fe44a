"""Hunter's problem (a rigid cylinder rolling frictionless over a standard-linear-solid
half-space, J. Appl. Mech. 28:611, 1961): gfmd's spectral, periodic solve against an independent
real-space solution of the same steady integral equation (scripts/hunter_reference.py), whose
own limits are Hertz's line contacts at E0 and E_inf."""
import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
from hunter_reference import gfmd_cylinder, hunter_reference  # noqa: E402

R, E0, EINF, TAU, A0 = 1.0, 1.0, 10.0, 1.0, 0.05
FORCE = math.pi * A0 ** 2 * E0 / (4 * R)  # a relaxed half-width of A0


def test_the_reference_has_hertz_line_contacts_at_both_ends():
    # Johnson, Contact Mechanics eq. (4.45): b = sqrt(4 F R / (pi E*)); centred, so no resistance.
    h = A0 / 100
    for v, e in ((1e-9, E0), (1e6, EINF)):
        r = hunter_reference(FORCE, R, E0, EINF, TAU, v, h, window=3 * A0)
        b = math.sqrt(4 * FORCE * R / (math.pi * e))
        assert r["leading"] == pytest.approx(b, abs=1.01 * h)
        assert r["trailing"] == pytest.approx(-b, abs=1.01 * h)
        assert abs(r["mu"]) < 1e-3 * b / R
    # In between the contact shifts forward and resists: mu > 0, the centroid ahead.
    mid = hunter_reference(FORCE, R, E0, EINF, TAU, 0.005, h, window=3 * A0)
    assert mid["mu"] > 0.02 and mid["leading"] > -mid["trailing"]


@pytest.mark.parametrize("velocity", [0.005, 0.02])  # V tau_c / a0 = 1 (the peak) and 4
def test_gfmd_converges_to_hunters_cylinder(velocity):
    # On a cell of 8 R (2 pi V tau_c / L <= 0.16: its longest mode nearly relaxed, as the
    # half-space's far field is) at a0/dx = 51 and 102: within 2 %, the error halving.
    ref = hunter_reference(FORCE, R, E0, EINF, TAU, velocity, A0 / 100, window=3 * A0)
    errors = [gfmd_cylinder(FORCE, R, E0, EINF, TAU, velocity, nx, 8.0)["mu"] / ref["mu"] - 1
              for nx in (8192, 16384)]
    assert abs(errors[1]) < 0.02
    assert abs(errors[1]) < 0.65 * abs(errors[0])
