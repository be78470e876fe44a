"""Measured surfaces: the x3p, .npy and CSV/TSV/text readers on files from the independent
writers in surface_writers.py, and the preparation of a map for a grid (units, crop,
missing points, detrending, periodicity, resampling) through gfmd.Topography.read and a case
file run by the gfmd program. Expected values come from the arrays written (exact for
doubles, the stated quantisation for integers) or from closed forms (a plane is harmonic,
a band-limited cosine is reproduced by Fourier interpolation)."""
import json
import os
import subprocess
import zipfile

import numpy as np
import pytest

import gfmd
from gfmd import _core

from surface_writers import write_npy, write_text, write_x3p, x3p_main_xml

RNG = np.random.default_rng(2025)
GFMD = os.path.join(os.environ.get("GFMD_BUILD_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "build")),
                    "gfmd")


def expect_error(path, *words, fn=None):
    with pytest.raises(gfmd.InputError) as e:
        (fn or _core.read_height_file)(str(path))
    msg = str(e.value)
    assert str(path) in msg, msg
    for w in words:
        assert w in msg, f"{w!r} not in {msg!r}"
    assert len(msg) < 600, msg
    return msg


# ---- x3p ---------------------------------------------------------------------------------

@pytest.mark.parametrize("ztype", ["D", "F", "I", "L"])
def test_x3p_round_trip(tmp_path, ztype):
    h = 1e-6 * RNG.standard_normal((6, 9))
    p = tmp_path / "m.x3p"
    write_x3p(p, h, lx=9 * 2e-6, ly=6 * 3e-6, ztype=ztype, zinc=1e-10 if ztype in "IL" else None)
    r = _core.read_height_file(str(p))
    assert r["format"] == "x3p" and r["unit"] == "m" and r["missing"] == 0
    assert r["h"].shape == (6, 9)
    assert r["lx"] == pytest.approx(18e-6, rel=1e-15) and r["ly"] == pytest.approx(18e-6, rel=1e-15)
    tol = {"D": 0.0, "F": 1e-7 * 4e-6, "I": 0.5e-10 * 1.0001, "L": 0.5e-10 * 1.0001}[ztype]
    assert np.max(np.abs(r["h"] - h)) <= tol


def test_x3p_missing_points_float_int_and_inline(tmp_path):
    h = 1e-6 * RNG.standard_normal((5, 4))
    h[1, 2] = np.nan
    h[4, 0] = np.nan
    for kw in ({"ztype": "D"}, {"ztype": "I", "zinc": 1e-9}, {"ztype": "D", "inline": True}):
        p = tmp_path / "m.x3p"
        write_x3p(p, h, 4e-6, 5e-6, **kw)
        r = _core.read_height_file(str(p))
        assert r["missing"] == 2, kw
        assert np.isnan(r["h"][1, 2]) and np.isnan(r["h"][4, 0])
        assert r["first_missing"] == "point (x, y) = (2, 1)"
        assert np.nanmax(np.abs(r["h"] - h)) <= (0.51e-9 if kw["ztype"] == "I" else 0.0)
    # Refused for a solve unless filled.
    expect_error(p, "2 points have no value", "indenter.missing", fn=lambda s: gfmd.Topography.read(s))


def test_x3p_damaged_files(tmp_path):
    h = 1e-6 * RNG.standard_normal((8, 8))
    good = tmp_path / "good.x3p"
    write_x3p(good, h, 8e-6, 8e-6)
    data = good.read_bytes()
    p = tmp_path / "bad.x3p"
    for n in sorted(set(range(0, 40)) | set(np.linspace(40, len(data) - 1, 40).astype(int))):
        p.write_bytes(data[:n])
        expect_error(p)
    # Not XML, not an x3p root, a profile, no increment, wrong data size, huge dims, 3 layers.
    cases = [
        ("<ISO5436_2><Record1>", "main.xml line"),
        ("<?xml version='1.0'?><other/>", "not <ISO5436_2>"),
        (x3p_main_xml(8, 8, 1e-6, 1e-6, feature="PRF"), "not SUR"),
        (x3p_main_xml(8, 8, 1e-6, None), "no <Increment>"),
        (x3p_main_xml(9, 8, 1e-6, 1e-6), "holds 512 bytes"),
        (x3p_main_xml(60000, 60000, 1e-6, 1e-6), "2 GiB of heights"),
        (x3p_main_xml(16000, 16000, 1e-6, 1e-6), "holds 512 bytes"),
        (x3p_main_xml(70000, 8, 1e-6, 1e-6), "at most 65536 per side"),
        (x3p_main_xml(8, 8, 1e-6, 1e-6, size_z=3), "SizeZ"),
        (x3p_main_xml(8, 8, -1e-6, 1e-6), "must be positive"),
        (x3p_main_xml(8, 8, 1e-6, 1e-6, ztype="Q"), "not one of I, L, F, D"),
        (x3p_main_xml(8, 8, 1e-6, 1e-6).replace("<SizeX>8</SizeX>", "<SizeX>eight</SizeX>"), "'eight'"),
    ]
    for xml, words in cases:
        write_x3p(p, h, 8e-6, 8e-6, main_xml=xml)
        expect_error(p, words)
    # An archive without main.xml; a zip that is no archive of ours.
    with zipfile.ZipFile(p, "w") as z:
        z.writestr("readme.txt", "hello")
    expect_error(p, "no main.xml")
    p.write_bytes(b"PK\x03\x04" + b"\0" * 50)
    expect_error(p, "zip")
    # Infinite heights are not heights.
    hi = h.copy()
    hi[0, 0] = np.inf
    write_x3p(p, hi, 8e-6, 8e-6)
    expect_error(p, "infinite")


# ---- npy ---------------------------------------------------------------------------------

@pytest.mark.parametrize("dtype", ["<f8", ">f8", "<f4", "<i2", ">i4", "|u1", "<i8"])
@pytest.mark.parametrize("fortran", [False, True])
def test_npy_round_trip(tmp_path, dtype, fortran):
    a = np.arange(35, dtype=float).reshape(5, 7) - 10.0
    if dtype.endswith("u1"):
        a = np.abs(a)
    p = tmp_path / "a.npy"
    write_npy(p, a, dtype=dtype, fortran=fortran, version=2 if fortran else 1)
    r = _core.read_height_file(str(p))
    assert r["format"] == "npy" and r["unit"] == "" and r["lx"] == 0.0
    assert np.array_equal(r["h"], a)
    # numpy's own writer agrees with ours.
    np.save(tmp_path / "b.npy", a.astype(np.dtype(dtype)))
    assert np.array_equal(_core.read_height_file(str(tmp_path / "b.npy"))["h"], a)


def test_npy_errors(tmp_path):
    p = tmp_path / "a.npy"
    a = RNG.standard_normal((4, 6))
    write_npy(p, a)
    data = p.read_bytes()
    for n in range(0, len(data) - 1, 7):
        (tmp_path / "t.npy").write_bytes(data[:n])
        expect_error(tmp_path / "t.npy")
    write_npy(p, RNG.standard_normal((2, 3, 4)))
    expect_error(p, "needs 2 dimensions")
    write_npy(p, a, shape=(16000, 16000))
    expect_error(p, "bytes of data follow")
    write_npy(p, a, shape=(60000, 60000))
    expect_error(p, "2 GiB of heights")
    write_npy(p, a, shape=(1 << 20, 6))
    expect_error(p, "at most 65536 per side")
    write_npy(p, a, descr="<c16")
    expect_error(p, "not supported")
    p.write_bytes(b"junk")
    p.rename(tmp_path / "junk.npy")
    expect_error(tmp_path / "junk.npy", "signature")
    a[2, 3] = np.nan
    write_npy(p, a)
    r = _core.read_height_file(str(p))
    assert r["missing"] == 1 and r["first_missing"] == "(iy, ix) = (2, 3)"


# ---- CSV / TSV / text with units ---------------------------------------------------------

@pytest.mark.parametrize("sep", [",", "\t", ";", " "])
def test_text_separators_and_units(tmp_path, sep):
    h = RNG.standard_normal((4, 5))
    p = tmp_path / "m.csv"
    write_text(p, h, sep=sep, lx=10.0, ly=8.0, size_unit="um", unit="nm")
    r = _core.read_height_file(str(p))
    assert r["unit"] == "m"
    assert r["lx"] == pytest.approx(10e-6, rel=1e-15) and r["ly"] == pytest.approx(8e-6, rel=1e-15)
    assert np.allclose(r["h"], h * 1e-9, rtol=1e-15, atol=0)
    # The size in the heights' unit when it names none.
    write_text(p, h, sep=sep, lx=10.0, ly=8.0, unit="µm")
    assert _core.read_height_file(str(p))["lx"] == pytest.approx(10e-6, rel=1e-15)
    # No units anywhere: the numbers as written.
    write_text(p, h, sep=sep, lx=10.0, ly=8.0)
    r = _core.read_height_file(str(p))
    assert r["unit"] == "" and r["lx"] == 10.0 and np.array_equal(r["h"], h)


def test_text_unit_errors(tmp_path):
    h = RNG.standard_normal((3, 3))
    p = tmp_path / "m.txt"
    write_text(p, h, lx=1.0, size_unit="um")
    expect_error(p, "line 1", "the heights have none")
    write_text(p, h, unit="furlong")
    expect_error(p, "unknown length unit 'furlong'")
    write_text(p, h, lx=1.0, size_unit="parsec", unit="nm")
    expect_error(p, "unknown length unit 'parsec'")
    h[1, 1] = np.nan
    write_text(p, h)
    r = _core.read_height_file(str(p))
    assert r["missing"] == 1 and r["first_missing"] == "line 2, value 2"


# ---- preparation for a grid --------------------------------------------------------------

def test_units_into_the_case_unit(tmp_path):
    h = 1e-6 * RNG.standard_normal((8, 8))
    p = tmp_path / "m.x3p"
    write_x3p(p, h, 8e-6, 8e-6)
    t = gfmd.Topography.read(p, case_unit="um")
    assert t.lx == pytest.approx(8.0, rel=1e-14)
    assert np.allclose(t.heights, h * 1e6, rtol=1e-14, atol=0)
    assert t.preprocessing["unit_factor"] == pytest.approx(1e6)
    assert gfmd.Topography.read(p).lx == pytest.approx(8e-6)  # metres by default
    with pytest.raises(gfmd.InputError, match="states its units"):
        gfmd.Topography.read(p, unit="nm")
    q = tmp_path / "m.npy"
    write_npy(q, h * 1e9)
    with pytest.raises(gfmd.InputError, match="states no unit"):
        gfmd.Topography.read(q, lx=8, case_unit="um")
    t = gfmd.Topography.read(q, lx=8, unit="nm", case_unit="um")
    assert np.allclose(t.heights, h * 1e6, rtol=1e-12, atol=0)


def test_plane_removal_and_harmonic_fill_are_exact_on_a_plane(tmp_path):
    ny, nx = 12, 16
    y, x = np.mgrid[0:ny, 0:nx]
    plane = 0.3 + 0.02 * x - 0.05 * y
    rough = 0.1 * np.cos(2 * np.pi * x / nx) * np.cos(2 * np.pi * 2 * y / ny)  # zero mean, no tilt
    h = plane + rough
    p = tmp_path / "m.txt"
    write_text(p, h, lx=float(nx), ly=float(ny))
    t = gfmd.Topography.read(p, detrend="plane")
    assert np.allclose(t.heights, rough, atol=1e-12)
    rep = t.preprocessing["detrend"]
    assert rep["removed_slope_x"] == pytest.approx(0.02, abs=1e-12)
    assert rep["removed_slope_y"] == pytest.approx(-0.05, abs=1e-12)
    # Holes in a plane are filled exactly by the harmonic fill; the mean fill uses the mean.
    hp = plane.copy()
    holes = [(3, 4), (3, 5), (4, 4), (7, 11), (8, 11)]  # interior: the discrete Laplacian of a plane is 0
    for iy, ix in holes:
        hp[iy, ix] = np.nan
    write_text(p, hp, lx=float(nx), ly=float(ny))
    t = gfmd.Topography.read(p, missing="interpolate")
    assert np.allclose(t.heights, plane, atol=1e-9)
    assert t.preprocessing["missing"]["points"] == 5 and t.preprocessing["missing"]["sweeps"] > 0
    t = gfmd.Topography.read(p, missing="mean")
    assert t.heights[3, 4] == pytest.approx(np.nanmean(hp), rel=1e-12)


def test_crop_mirror_pad(tmp_path):
    h = RNG.standard_normal((10, 12))
    p = tmp_path / "m.txt"
    write_text(p, h, lx=12.0, ly=10.0)
    t = gfmd.Topography.read(p, crop=(2, 3, 6, 4))
    assert np.array_equal(t.heights, h[3:7, 2:8]) and t.lx == 6.0 and t.ly == 4.0
    t = gfmd.Topography.read(p, periodize="mirror")
    assert t.shape == (20, 24) and t.lx == 24.0
    m = t.heights
    assert np.array_equal(m[:10, :12], h) and np.array_equal(m[:10, 12:], h[:, ::-1])
    assert np.array_equal(m[10:, :12], h[::-1, :])
    assert t.preprocessing["periodize"]["edge_mismatch"] > 0.5
    t = gfmd.Topography.read(p, periodize="pad")
    assert np.array_equal(t.heights[:10, :12], h)
    assert np.all(t.heights[10:, :] == h.min() - 10 * (h.max() - h.min()))
    assert t.preprocessing["map_area_fraction"] == 0.25
    for kw, word in (({"crop": (8, 0, 6, 4)}, "does not lie inside"), ({"crop": (2 ** 63 - 5, 0, 10, 4)}, "crop"), ({"periodize": "wrap"}, "periodize"),
                     ({"detrend": "quadratic"}, "detrend"), ({"missing": "zero"}, "missing")):
        with pytest.raises(gfmd.InputError, match=word):
            gfmd.Topography.read(p, **kw)


def test_spectral_resampling(tmp_path):
    ny, nx = 32, 32
    y, x = np.mgrid[0:ny, 0:nx] / nx
    f = lambda x, y: np.cos(2 * np.pi * 3 * x + 0.4) + 0.5 * np.sin(2 * np.pi * (2 * x - 5 * y))
    p = tmp_path / "m.txt"
    write_text(p, f(x, y), lx=1.0, ly=1.0)
    t = gfmd.Topography.read(p, nx=48, ny=80)
    yy, xx = np.mgrid[0:80, 0:48]
    assert np.allclose(t.heights, f(xx / 48, yy / 80), atol=1e-12)
    assert t.preprocessing["lost_gradient_fraction"] == 0.0 and t.preprocessing["warnings"] == []
    # A coarser grid drops the short wavelengths, with a warning that quantifies them.
    g = f(x, y) + 0.5 * np.cos(2 * np.pi * 12 * x)
    write_text(p, g, lx=1.0, ly=1.0)
    t = gfmd.Topography.read(p, nx=16, ny=16)
    yy, xx = np.mgrid[0:16, 0:16] / 16
    assert np.allclose(t.heights, f(xx, yy), atol=1e-12)
    lost = (0.5 * 12) ** 2 / ((3 ** 2) + 0.25 * (2 ** 2 + 5 ** 2) + (0.5 * 12) ** 2)
    assert t.preprocessing["lost_gradient_fraction"] == pytest.approx(lost, rel=1e-9)
    assert any("drops the wavelengths" in w for w in t.preprocessing["warnings"])


def test_case_file_runs_a_measured_map(tmp_path):
    """gfmd run on an x3p map: prepared as asked, recorded in summary.json, warnings on stderr;
    a bad option names its key and writes nothing."""
    n = 32
    y, x = np.mgrid[0:n, 0:n] / n
    h = 1e-6 * (np.cos(2 * np.pi * x) + np.cos(2 * np.pi * y)) + 2e-7 * x  # tilted egg-crate, in metres
    h[5, 7] = np.nan
    write_x3p(tmp_path / "map.x3p", h, 100e-6, 100e-6)
    case = tmp_path / "case.toml"
    case.write_text(
        '[grid]\nunit = "um"\n\n[elastic]\ncontact_modulus = 1.0\n\n'
        '[indenter]\ntype = "file"\npath = "map.x3p"\nmissing = "interpolate"\ndetrend = "plane"\n'
        'periodize = "mirror"\n\n[load]\npressure = 0.01\n\n[output]\npng = false\nfields = false\n')
    out = tmp_path / "out"
    r = subprocess.run([GFMD, "run", str(case), "-o", str(out), "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    pre = s["topography"]["preprocessing"]
    assert pre["format"] == "x3p" and pre["case_unit"] == "um" and pre["unit_factor"] == pytest.approx(1e6)
    assert pre["missing"] == {"method": "interpolate", "points": 1, "sweeps": pre["missing"]["sweeps"]}
    # The least-squares plane over the valid points, in um (x, y and h), computed here.
    yy, xx = np.mgrid[0:n, 0:n] * (100.0 / n)
    ok = ~np.isnan(h)
    A = np.column_stack([np.ones(ok.sum()), xx[ok], yy[ok]])
    coef = np.linalg.lstsq(A, h[ok] * 1e6, rcond=None)[0]
    assert pre["detrend"]["removed_slope_x"] == pytest.approx(coef[1], rel=1e-9)
    assert pre["detrend"]["removed_slope_y"] == pytest.approx(coef[2], rel=1e-6, abs=1e-15)
    assert pre["grid_points"] == [64, 64] and pre["periodize"]["method"] == "mirror"
    assert s["input"]["grid"]["lx"] == pytest.approx(200.0) and s["input"]["grid"]["unit"] == "um"
    assert s["units"].startswith("lengths in um")
    # The same map at a coarser grid: resampled.
    r = subprocess.run([GFMD, "run", str(case), "-o", str(tmp_path / "out2"), "-q", "--set", "grid.nx=32"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "out2" / "summary.json").read_text())["topography"]["preprocessing"][
        "resampled"] is True
    # Bad options: the key named, nothing written.
    for setting, words in (("indenter.periodize=\"wrap\"", "indenter.periodize"),
                           ("indenter.unit=\"nm\"", "states its units"),
                           ("grid.unit=\"inch\"", "grid.unit"),
                           ("indenter.crop=[0, 0, 99, 8]", "indenter.crop"),
                           ("indenter.missing=\"error\"", "1 point has no value")):
        bad = tmp_path / "bad"
        r = subprocess.run([GFMD, "run", str(case), "-o", str(bad), "-q", "--set", setting],
                           capture_output=True, text=True)
        assert r.returncode != 0, setting
        assert words in r.stderr, (setting, r.stderr)
        assert not bad.exists(), setting
    # A non-periodic map solved as periodic: warned.
    r = subprocess.run([GFMD, "run", str(case), "-o", str(tmp_path / "out3"), "-q", "--set",
                        "indenter.periodize=\"none\"", "--set", "indenter.crop=[0, 0, 20, 32]"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "not periodic" in r.stderr


def test_readme_round_trip_with_the_shipped_map(tmp_path):
    """The README's "Bring your own surface" example: the shipped x3p is what its generator
    makes, and `gfmd run examples/measured_x3p.toml` prepares it as the README says and writes
    the analysis."""
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    shipped = os.path.join(root, "examples", "surfaces", "ground_steel.x3p")
    env = dict(os.environ)
    import shutil
    shutil.copy(os.path.join(root, "examples", "surfaces", "make_ground_steel.py"), tmp_path)
    gen = tmp_path / "make_ground_steel.py"
    gen.write_text(gen.read_text().replace('os.path.join(here, "..", "..", "tests", "python")',
                                           repr(os.path.abspath(os.path.dirname(__file__)))))
    subprocess.run(["/usr/bin/python3", str(gen)], check=True, capture_output=True, env=env)
    a, b = _core.read_height_file(shipped), _core.read_height_file(str(tmp_path / "ground_steel.x3p"))
    assert a["missing"] == b["missing"] == 37
    assert np.array_equal(np.isnan(a["h"]), np.isnan(b["h"])) and np.allclose(a["h"], b["h"], equal_nan=True,
                                                                              rtol=0, atol=0)
    out = tmp_path / "x3p"
    r = subprocess.run([GFMD, "run", os.path.join(root, "examples", "measured_x3p.toml"), "-o", str(out), "-q",
                        "--set", "output.png=false"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    pre = s["topography"]["preprocessing"]
    assert pre["missing"]["points"] == 37 and pre["grid_points"] == [512, 512] and pre["unit_factor"] == 1e6
    assert pre["detrend"]["removed_slope_x"] == pytest.approx(1.93e-3, rel=0.01)  # the 2 mrad written
    an = s["analysis"]
    assert an["patches"]["count"] > 100 and not an["patches"]["percolating"]
    assert 0 < an["gap"]["median"] < an["gap"]["max"] and 0 < an["pressure"]["median"] < an["pressure"]["p90"]
    assert 0 < an["spectrum"]["hurst"] < 1
    for name in ("patches.csv", "distributions.csv", "spectrum.csv", "bands.csv", "flow.json"):
        assert (out / name).is_file(), name
    rows = (out / "patches.csv").read_text().splitlines()
    assert len(rows) == an["patches"]["count"] + 1
    areas = [float(x.split(",")[1]) for x in rows[1:]]
    assert areas == sorted(areas, reverse=True) and areas[0] == pytest.approx(an["patches"]["largest_area"])
    assert sum(areas) == pytest.approx(s["relative_contact_area"] * 256.0 ** 2, rel=1e-12)


def test_python_curve_matches_the_command(tmp_path):
    """gfmd.curve gives the rows and threshold `gfmd curve` gives for the same case."""
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    case = os.path.join(root, "examples", "eggcrate.toml")
    sets = ["grid.nx=64", "output.fields=false"]
    got = gfmd.curve(case, [0.1, 0.02, 0.05], str(tmp_path / "py"), set=sets)
    cmd = [GFMD, "curve", case, "--pressures", "0.02,0.05,0.1", "-o", str(tmp_path / "cli"), "-q", "--no-png"]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    want = json.loads((tmp_path / "cli" / "curve.json").read_text())
    assert got["pressures"] == [0.02, 0.05, 0.1]
    assert (tmp_path / "py" / "curve.csv").read_text() == (tmp_path / "cli" / "curve.csv").read_text()
    assert got["percolation"]["status"] == want["percolation"]["status"]
    with pytest.raises(gfmd.InputError, match="pressures"):
        gfmd.curve(case, [0.1, -1], str(tmp_path / "bad"))
    assert not (tmp_path / "bad").exists()


def test_a_size_over_the_files_own_is_said(tmp_path):
    # A file that states its size (10 x 8), read with another lx: the map is stretched along x
    # (the case's size wins, as documented), and a warning (in the case's summary and on stderr,
    # here in preprocessing) says so with the factor; the stated
    # size itself or none given warns nothing.
    h = np.random.default_rng(3).standard_normal((8, 10)) * 0.01
    p = tmp_path / "m.txt"
    write_text(p, h, lx=10.0, ly=8.0)
    t = gfmd.Topography.read(p, lx=20.0)
    assert (t.lx, t.ly) == (20.0, 8.0)
    assert any("grid.lx (20 for the map) replaces the 10 the file states: the map is stretched 2 times along x" in w
               for w in t.preprocessing["warnings"]), t.preprocessing["warnings"]
    for kw in ({}, {"lx": 10.0, "ly": 8.0}):
        assert not [w for w in gfmd.Topography.read(p, **kw).preprocessing["warnings"] if "stretched" in w]
