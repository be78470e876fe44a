"""Faults in height maps: wrong units, x,y,z points, NaNs, odd .npy/.x3p/.csv files.

Each function adds its faults in the order of the table (ids are positions); fault_table.py
calls them in that order."""
import math
import os
import random
import struct

from faults.checks import file_case, has_fragment, leftovers, npy_bytes, read_json


def issue_maps(F):
    """Height maps in the wrong unit or as x,y,z points (from the issue)."""
    add = F.add

    def f6(d):
        os.makedirs(d)
        n, L = 64, 10.0
        rows = []
        for j in range(n):
            y = j * L / n
            rows.append(",".join("%.4f" % (80.0 * math.sin(2 * math.pi * i / n) * math.cos(2 * math.pi * 2 * y / L)
                                           + 40.0 * math.sin(2 * math.pi * 3 * (i / n + y / L)))
                                 for i in range(n)))
        F.write(os.path.join(d, "map_nm.csv"), "\n".join(rows) + "\n")
        F.write(os.path.join(d, "case.toml"), file_case("nm", "map_nm.csv", 'unit = "um"'))
        r = F.run(["run", os.path.join(d, "case.toml"), "-o", os.path.join(d, "out"), "-q"])
        wrong = []
        if not (has_fragment(r.err, "gradient") and has_fragment(r.err, ("unit",))):
            wrong.append("no rms-gradient warning naming the unit keys")
        s = read_json(os.path.join(d, "out", "summary.json"))
        if r.rc == 0 and s is not None and not s.get("warnings"):
            wrong.append("summary.json has no warnings")
        return F.verdict(r, {0: "handled", 3: "handled"}, [], leftovers(os.path.join(d, "out")), wrong)
    add("nm height map declared as µm (rms gradient ~100)", f6)

    def xyz_case(d, scattered):
        os.makedirs(d)
        n, h = 32, 0.25
        lines = ["x,y,z"]
        rnd = random.Random(1)
        for j in range(n):
            for i in range(n):
                x, y = i * h, j * h
                if scattered:
                    x, y = rnd.uniform(0, n * h), rnd.uniform(0, n * h)
                z = 0.05 * math.sin(2 * math.pi * i / n) * math.sin(2 * math.pi * j / n)
                lines.append("%.6f,%.6f,%.6f" % (x, y, z))
        F.write(os.path.join(d, "points.csv"), "\n".join(lines) + "\n")
        F.write(os.path.join(d, "case.toml"),
                file_case("xyz", "points.csv", 'unit = "um"', grid='unit = "um"', load="pressure = 0.02"))
        out = os.path.join(d, "out")
        r = F.run(["run", os.path.join(d, "case.toml"), "-o", out, "-q"])
        if scattered:
            return F.verdict(r, {2: "refused"}, ["points.csv"], leftovers(out))
        s = read_json(os.path.join(out, "summary.json")) or {}
        grid = (s.get("input") or {}).get("grid", {})
        wrong = []
        if r.rc == 0 and (grid.get("nx"), grid.get("ny")) != (n, n):
            wrong.append("read as a %sx%s grid, not 32x32 points" % (grid.get("nx"), grid.get("ny")))
        if r.rc == 0 and abs(grid.get("lx", 0) - n * h) > 1e-9:
            wrong.append("lx = %s, not %g" % (grid.get("lx"), n * h))
        return F.verdict(r, {0: "handled", 2: "refused"}, ["points.csv"] if r.rc == 2 else [],
                         leftovers(out), wrong)
    add("x,y,z CSV, points on a regular 32x32 grid", lambda d: xyz_case(d, False))
    add("x,y,z CSV, scattered points", lambda d: xyz_case(d, True))


def bad_maps(F):
    """Height maps gfmd must refuse."""
    add = F.add

    def map_case(d, name, data, frags, extra='unit = "um"', mode="w"):
        os.makedirs(d, exist_ok=True)
        p = os.path.join(d, name)
        with open(p, mode) as f:
            f.write(data)
        F.write(os.path.join(d, "case.toml"), file_case(name, name, extra))
        out = os.path.join(d, "out")
        return F.expect_refusal(["run", os.path.join(d, "case.toml"), "-o", out], frags, new_dir=out)

    def nan_map(d):
        rows = []
        for j in range(32):
            rows.append(",".join("nan" if (i, j) in ((3, 4), (10, 20)) else "%.3f" % (0.01 * math.sin(i + j))
                                 for i in range(32)))
        return map_case(d, "holes.csv", "\n".join(rows) + "\n", ["holes.csv", "missing"])
    add("height map with NaNs (missing = \"error\")", nan_map)

    def npy_complex(d):
        raw = struct.pack("<%dd" % (2 * 32 * 32), *([0.1] * (2 * 32 * 32)))
        return map_case(d, "complex.npy", npy_bytes("<c16", (32, 32), raw), ["complex.npy"], mode="wb")
    add(".npy of complex128", npy_complex)

    def npy_str(d):
        raw = ("abc" * (32 * 32)).encode("utf-32-le")
        return map_case(d, "strings.npy", npy_bytes("<U3", (32, 32), raw), ["strings.npy"], mode="wb")
    add(".npy of strings (<U3)", npy_str)

    def npy_3d(d):
        raw = struct.pack("<%dd" % (2 * 16 * 16), *([0.1] * (2 * 16 * 16)))
        return map_case(d, "cube.npy", npy_bytes("<f8", (2, 16, 16), raw), ["cube.npy"], mode="wb")
    add(".npy with 3 dimensions", npy_3d)

    def npy_truncated(d):
        raw = struct.pack("<%dd" % 100, *([0.1] * 100))
        return map_case(d, "short.npy", npy_bytes("<f8", (32, 32), raw), ["short.npy"], mode="wb")
    add(".npy shorter than its header says", npy_truncated)

    add("x3p that is not a zip",
        lambda d: map_case(d, "fake.x3p", "this is not a zip archive\n", ["fake.x3p"], extra=""))
    add("empty height-map file (0 bytes .csv)", lambda d: map_case(d, "empty.csv", "", ["empty.csv"]))

    def map_missing(d):
        os.makedirs(d)
        F.write(os.path.join(d, "case.toml"), file_case("x", "nowhere.csv", 'unit = "um"'))
        out = os.path.join(d, "out")
        return F.expect_refusal(["run", os.path.join(d, "case.toml"), "-o", out], ["nowhere.csv"], new_dir=out)
    add("height-map path that does not exist", map_missing)
