"""Result: a solved case's summary and fields."""
from __future__ import annotations

import math
import os
import numbers
from typing import Iterable, Optional

import numpy as np

from ._core import InputError
from ._checks import _flag, _positive
from ._topography import Topography


class Result:
    """A solved case: .summary (the keys of summary.json), every field of fields.nc as a read-only
    numpy view (ny, nx) (result.pressure, result["gap"], result.fields), .save(dir), .plot(), .flow()."""

    def __init__(self, solution, topography: Optional[Topography] = None):
        self._s = solution
        self._summary = None
        self.topography = topography

    @property
    def summary(self) -> dict:
        if self._summary is None:
            self._summary = self._s.summary
        return self._summary

    @property
    def field_names(self):
        return list(self._s.field_names())

    @property
    def fields(self) -> dict:
        """Every field by name (views, no copies)."""
        return {n: self._s.field(n) for n in self._s.field_names()}

    def __getitem__(self, name: str) -> np.ndarray:
        return self._s.field(name)

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        try:
            return self._s.field(name)
        except KeyError:
            raise AttributeError(f"Result has no field or attribute {name!r}; fields: {self.field_names}") from None

    def field_info(self, name: str):
        """(description, units) of a field, as in fields.nc."""
        return tuple(self._s.field_info(name))

    @property
    def grid(self):
        """(nx, ny, lx, ly)."""
        return tuple(self._s.grid)

    @property
    def toml(self) -> str:
        """The case as TOML (what `gfmd run` would read). Heights given as an array (every
        gfmd.Topography) are read there from heights.npy beside the case file, which save_case
        writes (a comment in the text says so)."""
        return self._s.toml

    def save_case(self, path: str) -> None:
        """Writes the case as a TOML file that `gfmd run PATH` (or gfmd.run) solves again to the same
        numbers; heights given as an array go beside it as <stem>_heights.npy. Each file is written
        whole (a temporary file renamed) or not at all."""
        path = os.fspath(path)
        if not path.endswith(".toml"):
            raise InputError(f"path: a case file ends in .toml (got {path!r})")
        folder = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(folder):
            raise InputError(f"path: its folder {folder} does not exist")
        stem = os.path.splitext(os.path.basename(path))[0]
        heights = stem + "_heights.npy"
        # Both written to temporary files first, then renamed (the heights, then the case): a
        # failed write leaves the earlier pair as it was, and no temporary file.
        staged = []
        try:
            tmp_case = os.path.join(folder, f".{stem}.toml.{os.getpid()}.tmp")
            staged.append(tmp_case)
            with open(tmp_case, "w") as f:
                f.write(self._s.toml_with_heights(heights))
            tmp_h = os.path.join(folder, f".{heights}.{os.getpid()}.tmp")
            if self._s.given_heights:
                staged.append(tmp_h)
                with open(tmp_h, "wb") as f:
                    np.save(f, np.asarray(self._s.field("topography")))
                os.replace(tmp_h, os.path.join(folder, heights))
            os.replace(tmp_case, path)
        finally:
            for t in staged:
                if os.path.exists(t):
                    os.remove(t)

    def save(self, directory: str, png: bool = False, force: bool = False) -> None:
        """Writes the run directory `gfmd run -o DIR` writes (summary.json, fields.nc, profiles.csv, ...);
        png=True also draws its PNG maps and profiles.png as `gfmd run` does (in a separate Python).
        The directory must be new, empty or made by gfmd (force=True: any other, as --force); the
        files are staged and replace an earlier result only once complete."""
        self._s.save(str(directory), _flag("png", png), _flag("force", force))

    def flow(self, directions: Iterable = ("x", "y"), tolerance: float = 1e-10, solver: str = "auto") -> dict:
        """Reynolds flow through the deformed gap (as `gfmd flow`): {'summary': flow.json keys, 'fields': currents}.

        directions: "x", "y" or angles in degrees.
        """
        angles = []
        for d in directions:
            if d == "x":
                angles.append(0.0)
            elif d == "y":
                angles.append(90.0)
            elif isinstance(d, numbers.Real) and not isinstance(d, bool) and math.isfinite(d):
                angles.append(float(d))
            else:
                raise InputError(f"directions: 'x', 'y' or an angle in degrees (got {d!r})")
        if not angles:
            raise InputError("directions: give at least one")
        return self._s.flow(angles, _positive("tolerance", tolerance), str(solver))

    def plot(self, field: str = "pressure", ax=None, **imshow):
        """Draws a field over the cell in physical coordinates with a labelled colour bar; returns the axes.

        Labels as in gfmd run's maps: "quantity (unit)", lengths in grid.unit ("x (µm)") or L
        where the case names none ("x (L)"), pressures and stresses in E*, "(–)" for a
        dimensionless field; cell ix is centred at x = ix lx/nx."""
        import textwrap

        import matplotlib.pyplot as plt

        def unit_text(u):  # scripts/figure_io.py unit_text: the same notation as the CLI's figures
            if u in ("", "1"):
                return "–"
            out = []
            for t in u.split():
                base, _, power = t.partition("^")
                base = {"length": "L", "um": "µm"}.get(base, base)
                out.append(base + power.translate(str.maketrans("-1234", "⁻¹²³⁴")))
            return " ".join(out)

        data = self._s.field(field)
        nx, ny, lx, ly = self.grid
        dx, dy = lx / nx, ly / ny
        if ax is None:
            _, ax = plt.subplots()
        im = ax.imshow(data, origin="lower", extent=(-dx / 2, lx - dx / 2, -dy / 2, ly - dy / 2), **imshow)
        desc, units = self.field_info(field)
        length = unit_text(self.field_info("gap")[1] if "gap" in self.field_names else "length")
        ax.figure.colorbar(im, ax=ax, label=f"{field} ({unit_text(units)})")
        ax.set_xlabel(f"x ({length})")
        ax.set_ylabel(f"y ({length})")
        ax.set_aspect("equal")
        # The description up to its formula ("dissipated power density / v0 = tau . v_slip / v0 ..."),
        # wrapped to the axes' width: the title stays inside the figure.
        ax.set_title(textwrap.fill(desc.split(" = ")[0], 42), fontsize=10)
        return ax

    def __repr__(self) -> str:
        s = self.summary
        return (f"Result({s.get('status')}, contact area {s.get('relative_contact_area', float('nan')):.4g}, "
                f"friction {s.get('friction_coefficient', float('nan')):.4g})")
