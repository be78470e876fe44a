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


def test_a_step_from_python():
    # The raised strip: 2 m + 1 nodes at height 0 about the centre column, the rest depth below.
    t = gfmd.Topography.indenter("step", 64, 1.0, width=0.25, depth=0.05)
    assert np.count_nonzero(t.heights[0] == 0.0) == 17 and t.heights.min() == pytest.approx(-0.05)
    assert np.all(t.heights == t.heights[:1, :])  # the strip lies along y
    r = gfmd.solve(t, pressure=0.01, interaction="hardwall")
    assert r.summary["relative_contact_area"] == pytest.approx(17 / 64, abs=1e-12)
    with pytest.raises(gfmd.InputError, match="indenter.width"):
        gfmd.Topography.indenter("step", 64, 1.0, width=0.01)


def test_an_anisotropic_surface_from_python():
    iso = gfmd.Topography.self_affine(128, 1.0, lambda_long=0.25, lambda_short=0.05, rms_height=0.01, seed=1)
    same = gfmd.Topography.self_affine(128, 1.0, lambda_long=0.25, lambda_short=0.05, rms_height=0.01, seed=1,
                                       peklenik=1.0)
    assert np.array_equal(iso.heights, same.heights)
    ani = gfmd.Topography.self_affine(128, 1.0, lambda_long=0.25, lambda_short=0.05, rms_height=0.01, seed=1,
                                      peklenik=4.0)
    gx = np.diff(ani.heights, axis=1).std()
    gy = np.diff(ani.heights, axis=0).std()
    assert gx < 0.5 * gy  # stretched along x: flatter along x
    with pytest.raises(gfmd.InputError, match="peklenik"):
        gfmd.Topography.self_affine(128, 1.0, lambda_long=0.25, lambda_short=0.05, rms_height=0.01, peklenik=0.0)
