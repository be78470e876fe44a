"""Independent writers of Gwyddion .gwy and Digital Surf .sur height maps for the reader tests.

Written from the format descriptions, not from the C++ readers:

GWY (Gwyddion user guide, "Format of Gwyddion Files"): the magic b"GWYP", then one serialized
object. An object is its type name + NUL, a little-endian u32 with the byte size of its
components, then the components. A component is its name + NUL, one type character and the
value: b (bool byte), c (char), i (int32), q (int64), d (double), s (NUL-terminated string),
o (object); arrays C I Q D S O are a u32 count followed by the items. The file's object is a
GwyContainer; channel N's image is its component "/N/data", a GwyDataField with xres, yres (i),
xreal, yreal, xoff, yoff (d), si_unit_xy, si_unit_z (o: GwySIUnit with "unitstr") and data
(D: xres * yres doubles, row by row); "/N/mask" is a GwyDataField of 0/1 (1 = masked).

SUR (Digital Surf / MountainsMap, as laid out by Gwyddion's surffile.c and the readers of
SurfaceTopography, surfalize and RosettaSciIO): a 512-byte little-endian header (offsets in
SUR_OFFSETS), a comment and a private zone of the sizes the header gives, then the points as
int16 or int32, line by line; height = value * z spacing + z offset, in the z spacing unit;
with the non-measured flag set, points equal to zmin - 2 carry no value.
"""
import struct

import numpy as np

# ---------------------------------------------------------------------------------------
# GWY

_FIXED = {"b": "<B", "c": "<c", "i": "<i", "q": "<q", "d": "<d"}
_ARRAY = {"C": "<u1", "I": "<i4", "Q": "<i8", "D": "<f8"}


def gwy_object(type_name, components):
    """A serialized object from a list of serialized components (bytes)."""
    body = b"".join(components)
    return type_name.encode() + b"\0" + struct.pack("<I", len(body)) + body


def gwy_component(name, typecode, value):
    """A serialized component: value is a Python value, a serialized object (o) or a list."""
    head = name.encode() + b"\0" + typecode.encode()
    if typecode in _FIXED:
        return head + struct.pack(_FIXED[typecode], value)
    if typecode == "s":
        return head + value.encode() + b"\0"
    if typecode == "o":
        return head + value
    if typecode in _ARRAY:
        arr = np.ascontiguousarray(value, dtype=_ARRAY[typecode]).ravel()
        return head + struct.pack("<I", arr.size) + arr.tobytes()
    if typecode == "S":
        return head + struct.pack("<I", len(value)) + b"".join(s.encode() + b"\0" for s in value)
    if typecode == "O":
        return head + struct.pack("<I", len(value)) + b"".join(value)
    raise ValueError(f"unknown GWY type code {typecode!r}")


def gwy_si_unit(unit):
    comps = [] if unit is None else [gwy_component("unitstr", "s", unit)]
    return gwy_object("GwySIUnit", comps)


def gwy_data_field(values, xreal, yreal, xy_unit, z_unit, xres=None, yres=None, extra=()):
    values = np.asarray(values, dtype=np.float64)
    ny, nx = values.shape
    comps = [
        gwy_component("xres", "i", nx if xres is None else xres),
        gwy_component("yres", "i", ny if yres is None else yres),
        gwy_component("xreal", "d", xreal),
        gwy_component("yreal", "d", yreal),
        gwy_component("xoff", "d", 0.0),
        gwy_component("yoff", "d", 0.0),
    ]
    if xy_unit is not None:
        comps.append(gwy_component("si_unit_xy", "o", gwy_si_unit(xy_unit)))
    if z_unit is not None:
        comps.append(gwy_component("si_unit_z", "o", gwy_si_unit(z_unit)))
    comps.extend(extra)
    comps.append(gwy_component("data", "D", values))
    return gwy_object("GwyDataField", comps)


def _every_type():
    """Components of every type, which a reader must skip."""
    meta = gwy_object("GwyContainer", [gwy_component("Operator", "s", "nobody")])
    return [
        gwy_component("/0/data/visible", "b", 1),
        gwy_component("/0/base/range-type", "c", b"x"),
        gwy_component("/0/base/palette-index", "i", 7),
        gwy_component("/0/base/stamp", "q", 1 << 40),
        gwy_component("/0/base/min", "d", -1.5),
        gwy_component("/0/data/title", "s", "Height"),
        gwy_component("/0/meta", "o", meta),
        gwy_component("/0/bytes", "C", np.arange(5, dtype=np.uint8)),
        gwy_component("/0/ints", "I", np.arange(3)),
        gwy_component("/0/longs", "Q", np.arange(2)),
        gwy_component("/0/doubles", "D", np.linspace(0.0, 1.0, 4)),
        gwy_component("/0/strings", "S", ["a", "bc", ""]),
        gwy_component("/0/objects", "O", [meta, gwy_si_unit("m")]),
    ]


def write_gwy(path, h, lx, ly, xy_unit="m", z_unit="m", mask=None, *, xres=None, yres=None, extras=True,
              channel=0):
    """Writes h (2-D, [iy, ix], in z_unit) as channel `channel` of a .gwy file of size lx x ly (xy_unit).

    A unit of None leaves the GwySIUnit out; xres/yres override the declared dimensions;
    extras adds components of every type before the image."""
    h = np.asarray(h, dtype=np.float64)
    comps = list(_every_type()) if extras else []
    extra_field = [gwy_component("cache", "O", [gwy_si_unit("m")])] if extras else []
    comps.append(gwy_component(f"/{channel}/data", "o",
                               gwy_data_field(h, lx, ly, xy_unit, z_unit, xres, yres, extra_field)))
    if mask is not None:
        m = np.asarray(mask, dtype=np.float64)
        comps.append(gwy_component(f"/{channel}/mask", "o", gwy_data_field(m, lx, ly, xy_unit, "")))
    data = b"GWYP" + gwy_object("GwyContainer", comps)
    with open(path, "wb") as f:
        f.write(data)
    return data


# ---------------------------------------------------------------------------------------
# SUR

SUR_HEADER = 512
SUR_OFFSETS = {
    "signature": (0, "12s"), "format": (12, "<h"), "n_objects": (14, "<h"), "version": (16, "<h"),
    "type": (18, "<h"), "object_name": (20, "30s"), "operator_name": (50, "30s"),
    "non_measured": (86, "<h"), "absolute": (88, "<h"), "bits": (98, "<h"), "zmin": (100, "<i"),
    "zmax": (104, "<i"), "nx": (108, "<i"), "ny": (112, "<i"), "n_points": (116, "<i"),
    "dx": (120, "<f"), "dy": (124, "<f"), "dz": (128, "<f"),
    "x_name": (132, "16s"), "y_name": (148, "16s"), "z_name": (164, "16s"),
    "dx_unit": (180, "16s"), "dy_unit": (196, "16s"), "dz_unit": (212, "16s"),
    "x_unit": (228, "16s"), "y_unit": (244, "16s"), "z_unit": (260, "16s"),
    "x_ratio": (276, "<f"), "y_ratio": (280, "<f"), "z_ratio": (284, "<f"),
    "comment_size": (334, "<h"), "private_size": (336, "<h"),
    "x_offset": (466, "<f"), "y_offset": (470, "<f"), "z_offset": (474, "<f"),
}


def sur_patch(data, field, value):
    """The bytes `data` with one header field replaced."""
    off, fmt = SUR_OFFSETS[field]
    out = bytearray(data)
    struct.pack_into(fmt, out, off, value)
    return bytes(out)


def write_sur(path, h, dx, dy, xy_unit="um", z_unit="um", bits=32, missing=None, *, encoding="latin-1",
              comment=b"", private=b"", studiable_type=2, signature=b"DIGITAL SURF"):
    """Writes h (2-D, [iy, ix], in z_unit; NaN or `missing` True = no value) with point spacings
    dx, dy (xy_unit) as a single-surface .sur file of bits-bit integers. Returns
    (bytes written, z spacing, z offset): the heights come back within z spacing / 2."""
    h = np.asarray(h, dtype=np.float64)
    ny, nx = h.shape
    absent = np.isnan(h) if missing is None else (np.asarray(missing, dtype=bool) | np.isnan(h))
    valid = h[~absent]
    lo, hi = (float(valid.min()), float(valid.max())) if valid.size else (0.0, 0.0)
    # Integers in about [-top, top], with room for the float32 rounding of the z offset (a few
    # hundred steps at 32 bits) and for the no-data value zmin - 2.
    top = int(0.9 * 2 ** (bits - 1))
    dz = np.nextafter(np.float32((hi - lo) / (2 * top) if hi > lo else 1.0), np.float32(np.inf))
    zoff = np.float32(0.5 * (lo + hi))
    ints = np.rint((np.where(absent, zoff, h) - float(zoff)) / float(dz)).astype(np.int64)
    assert np.all(np.abs(ints) < 2 ** (bits - 1) - 4), "heights out of the integer range"
    zmin, zmax = (int(ints[~absent].min()), int(ints[~absent].max())) if valid.size else (0, 0)
    ints[absent] = zmin - 2

    hdr = bytearray(SUR_HEADER)
    fields = {
        "signature": signature, "format": 0, "n_objects": 1, "version": 1, "type": studiable_type,
        "object_name": b"test surface", "operator_name": b"writers_gwy_sur",
        "non_measured": int(absent.any()), "absolute": 1, "bits": bits, "zmin": zmin, "zmax": zmax,
        "nx": nx, "ny": ny, "n_points": nx * ny, "dx": dx, "dy": dy, "dz": dz,
        "x_name": b"X", "y_name": b"Y", "z_name": b"Z",
        "dx_unit": xy_unit.encode(encoding), "dy_unit": xy_unit.encode(encoding),
        "dz_unit": z_unit.encode(encoding), "x_unit": xy_unit.encode(encoding),
        "y_unit": xy_unit.encode(encoding), "z_unit": z_unit.encode(encoding),
        "x_ratio": 1.0, "y_ratio": 1.0, "z_ratio": 1.0,
        "comment_size": len(comment), "private_size": len(private),
        "x_offset": 0.0, "y_offset": 0.0, "z_offset": zoff,
    }
    for name, value in fields.items():
        off, fmt = SUR_OFFSETS[name]
        struct.pack_into(fmt, hdr, off, value)
    dtype = "<i2" if bits == 16 else "<i4"
    data = bytes(hdr) + comment + private + ints.astype(dtype).tobytes()
    with open(path, "wb") as f:
        f.write(data)
    return data, float(dz), float(zoff)
