"""Independent writers of height-map files for the reader tests, written from the formats'
published descriptions (not from gfmd's readers):

- x3p: ISO 25178-72 (XML 3D surface profile), as described by the OpenGPS consortium's
  ISO5436_2 schema: a zip archive with main.xml (Record1: revision, feature type SUR, axes
  CX/CY incremental with their increments in metres, CZ absolute with its data type;
  Record3: MatrixDimension SizeX/SizeY/SizeZ and a PointDataLink to bindata/data.bin, or an
  inline DataList), little-endian point data, x fastest; md5checksum.hex. Invalid points of
  float data are NaN; of integer data they are marked in bindata/valid.bin (1 bit per point,
  1 = valid, least significant bit first).
- npy: NumPy's format description (NEP 1): magic "\\x93NUMPY", version, header length, a
  Python dict literal (descr, fortran_order, shape) padded with spaces to a multiple of 64
  bytes and ending in a newline, then the raw data. Written here with struct, not numpy.save.
- text: CSV/TSV/whitespace matrices with '# lx = <v> <unit>' / '# unit = <u>' headers.
"""
import hashlib
import struct
import zipfile

import numpy as np

_TYPES = {"I": ("<i2", 2), "L": ("<i4", 4), "F": ("<f4", 4), "D": ("<f8", 8)}


def x3p_main_xml(nx, ny, dx, dy, ztype="D", zinc=None, zoff=None, datalist=None, feature="SUR",
                 valid_link=False, md5="", size_z=1):
    """main.xml text of an x3p file (metres)."""
    def axis(name, atype, inc, dtype=None, off=None):
        parts = [f"<{name}>", f"<AxisType>{atype}</AxisType>"]
        if dtype:
            parts.append(f"<DataType>{dtype}</DataType>")
        if inc is not None:
            parts.append(f"<Increment>{inc!r}</Increment>")
        if off is not None:
            parts.append(f"<Offset>{off!r}</Offset>")
        parts.append(f"</{name}>")
        return "".join(parts)

    if datalist is None:
        data = ("<DataLink><PointDataLink>bindata/data.bin</PointDataLink>"
                f"<MD5ChecksumPointData>{md5}</MD5ChecksumPointData></DataLink>")
    else:
        data = "<DataList>" + "".join("<Datum/>" if d is None else f"<Datum>{d!r}</Datum>" for d in datalist) + \
            "</DataList>"
    valid = "<ValidPointsLink>bindata/valid.bin</ValidPointsLink>" if valid_link else ""
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2" '
            'xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">\n'
            "<Record1><Revision>ISO5436 - 2000</Revision>"
            f"<FeatureType>{feature}</FeatureType><Axes>"
            + axis("CX", "I", dx, "D", 0.0) + axis("CY", "I", dy, "D", 0.0)
            + axis("CZ", "A", zinc, ztype, zoff)
            + "</Axes></Record1>\n"
            "<Record2><Date>2026-11-25T00:00:00+00:00</Date><Creator>gfmd tests</Creator>"
            "<Instrument><Manufacturer>none</Manufacturer><Model>writer</Model><Serial>0</Serial>"
            "<Version>1</Version></Instrument><CalibrationDate>2026-01-01T00:00:00+00:00</CalibrationDate>"
            "<ProbingSystem><Type>NonContacting</Type><Identification>synthetic</Identification>"
            "</ProbingSystem><Comment>made by tests/python/surface_writers.py</Comment></Record2>\n"
            f"<Record3><MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>{size_z}</SizeZ>"
            f"</MatrixDimension>{data}{valid}</Record3>\n"
            "<Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4>\n"
            "</p:ISO5436_2>\n")


def write_x3p(path, h, lx, ly, ztype="D", zinc=None, zoff=None, inline=False, valid=None, main_xml=None,
              data_bytes=None):
    """h: heights in metres, indexed [iy, ix]; NaN = invalid. Integer types store
    round((h - zoff) / zinc) and mark invalid points in valid.bin."""
    h = np.asarray(h, dtype=float)
    ny, nx = h.shape
    dx, dy = lx / nx, ly / ny
    flat = h.reshape(-1)  # x fastest
    dtype, _ = _TYPES[ztype]
    if ztype in "IL":
        zinc = 1e-9 if zinc is None else zinc
        zoff = 0.0 if zoff is None else zoff
        raw = np.where(np.isnan(flat), 0, np.round((np.nan_to_num(flat) - zoff) / zinc)).astype(dtype)
        if valid is None and np.isnan(flat).any():
            valid = ~np.isnan(flat)
    else:
        raw = flat.astype(dtype) if zinc is None else ((flat - (zoff or 0.0)) / zinc).astype(dtype)
    data = raw.tobytes() if data_bytes is None else data_bytes
    md5 = hashlib.md5(data).hexdigest()
    if main_xml is None:
        main_xml = x3p_main_xml(nx, ny, dx, dy, ztype, zinc, zoff,
                                datalist=[None if np.isnan(v) else float(v) for v in flat] if inline else None,
                                valid_link=valid is not None, md5=md5)
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as z:
        z.writestr("main.xml", main_xml)
        if not inline:
            z.writestr("bindata/data.bin", data)
        if valid is not None:
            bits = np.packbits(np.asarray(valid, dtype=np.uint8), bitorder="little")
            z.writestr("bindata/valid.bin", bits.tobytes())
        z.writestr("md5checksum.hex", hashlib.md5(main_xml.encode()).hexdigest() + " *main.xml\n")


def write_npy(path, a, dtype="<f8", fortran=False, shape=None, descr=None, version=1):
    """NumPy .npy written from its format description (not with numpy.save)."""
    a = np.asarray(a)
    shape = a.shape if shape is None else shape
    descr = dtype if descr is None else descr
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (
        descr, "True" if fortran else "False", "(" + ", ".join(str(int(s)) for s in shape) +
        ("," if len(shape) == 1 else "") + ")")
    pre = 10 if version == 1 else 12
    pad = (64 - (pre + len(header) + 1) % 64) % 64
    header = header + " " * pad + "\n"
    data = np.asarray(a, dtype=dtype).tobytes(order="F" if fortran else "C")
    with open(path, "wb") as f:
        f.write(b"\x93NUMPY" + bytes([version, 0]))
        f.write(struct.pack("<H", len(header)) if version == 1 else struct.pack("<I", len(header)))
        f.write(header.encode("latin1"))
        f.write(data)


def write_text(path, h, sep=" ", lx=None, ly=None, unit=None, size_unit=None):
    """A matrix, one row (iy) per line; NaN written as 'nan'."""
    lines = []
    if lx is not None:
        lines.append(f"# lx = {lx!r}" + (f" {size_unit}" if size_unit else ""))
    if ly is not None:
        lines.append(f"# ly = {ly!r}" + (f" {size_unit}" if size_unit else ""))
    if unit is not None:
        lines.append(f"# unit = {unit}")
    for row in np.asarray(h, dtype=float):
        lines.append(sep.join("nan" if np.isnan(v) else repr(float(v)) for v in row))
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
