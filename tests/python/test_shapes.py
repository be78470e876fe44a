"""The indenter shapes as parts from Python: gfmd.indenter_types() lists them, and
gfmd.Topography.indenter(...) reads their keys as a case file's [indenter] is read."""
import numpy as np
import pytest

import gfmd


def test_the_new_shapes_are_registered_and_made():
    names = {t["name"] for t in gfmd.indenter_types()}
    assert {"powerlaw", "sphere", "cylinder"} <= names
    p = gfmd.Topography.indenter("powerlaw", 64, 2.0, radius=1.0, exponent=2.0)
    h = gfmd.Topography.hertz(nx=64, lx=2.0, radius=1.0)
    assert np.allclose(p.heights, h.heights, rtol=0, atol=1e-14)
    s = gfmd.Topography.indenter("sphere", 64, 2.0, radius=1.0)
    assert s.heights.max() == 0.0 and s.heights.min() == pytest.approx(-1.0)
    c = gfmd.Topography.indenter("cylinder", 64, 2.0, radius=1.0, axis="x")
    assert np.all(c.heights == c.heights[:, :1])  # constant along x
    with pytest.raises(gfmd.InputError, match="indenter.exponent"):
        gfmd.Topography.indenter("powerlaw", 64, 2.0, radius=1.0, exponent=0.2)
