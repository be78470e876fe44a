"""Plausibility (issue 41) through the Python package: masked arrays, the steep-surface warning,
the pressure limit under approach control, the generators' memory check, x, y, z text maps."""
import resource
import warnings

import numpy as np
import pytest

import gfmd


def _smooth(n=16, amplitude=1.0):
    x = np.arange(n) / n
    return amplitude * np.cos(2 * np.pi * x)[None, :] * np.cos(2 * np.pi * x)[:, None]


def test_masked_points_are_missing_points():
    h = _smooth()
    mask = np.zeros(h.shape, bool)
    mask[2, 3] = mask[5, 1] = True
    with pytest.raises(gfmd.InputError, match=r"heights: holds 2 missing points \(masked or NaN: non-finite\), "
                                              r"the first at \(iy, ix\) = \(2, 3\)"):
        gfmd.Topography.from_array(np.ma.masked_array(h, mask), lx=1.0)
    # NaN holes read the same way; a mask with nothing masked is the plain array.
    with pytest.raises(gfmd.InputError, match=r"holds 1 missing point \(NaN: non-finite\), the first at \(iy, ix\) = \(5, 1\)"):
        gfmd.Topography.from_array(np.where(mask & (np.arange(16)[None, :] == 1), np.nan, h), lx=1.0)
    t = gfmd.Topography.from_array(np.ma.masked_array(h, np.zeros_like(mask)), lx=1.0)
    assert np.array_equal(t.heights, h)
    # An integer masked array too.
    with pytest.raises(gfmd.InputError, match="masked"):
        gfmd.Topography.from_array(np.ma.masked_array(np.arange(16).reshape(4, 4), np.eye(4, dtype=bool)), lx=1.0)


def test_steep_surfaces_warn_naming_what_to_check():
    # rms gradient of A cos(2 pi x) cos(2 pi y) on a unit cell: 2 pi A / sqrt 2 = 4.44 A.
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # below the limit: silent
        gfmd.Topography.from_array(_smooth(amplitude=1.0), lx=1.0)
        gfmd.Topography.hertz(nx=32, lx=4.0, radius=1.0)
    with pytest.warns(UserWarning, match=r"array topography: rms gradient 8\.89, above 5 .*check the heights "
                                         r"against lx, ly"):
        gfmd.Topography.from_array(_smooth(amplitude=2.0), lx=1.0)
    with pytest.warns(UserWarning, match=r"selfaffine topography: rms gradient .*check rms_height against lx"):
        gfmd.Topography.self_affine(nx=64, lx=1.0, lambda_short=1 / 16, rms_height=0.5, seed=1)
    with pytest.warns(UserWarning, match=r"hertz topography: rms gradient .*radius against lx"):
        gfmd.Topography.hertz(nx=32, lx=4.0, radius=0.05)


def test_solve_warns_once_and_records_the_warning():
    with pytest.warns(UserWarning) as record:
        t = gfmd.Topography.hertz(nx=64, lx=4.0, radius=0.05)
        r = gfmd.solve(t, force=0.1)
    mine = [str(w.message) for w in record if issubclass(w.category, UserWarning)]
    assert len(mine) == 1, mine  # the topography's; solve does not repeat it
    assert len(r.summary["warnings"]) == 1 and "rms gradient is 33.1" in r.summary["warnings"][0]
    r = gfmd.solve(gfmd.Topography.hertz(nx=32, lx=4.0, radius=1.0), force=0.01)
    assert r.summary["warnings"] == []


def test_approach_beyond_the_pressure_limit_is_refused():
    t = gfmd.Topography.hertz(nx=32, lx=4.0, radius=1.0)
    with pytest.raises(gfmd.SolveError, match=r"approach = 1e\+06 reached a mean pressure of .* E\*, above the "
                                              r"limit of 1000 E\*"):
        gfmd.solve(t, approach=1e6)
    assert gfmd.solve(t, approach=0.01).summary["converged"]


def test_generators_check_memory_before_allocating():
    soft, hard = resource.getrlimit(resource.RLIMIT_DATA)
    limit = 8 << 30  # bytes: below what a 65536^2 map needs (34 GB of heights)
    if hard != resource.RLIM_INFINITY and hard < limit:
        limit = hard
    resource.setrlimit(resource.RLIMIT_DATA, (limit, hard))
    try:
        with pytest.raises(MemoryError, match=r"nx, ny: a 65536 x 65536 Hertz topography .* needs about 68\.7 GB, "
                                              r"more than the .* GB allowed here \(80% of RLIMIT_DATA"):
            gfmd.Topography.hertz(nx=65536, lx=1.0, radius=1.0)
        with pytest.raises(MemoryError, match=r"a 65536 x 32768 self-affine topography .* needs about 85\.9 GB"):
            gfmd.Topography.self_affine(nx=65536, ny=32768, lx=1.0, rms_height=0.01)
        with pytest.raises(MemoryError, match=r"a 65536 x 65536 egg-crate topography"):
            gfmd.Topography.eggcrate(nx=65536, lx=1.0)
    finally:
        resource.setrlimit(resource.RLIMIT_DATA, (soft, hard))


def test_xyz_points_read_as_a_map(tmp_path):
    rows = [(0.25 * ix, 0.5 * iy, 0.01 * (ix + 10 * iy)) for iy in range(4) for ix in range(8)]
    p = tmp_path / "points.csv"
    p.write_text("x,y,z\n" + "".join(f"{x},{y},{z}\n" for x, y, z in reversed(rows)))
    t = gfmd.Topography.read(str(p))
    assert t.shape == (4, 8) and t.lx == 2.0 and t.ly == 2.0
    assert t.heights[3, 5] == pytest.approx(0.35, abs=1e-15) and t.heights[0, 7] == pytest.approx(0.07, abs=1e-15)
