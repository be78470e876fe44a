"""The .gwy and .sur readers (gfmd._core.read_height_file) on files from the independent
writers in writers_gwy_sur.py: round trips, units, missing points, and damaged files, which
must give an InputError naming the file, never a crash or a huge allocation."""
import struct

import numpy as np
import pytest

import gfmd
from gfmd import _core

from writers_gwy_sur import sur_patch, write_gwy, write_sur

read = getattr(_core, "read_height_file", None)
pytestmark = pytest.mark.skipif(read is None, reason="gfmd._core.read_height_file is not built")

RNG = np.random.default_rng(25)


def heights(ny=5, nx=7, scale=1.0):
    return scale * RNG.standard_normal((ny, nx))


def expect_error(path, *words):
    with pytest.raises(gfmd.InputError) as e:
        read(str(path))
    msg = str(e.value)
    assert str(path) in msg, msg
    for w in words:
        assert w in msg, f"{w!r} not in {msg!r}"
    return msg


def truncations(data, path):
    """Every prefix at a spread of lengths (all of the first 64 bytes) gives an InputError."""
    cuts = sorted(set(range(0, min(64, len(data)))) | set(np.linspace(0, len(data) - 1, 60).astype(int)))
    for n in cuts:
        path.write_bytes(data[:n])
        expect_error(path)


# ---------------------------------------------------------------------------------------
# GWY


def test_gwy_round_trip_exact_in_metres(tmp_path):
    h = heights(scale=1e-7)
    p = tmp_path / "a.gwy"
    write_gwy(p, h, 3e-6, 2e-6)
    m = read(str(p))
    assert m["format"] == "gwy" and m["unit"] == "m"
    assert m["h"].shape == (5, 7)
    assert np.array_equal(m["h"], h)
    assert (m["lx"], m["ly"]) == (3e-6, 2e-6)
    assert m["missing"] == 0 and m["first_missing"] == ""


def test_gwy_prefixed_units_convert_to_metres(tmp_path):
    h = heights()
    p = tmp_path / "b.gwy"
    write_gwy(p, h, 30.0, 20.0, xy_unit="µm", z_unit="nm")
    m = read(str(p))
    assert m["unit"] == "m"
    np.testing.assert_allclose(m["h"], h * 1e-9, rtol=1e-15)
    np.testing.assert_allclose((m["lx"], m["ly"]), (30e-6, 20e-6), rtol=1e-15)


def test_gwy_without_units_keeps_values(tmp_path):
    h = heights()
    for xy, z in ((None, None), ("", "")):
        p = tmp_path / "c.gwy"
        write_gwy(p, h, 4.0, 5.0, xy_unit=xy, z_unit=z)
        m = read(str(p))
        assert m["unit"] == "" and np.array_equal(m["h"], h) and (m["lx"], m["ly"]) == (4.0, 5.0)


def test_gwy_non_length_or_one_sided_units_are_errors(tmp_path):
    p = tmp_path / "d.gwy"
    write_gwy(p, heights(), 1.0, 1.0, xy_unit="m", z_unit="V")
    expect_error(p, "si_unit_z", "'V'", "not a length")
    write_gwy(p, heights(), 1.0, 1.0, xy_unit="s", z_unit="m")
    expect_error(p, "si_unit_xy", "'s'")
    write_gwy(p, heights(), 1.0, 1.0, xy_unit="m", z_unit=None)
    expect_error(p, "si_unit_z", "not a length")


def test_gwy_mask_marks_missing_points(tmp_path):
    h = heights(6, 4)
    mask = np.zeros_like(h)
    mask[1, 2] = mask[4, 0] = mask[5, 3] = 1.0
    p = tmp_path / "e.gwy"
    write_gwy(p, h, 1e-6, 1e-6, mask=mask)
    m = read(str(p))
    assert m["missing"] == 3
    assert np.array_equal(np.isnan(m["h"]), mask == 1)
    assert np.array_equal(m["h"][mask == 0], h[mask == 0])
    assert "(1, 2)" in m["first_missing"] and "mask" in m["first_missing"]


def test_gwy_first_channel_and_skipped_components(tmp_path):
    # Components of every type come before the image and inside the data field.
    h = heights()
    p = tmp_path / "f.gwy"
    write_gwy(p, h, 1.0, 1.0, channel=3, extras=True)
    assert np.array_equal(read(str(p))["h"], h)
    write_gwy(p, h, 1.0, 1.0, extras=False)
    assert np.array_equal(read(str(p))["h"], h)


def test_gwy_truncated_anywhere_is_an_input_error(tmp_path):
    p = tmp_path / "t.gwy"
    data = write_gwy(p, heights(), 1e-6, 1e-6, mask=np.zeros((5, 7)))
    truncations(data, p)


def test_gwy_dims_disagree_with_data(tmp_path):
    p = tmp_path / "g.gwy"
    write_gwy(p, heights(5, 7), 1.0, 1.0, xres=6)
    expect_error(p, "35 values", "xres x yres = 6 x 5")


def test_gwy_huge_dims_fail_before_allocating(tmp_path):
    p = tmp_path / "h.gwy"
    write_gwy(p, heights(2, 2), 1.0, 1.0, xres=60000, yres=60000)
    expect_error(p, "60000 x 60000")
    write_gwy(p, heights(2, 2), 1.0, 1.0, xres=-3, yres=2)
    expect_error(p, "-3 x 2")


def test_gwy_corrupt_structure(tmp_path):
    p = tmp_path / "i.gwy"
    data = write_gwy(p, heights(), 1.0, 1.0, extras=False)
    # The container's declared size is larger than the file.
    bad = bytearray(data)
    struct.pack_into("<I", bad, 4 + len(b"GwyContainer\0"), len(data))
    p.write_bytes(bytes(bad))
    expect_error(p, "GwyContainer", "truncated")
    # A nested object (the data field) declares more bytes than its container holds.
    k = data.index(b"GwyDataField\0") + len(b"GwyDataField\0")
    bad = bytearray(data)
    struct.pack_into("<I", bad, k, 1 << 30)
    p.write_bytes(bytes(bad))
    expect_error(p, "GwyDataField", "offset")
    # An unknown type character.
    k = data.index(b"xres\0") + len(b"xres\0")
    p.write_bytes(data[:k] + b"z" + data[k + 1:])
    expect_error(p, "xres", "'z'")
    # A data array count beyond the bytes left.
    k = data.index(b"data\0D") + len(b"data\0D")
    bad = bytearray(data)
    struct.pack_into("<I", bad, k, 0xFFFFFFFF)
    p.write_bytes(bytes(bad))
    expect_error(p, "4294967295 items")
    # No image channel at all.
    from writers_gwy_sur import gwy_component, gwy_object
    p.write_bytes(b"GWYP" + gwy_object("GwyContainer", [gwy_component("/0/title", "s", "x")]))
    expect_error(p, "no image channel")


# ---------------------------------------------------------------------------------------
# SUR


@pytest.mark.parametrize("bits", [16, 32])
def test_sur_round_trip_within_quantisation(tmp_path, bits):
    h = heights(6, 9, scale=0.3)  # micrometres
    p = tmp_path / "a.sur"
    _, dz, _ = write_sur(p, h, 0.5, 0.25, bits=bits)
    m = read(str(p))
    assert m["format"] == "sur" and m["unit"] == "m" and m["h"].shape == (6, 9)
    assert np.max(np.abs(m["h"] - h * 1e-6)) <= (0.5 * dz + 1e-12 * abs(h).max()) * 1e-6
    np.testing.assert_allclose((m["lx"], m["ly"]), (9 * 0.5e-6, 6 * 0.25e-6), rtol=1e-7)
    assert m["missing"] == 0


def test_sur_units_in_either_micro_encoding_and_nm(tmp_path):
    h = heights()
    p = tmp_path / "b.sur"
    for enc in ("latin-1", "utf-8"):
        write_sur(p, h, 2.0, 2.0, xy_unit="µm", z_unit="nm", encoding=enc)
        m = read(str(p))
        assert m["lx"] == pytest.approx(7 * 2e-6) and m["ly"] == pytest.approx(5 * 2e-6)
        np.testing.assert_allclose(m["h"], h * 1e-9, atol=1e-12 * abs(h).max())


def test_sur_no_data_points_are_missing(tmp_path):
    h = heights(4, 5)
    absent = np.zeros(h.shape, bool)
    absent[0, 3] = absent[2, 2] = True
    p = tmp_path / "c.sur"
    write_sur(p, h, 1.0, 1.0, missing=absent, bits=16)
    m = read(str(p))
    assert m["missing"] == 2 and np.array_equal(np.isnan(m["h"]), absent)
    assert "(0, 3)" in m["first_missing"]


def test_sur_comment_and_private_zones_are_skipped(tmp_path):
    h = heights()
    p = tmp_path / "d.sur"
    _, dz, _ = write_sur(p, h, 1.0, 1.0, comment=b"$Operator = someone\n", private=b"\x01\x02\x03")
    assert np.max(np.abs(read(str(p))["h"] * 1e6 - h)) <= 0.5 * dz + 1e-12


def test_sur_truncated_anywhere_is_an_input_error(tmp_path):
    p = tmp_path / "t.sur"
    data, _, _ = write_sur(p, heights(), 1.0, 1.0, comment=b"abc")
    truncations(data, p)


def test_sur_huge_or_inconsistent_dims(tmp_path):
    p = tmp_path / "e.sur"
    data, _, _ = write_sur(p, heights(2, 2), 1.0, 1.0)
    big = sur_patch(sur_patch(data, "nx", 60000), "ny", 60000)
    p.write_bytes(big)
    expect_error(p, "60000 x 60000")
    # Plausible dims whose points are not in the file: refused before allocating.
    p.write_bytes(sur_patch(sur_patch(sur_patch(data, "nx", 5000), "ny", 5000), "n_points", 25000000))
    expect_error(p, "5000 x 5000", "truncated")
    p.write_bytes(sur_patch(data, "n_points", 5))
    expect_error(p, "5 points in all")


def test_sur_refused_variants(tmp_path):
    p = tmp_path / "f.sur"
    data, _, _ = write_sur(p, heights(), 1.0, 1.0)
    p.write_bytes(b"DSCOMPRESSED" + data[12:])
    expect_error(p, "compressed")
    p.write_bytes(sur_patch(data, "n_objects", 3))
    expect_error(p, "multi-object")
    p.write_bytes(sur_patch(data, "type", 1))
    expect_error(p, "profile")
    p.write_bytes(sur_patch(data, "bits", 8))
    expect_error(p, "8 bits")
    p.write_bytes(sur_patch(data, "format", 257))
    expect_error(p, "257")
    p.write_bytes(sur_patch(data, "dx", 0.0))
    expect_error(p, "x spacing")
    p.write_bytes(sur_patch(data, "dz_unit", b"V"))
    expect_error(p, "z unit 'V'", "not a length")


def test_sur_gwyddion_export_typed_as_profile_is_read(tmp_path):
    # Gwyddion's .sur export labels surfaces as profiles (type 1), object SCRATCH, operator csm.
    h = heights()
    p = tmp_path / "g.sur"
    data, dz, _ = write_sur(p, h, 1.0, 1.0, studiable_type=1)
    p.write_bytes(sur_patch(sur_patch(data, "object_name", b"SCRATCH"), "operator_name", b"csm"))
    assert np.max(np.abs(read(str(p))["h"] * 1e6 - h)) <= 0.5 * dz + 1e-12


def test_sur_without_units_keeps_values(tmp_path):
    h = heights()
    p = tmp_path / "h.sur"
    data, dz, _ = write_sur(p, h, 0.5, 0.5, xy_unit="", z_unit="")
    m = read(str(p))
    assert m["unit"] == "" and m["lx"] == 3.5 and np.max(np.abs(m["h"] - h)) <= 0.5 * dz + 1e-12
