"""The Python API: topographies as values, elastic bodies, solve() and its Result."""
from __future__ import annotations

import json
import math
import numbers
import os
import re
import warnings
from dataclasses import dataclass
from typing import Callable, Iterable, Optional

import numpy as np

from . import _core
from ._core import InputError, SolveError


def _positive(name: str, value) -> float:
    """A positive finite number, or InputError naming the argument."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name}: must be a number (got {value!r})")
    v = float(value)
    if not (v > 0 and math.isfinite(v)):
        raise InputError(f"{name}: must be positive and finite (got {value!r})")
    return v


def _flag(name: str, value) -> bool:
    if not isinstance(value, bool):
        raise InputError(f"{name}: must be True or False, got {value!r}")
    return value


def _count(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not 2 <= int(value) <= 65536:
        raise InputError(f"{name}: must be an integer in [2, 65536] (got {value!r})")
    return int(value)


def _heights(name: str, heights) -> np.ndarray:
    """float64, C-contiguous, 2-D, finite: converted (one copy at most) or refused.

    A numpy masked array's masked entries are missing points, as NaN is: refused, naming them.
    """
    mask = None
    if isinstance(heights, np.ma.MaskedArray):
        mask = np.ma.getmaskarray(heights)
        heights = np.ma.getdata(heights)
    a = np.asarray(heights)
    if a.dtype.kind not in "fiu" or a.dtype == np.bool_:
        raise InputError(f"{name}: must be a real array (got dtype {a.dtype})")
    if a.ndim != 2:
        raise InputError(f"{name}: must be 2-D (ny, nx) (got shape {a.shape})")
    if a.shape[0] < 2 or a.shape[1] < 2:
        raise InputError(f"{name}: needs at least 2 x 2 points (got shape {a.shape})")
    a = np.ascontiguousarray(a, dtype=np.float64)
    missing = np.isnan(a) if mask is None else (mask | np.isnan(a))
    if missing.any():
        iy, ix = np.unravel_index(int(np.argmax(missing)), a.shape)
        n = int(missing.sum())
        raise InputError(f"{name}: holds {n} missing point{'s' if n > 1 else ''} ("
                         f"{'masked or NaN' if mask is not None else 'NaN'}: non-finite), the first at (iy, ix) = "
                         f"({iy}, {ix}); a topography needs a height everywhere: fill them first (np.ma.filled, "
                         f"or Topography.read(path, missing=\"interpolate\") on a saved .npy)")
    if not np.all(np.isfinite(a)):
        bad = int(np.argmax(~np.isfinite(a)))
        raise InputError(f"{name}: holds a non-finite value at (iy, ix) = {np.unravel_index(bad, a.shape)}")
    return a


def _warn_implausible(topography: "Topography", check: str) -> "Topography":
    """Warns (UserWarning) where the rms gradient is above the CLI's plausibility limit (5): most
    likely heights and lateral lengths in different units; `check` names the arguments to check."""
    g = topography.rms_gradient()
    limit = _core.max_plausible_rms_gradient
    if g > limit:
        warnings.warn(f"{topography.kind} topography: rms gradient {g:.3g}, above {limit:g} (slopes steeper than "
                      f"79 degrees): heights and lateral lengths are likely in different units; check {check}",
                      UserWarning, stacklevel=3)
        topography._warned = True
    return topography


class Topography:
    """A rigid indenter's heights on a periodic lx x ly cell: h[iy, ix] at x = ix lx/nx, y = iy ly/ny.

    Heights point towards the elastic body (asperity peaks are maxima and touch first). Make one
    with hertz(), eggcrate(), self_affine(), from_array() or read(); .heights is read-only.
    """

    def __init__(self, heights, lx: float, ly: Optional[float] = None, kind: str = "array"):
        # A view, so that marking it read-only leaves the caller's array as it was.
        self._h = _heights("heights", heights).view()
        self._h.setflags(write=False)
        self.lx = _positive("lx", lx)
        self.ly = _positive("ly", self.lx * self._h.shape[0] / self._h.shape[1] if ly is None else ly)
        self.kind = kind

    # -- constructors ------------------------------------------------------------------
    @classmethod
    def hertz(cls, nx: int, lx: float, radius: Optional[float] = None, *, radius_x: Optional[float] = None,
              radius_y: Optional[float] = None, ny: Optional[int] = None, ly: Optional[float] = None) -> "Topography":
        """Paraboloid h = -(x-xc)^2/(2 radius_x) - (y-yc)^2/(2 radius_y), apex (max h = 0) at the cell centre."""
        nx, ny, lx, ly = cls._grid(nx, lx, ny, ly)
        rx = radius_x if radius_x is not None else radius
        ry = radius_y if radius_y is not None else radius
        if rx is None or ry is None:
            raise InputError("radius: give radius (or radius_x and radius_y)")
        h = _core.make_hertz(nx, ny, lx, ly, _positive("radius_x" if radius_x is not None else "radius", rx),
                             _positive("radius_y" if radius_y is not None else "radius", ry))
        return _warn_implausible(cls(h, lx, ly, "hertz"), "radius against lx, ly (a paraboloid is a sphere only "
                                 "where its slope is small)")

    @classmethod
    def eggcrate(cls, nx: int, lx: float, wavelength: Optional[float] = None, amplitude: Optional[float] = None, *,
                 ny: Optional[int] = None, ly: Optional[float] = None) -> "Topography":
        """h = amplitude [cos(2 pi x/wavelength) + cos(2 pi y/wavelength)]; wavelength must divide lx and ly.

        Defaults: wavelength = lx, amplitude = wavelength / (2 pi)^2 (peak radius of curvature = wavelength).
        """
        nx, ny, lx, ly = cls._grid(nx, lx, ny, ly)
        wl = lx if wavelength is None else _positive("wavelength", wavelength)
        amp = wl / (4 * math.pi ** 2) if amplitude is None else _positive("amplitude", amplitude)
        return _warn_implausible(cls(_core.make_eggcrate(nx, ny, lx, ly, wl, amp), lx, ly, "eggcrate"),
                                 "amplitude against wavelength")

    @classmethod
    def self_affine(cls, nx: int, lx: float, *, hurst: float = 0.8, lambda_long: Optional[float] = None,
                    lambda_short: Optional[float] = None, rms_height: Optional[float] = None,
                    rms_gradient: Optional[float] = None, lambda_rolloff: Optional[float] = None, seed: int = 0,
                    ny: Optional[int] = None, ly: Optional[float] = None) -> "Topography":
        """Random self-affine surface, spectrum C q^(-2-2 hurst) between 2 pi/lambda_long and 2 pi/lambda_short.

        Give exactly one of rms_height and rms_gradient (the realised value is exact). Defaults:
        lambda_long = lx/2, lambda_short = lambda_long/128. The same seed gives the same bits everywhere.
        """
        nx, ny, lx, ly = cls._grid(nx, lx, ny, ly)
        if (rms_height is None) == (rms_gradient is None):
            raise InputError("rms_height: give exactly one of rms_height and rms_gradient")
        ll = lx / 2 if lambda_long is None else _positive("lambda_long", lambda_long)
        ls = ll / 128 if lambda_short is None else _positive("lambda_short", lambda_short)
        if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
            raise InputError(f"seed: must be an integer >= 0 (got {seed!r})")
        h = _core.make_selfaffine(
            nx, ny, lx, ly, float(hurst), ll, ls, 0.0 if rms_height is None else _positive("rms_height", rms_height),
            0.0 if rms_gradient is None else _positive("rms_gradient", rms_gradient),
            0.0 if lambda_rolloff is None else _positive("lambda_rolloff", lambda_rolloff), int(seed))
        return _warn_implausible(cls(h, lx, ly, "selfaffine"),
                                 "rms_height against lx" if rms_gradient is None else "rms_gradient (asked for)")

    @classmethod
    def from_array(cls, heights, lx: float, ly: Optional[float] = None) -> "Topography":
        """Heights (ny, nx) on an lx x ly cell (ly defaults to keeping square cells: lx ny/nx).

        A C-ordered float64 array is kept, not copied (change it afterwards and the topography
        changes too); integer arrays, non-contiguous views and masked arrays are converted (one
        copy); NaN or masked points (missing), infinite values, non-2-D or non-real arrays raise
        InputError. An rms gradient above 5 warns (heights and lx likely in different units).
        """
        return _warn_implausible(cls(heights, lx, ly, "array"), "the heights against lx, ly (the same unit?)")

    @classmethod
    def read(cls, path: str, lx: Optional[float] = None, ly: Optional[float] = None, *,
             unit: Optional[str] = None, case_unit: Optional[str] = None, missing: str = "error",
             detrend: str = "none", periodize: str = "none", crop=None,
             nx: Optional[int] = None, ny: Optional[int] = None) -> "Topography":
        """A measured or saved height map: x3p, CSV/TSV/text, .npy, .gwy, .sur or NetCDF.

        The options are those of a case's file indenter (README, "Bring your own surface"):
        ``unit`` the unit of a file that states none, ``case_unit`` the unit to convert to
        (metres when the file states units and none is named), ``lx``/``ly`` the map's size
        (wins over the file's), ``crop=(ix0, iy0, nx, ny)``, ``missing`` ("error", "mean",
        "interpolate"), ``detrend`` ("none", "mean", "plane"), ``periodize`` ("none",
        "mirror", "pad"), ``nx``/``ny`` a grid to resample onto. What was done is in
        ``preprocessing`` (the summary.json record).
        """
        h, lx2, ly2, report = _core.load_height_map(
            str(path), case_unit or "", unit or "",
            0.0 if lx is None else _positive("lx", lx), 0.0 if ly is None else _positive("ly", ly),
            [] if crop is None else [int(c) for c in crop], missing, detrend, periodize,
            0 if nx is None else _count("nx", nx), 0 if ny is None else _count("ny", ny))
        t = cls(h, lx2, ly2, "file")
        t._preprocessing = report
        return _warn_implausible(t, "unit (the unit of the file's heights where it states none) against the "
                                 "map's size (lx, ly, or the file's stated size)")

    @property
    def preprocessing(self) -> Optional[dict]:
        """For a map read from a file: its format, units, and what was done to it (else None)."""
        return getattr(self, "_preprocessing", None)

    @staticmethod
    def _grid(nx, lx, ny, ly):
        nx = _count("nx", nx)
        ny = nx if ny is None else _count("ny", ny)
        lx = _positive("lx", lx)
        ly = lx * ny / nx if ly is None else _positive("ly", ly)
        return nx, ny, lx, ly

    # -- values ------------------------------------------------------------------------
    @property
    def heights(self) -> np.ndarray:
        """The heights, (ny, nx), read-only."""
        return self._h

    @property
    def shape(self):
        return self._h.shape

    @property
    def nx(self) -> int:
        return self._h.shape[1]

    @property
    def ny(self) -> int:
        return self._h.shape[0]

    def _stats(self):
        return _core.statistics(self._h, self.lx, self.ly)

    def rms_height(self) -> float:
        """Root mean square height about the mean (length)."""
        return self._stats()["rms_height"]

    def rms_gradient(self) -> float:
        """sqrt(<|grad h|^2>), computed spectrally (dimensionless)."""
        return self._stats()["rms_gradient"]

    def rms_curvature(self) -> float:
        """sqrt(<(lap h / 2)^2>), computed spectrally (1/length)."""
        return self._stats()["rms_curvature"]

    def psd(self, bins: int = 64):
        """Radially averaged power spectral density C(q) (length^4), with its wave numbers q (1/length).

        C(q) = (lx ly) / (2 pi)^2 |h~(q)|^2 / (nx ny)^2 with h~ the discrete transform; returns
        (q, C) over logarithmic bins between the smallest and largest |q| with modes: the
        geometric bin centres and the mean C over each bin's modes, as a run's spectrum.csv.
        """
        if isinstance(bins, bool) or not isinstance(bins, (int, np.integer)):
            raise InputError(f"bins: must be a positive integer (got {bins!r})")  # the core checks the range
        return _core.isotropic_psd(self._h, self.lx, self.ly, int(bins))

    def __repr__(self) -> str:
        return f"Topography({self.kind}, {self.nx} x {self.ny} on {self.lx:g} x {self.ly:g})"


@dataclass(frozen=True)
class ElasticBody:
    """An elastic layer of the given thickness on a rigid base, or a half-space (thickness = inf).

    contact_modulus: E* = E / (1 - nu^2), the unit of pressures and stresses. poisson: nu in
    (-1, 0.5] (0.5 only for a half-space); checked on construction (InputError). coupling = False drops the normal/in-plane coupling
    (the usual uncoupled approximation) for comparison.
    """

    contact_modulus: float = 1.0
    poisson: float = 0.25
    thickness: float = math.inf
    coupling: bool = True

    def __post_init__(self):
        # Checked here, as [elastic] is in a case file, not only when a solve uses the body.
        for name in ("contact_modulus", "poisson", "thickness"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real):
                raise InputError(f"ElasticBody.{name}: must be a number, got {v!r}")
        if not isinstance(self.coupling, bool):
            raise InputError(f"ElasticBody.coupling: must be True or False, got {self.coupling!r}")
        try:
            _core.check_elastic(float(self.contact_modulus), float(self.poisson), float(self.thickness))
        except InputError as e:
            raise InputError(f"ElasticBody.{e}") from None


_SOLVER_KEYS = {"tolerance", "max_iterations", "max_outer", "max_tangential", "anderson", "mixing", "threads",
                "fft_planner", "backend"}
_FRICTION_KEYS = {"regularization", "creepage", "lateral_creepage", "slip_derivative", "stick_step",
                  "stick_acceleration", "reference"}


def _toml_value(name: str, v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        f = float(v)
        if math.isnan(f):
            raise InputError(f"{name}: must not be NaN")
        return "inf" if f == math.inf else ("-inf" if f == -math.inf else repr(f))
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(name, x) for x in v) + "]"
    raise InputError(f"{name}: unsupported value {v!r}")


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
        """The case as TOML (what `gfmd run` would read)."""
        return self._s.toml

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


def solve(topography: Topography, body: Optional[ElasticBody] = None, *, pressure: Optional[float] = None,
          force: Optional[float] = None, approach: Optional[float] = None, friction: float = 0.0,
          direction: float = 0.0, interaction: str = "harmonic", stress_depths: Iterable[float] = (),
          progress: Optional[Callable[[int, int, float], None]] = None, **options) -> Result:
    """Presses (and, with friction > 0, slides) the topography on the body; returns a Result.

    Exactly one of pressure (mean, E*), force (E* L^2) or approach (L). friction: the local
    Coulomb coefficient mu_c; direction: sliding direction in degrees from x. options: the
    [solver] keys (tolerance, max_iterations, max_outer, max_tangential, anderson, mixing,
    threads, fft_planner, backend) and the [friction] keys (regularization, creepage,
    lateral_creepage, slip_derivative, stick_step, stick_acceleration, reference). progress(iteration, friction_step, change) is called about every
    0.2 s; progress=True shows a tqdm bar (plain lines without tqdm). Ctrl-C raises KeyboardInterrupt within an iteration. The same case through
    gfmd.run or `gfmd run` gives the same numbers.
    """
    if not isinstance(topography, Topography):
        raise InputError(f"topography: must be a gfmd.Topography (got {type(topography).__name__})")
    body = ElasticBody() if body is None else body
    if not isinstance(body, ElasticBody):
        raise InputError(f"body: must be a gfmd.ElasticBody (got {type(body).__name__})")
    loads = {k: v for k, v in (("pressure", pressure), ("force", force), ("approach", approach)) if v is not None}
    if len(loads) != 1:
        raise InputError("pressure: give exactly one of pressure, force, approach")
    unknown = sorted(set(options) - _SOLVER_KEYS - _FRICTION_KEYS)
    if unknown:
        raise InputError(f"{unknown[0]}: unknown keyword argument of gfmd.solve (solver options: "
                         f"{', '.join(sorted(_SOLVER_KEYS))}; friction options: {', '.join(sorted(_FRICTION_KEYS))})")
    bar = None
    if progress is True:
        progress, bar = _progress_bar()
    elif progress is not None and progress is not False and not callable(progress):
        raise InputError("progress: True (a bar) or a callable (iteration, friction_step, change)")
    elif progress is False:
        progress = None
    (lk, lv), = loads.items()
    lines = ["[grid]", f"nx = {topography.nx}", f"ny = {topography.ny}", f"lx = {topography.lx!r}",
             f"ly = {topography.ly!r}", "[elastic]",
             f"contact_modulus = {_toml_value('contact_modulus', body.contact_modulus)}",
             f"poisson = {_toml_value('poisson', body.poisson)}",
             f"thickness = {_toml_value('thickness', body.thickness)}",
             f"coupling = {_toml_value('coupling', body.coupling)}",
             "[indenter]", 'type = "array"', "[load]", f"{lk} = {_toml_value(lk, lv)}",
             "[friction]", f"coefficient = {_toml_value('friction', friction)}",
             f"direction = {_toml_value('direction', direction)}"]
    lines += [f"{k} = {_toml_value(k, v)}" for k, v in options.items() if k in _FRICTION_KEYS]
    lines += ["[interaction]", f"model = {_toml_value('interaction', interaction)}", "[solver]"]
    lines += [f"{k} = {_toml_value(k, v)}" for k, v in options.items() if k in _SOLVER_KEYS]
    depths = list(stress_depths)
    lines += ["[stress]", f"depths = {_toml_value('stress_depths', depths)}", "[output]", "png = false"]
    try:
        solution = _core.solve_case("\n".join(lines) + "\n", topography.heights, topography.lx, topography.ly,
                                    progress)
    except InputError as e:
        # The case text is made here from the arguments: its line numbers mean nothing to the caller.
        text = re.sub(r" \[<gfmd\.solve>:\d+\]", "", str(e))
        raise InputError(text.replace("<gfmd.solve>: ", "gfmd.solve: ", 1)) from None
    finally:
        if bar is not None:
            bar.close()
    result = Result(solution, topography)
    if not getattr(topography, "_warned", False):  # a Topography warns once, when made
        for w in result.summary.get("warnings", []):
            warnings.warn(w, UserWarning, stacklevel=2)
    return result


def _progress_bar():
    """A tqdm bar over the solver's iterations (or plain lines on stderr without tqdm)."""
    try:
        from tqdm import tqdm
    except ImportError:
        import sys

        class _Lines:
            def update(self, it, step, change):
                sys.stderr.write(f"  iteration {it}  friction step {step}  change {change:.2e}\n")

            def close(self):
                pass

        lines = _Lines()
        return lines.update, lines

    bar = tqdm(unit="it", desc="gfmd.solve", leave=False)

    def update(it, step, change):
        bar.n = it
        bar.set_postfix(step=step, change=f"{change:.1e}", refresh=False)
        bar.refresh()

    return update, bar


def run(case: str, set: Iterable[str] = (), output: str = "", force: bool = False) -> dict:
    """Solves a case file as `gfmd run` does: {'summary': dict, 'fields': {name: ndarray}}; with
    output, also writes the run directory there (a new or empty directory, or one gfmd made;
    force=True writes into any other, as --force; checked before the solve)."""
    return _core.run(str(case), list(set), str(output), _flag("force", force))


def run_toml(toml: str, set: Iterable[str] = ()) -> dict:
    """As run(), for a case given as TOML text."""
    return _core.run_toml(toml, list(set))


# --- studies over case files (the same C++ studies as the command line) -------------------

def sweep(case: str, parameter: str, values: Iterable[float], output: str, set: Iterable[str] = (),
          plot: Optional[str] = None, force: bool = False) -> dict:
    """A load sweep as `gfmd sweep CASE --set parameter=v1,v2,...`: points solved in order, each
    warm-started from the previous one, into output/point_NNN/; returns sweep.json (one row of
    scalar summary keys per point). Points already solved with the same input are reused.
    plot: a column (summary key) to draw against the parameter into output/sweep_<plot>.png, as
    `gfmd sweep --plot` does (InputError if the summaries have no such column)."""
    vals = [float(v) for v in values]
    if not isinstance(parameter, str) or "." not in parameter:
        raise InputError(f"parameter: a config key section.key (got {parameter!r})")
    if plot is not None and (not isinstance(plot, str) or not plot):
        raise InputError(f"plot: a summary key such as 'friction_coefficient' (got {plot!r})")
    _core.sweep_case(str(case), parameter, vals, list(set), str(output), plot or "", _flag("force", force))
    with open(os.path.join(str(output), "sweep.json")) as f:
        return json.load(f)


def percolation(case: str, direction: str = "x", set: Iterable[str] = (), area_tolerance: float = 0.002,
                output: str = "", force: bool = False) -> dict:
    """The critical relative contact area at which flow along direction ("x" or "y") stops, as
    `gfmd percolation`; returns percolation.json's contents (and writes it into output if given)."""
    return _core.percolation_case(str(case), str(direction), list(set), _positive("area_tolerance", area_tolerance),
                                  str(output), _flag("force", force))


def curve(case: str, pressures, output: str, set: Iterable[str] = (), force: bool = False) -> dict:
    """Load curves as `gfmd curve`: the case solved at each mean pressure (/E*, sorted, warm
    started, leakage on) into output/points/; writes output/curve.csv and curve.json (the
    figure curve.png is drawn by `gfmd curve`) and returns curve.json (rows under "points",
    the percolation threshold under "percolation")."""
    try:
        ps = [float(p) for p in pressures]
    except (TypeError, ValueError):
        raise InputError(f"pressures: a list of numbers (got {pressures!r})") from None
    return _core.curve_case(str(case), ps, list(set), str(output), _flag("force", force))


def ensemble(case: str, output: str, seeds=(0, 7), set: Iterable[str] = (), force: bool = False) -> dict:
    """Flow over roughness seeds seeds[0]..seeds[1] (inclusive) as `gfmd ensemble --seeds A..B`,
    into output/seed_N/; returns ensemble.json (per seed, mean, spread, Bruggeman value)."""
    try:
        first, last = (int(seeds[0]), int(seeds[1]))
    except (TypeError, ValueError, IndexError):
        raise InputError(f"seeds: (first, last) integers (got {seeds!r})") from None
    return _core.ensemble_case(str(case), first, last, list(set), str(output), _flag("force", force))


def _package_file(*parts: str) -> str:
    """A file shipped with the package (installed: gfmd/bin/gfmd) or, in the build tree
    (build/python/gfmd), the build's. "" if absent."""
    here = os.path.dirname(os.path.abspath(__file__))
    for base in (here, os.path.dirname(os.path.dirname(here))):
        path = os.path.join(base, *parts)
        if os.path.exists(path):
            return path
    return ""


def study(study_file: str, quick: bool = False, output: str = os.path.join("out", "studies"),
          set: Iterable[str] = ()) -> dict:
    """Runs a figure study (studies/*.toml) as `gfmd study` does: its sweeps or runs (reusing
    finished results), then its figure (PNG, PDF) and the plotted data (CSV) in
    output/<name>/<quick|full>/. Returns study.json (figure path, series, wall time, series
    that stopped early). The study's case paths are relative to the folder above the study
    file's (the repository root for studies/*.toml). Raises SolveError if a series stopped
    early (its finished points are drawn), InputError (a ValueError) for a missing or malformed
    study file or a case file given as a study, naming the file and the key. `set`: settings
    for every run of the study, after its own (e.g. 'solver.backend="cuda"').
    KeyboardInterrupt (Ctrl-C, or a notebook's interrupt) stops the study's runs, waits for
    them and is raised again; the finished runs are reused by the next call."""
    import signal
    import subprocess
    import tempfile

    path = os.path.abspath(str(study_file))
    if not os.path.isfile(path):
        raise InputError(f"study_file: {study_file}: no such file")
    program = _package_file("bin", "gfmd") or _package_file("gfmd")
    if not program:
        raise InputError("study: the gfmd program is not installed with the package")
    # `gfmd study` itself (it finds study.py beside it and calls itself back for the runs).
    args = [program, "study", path, "-o", str(output)] + (["--quick"] if quick else [])
    for kv in set:
        args += ["--set", str(kv)]
    # In a process group of its own, so that an interrupt of this process (which may come
    # alone, as a notebook's does) reaches gfmd study, study.py and the run in progress at
    # once; they stop cleanly (exit status 4) and are waited for.
    with tempfile.TemporaryFile(mode="w+", encoding="utf-8", errors="replace") as err:
        p = subprocess.Popen(args, stderr=err, process_group=0)
        interrupted = False
        while True:
            try:
                p.wait()
                break
            except KeyboardInterrupt:
                interrupted = True
                try:
                    os.killpg(p.pid, signal.SIGINT)
                except OSError:
                    pass
        err.seek(0)
        stderr = err.read()
    name = os.path.splitext(os.path.basename(path))[0]
    report = os.path.join(str(output), name, "quick" if quick else "full", "study.json")
    if interrupted or p.returncode == 4:  # 4: interrupted (a signal that reached the study directly)
        raise KeyboardInterrupt(f"study {name} interrupted; the same call continues it")
    if p.returncode != 0:
        tail = stderr.strip().splitlines()[-1] if stderr.strip() else f"exit status {p.returncode}"
        if p.returncode == 2:  # bad input: the study file, a setting
            raise InputError(tail[len("gfmd study: "):] if tail.startswith("gfmd study: ") else tail)
        raise SolveError(f"study {name}: {tail}")
    with open(report) as f:
        return json.load(f)
