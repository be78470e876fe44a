"""Topography: a rigid indenter's heights on a periodic cell, as a value."""
from __future__ import annotations

import math
import numbers
from typing import Optional

import numpy as np

from . import _core
from ._core import InputError
from ._checks import _count, _heights, _positive, _warn_implausible


def _crop(crop) -> list:
    """crop=(ix0, iy0, nx, ny): four whole numbers (a fraction was truncated without a word)."""
    try:
        items = list(crop)
    except TypeError:
        raise InputError(f"crop: (ix0, iy0, nx, ny), four whole numbers (got {crop!r})") from None
    out = []
    for c in items:
        if isinstance(c, bool) or not isinstance(c, numbers.Real) or c != int(c):
            raise InputError(f"crop: (ix0, iy0, nx, ny), four whole numbers (got {crop!r})")
        out.append(int(c))
    return out


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
    def flatpunch(cls, nx: int, lx: float, radius: float, depth: Optional[float] = None, *,
                  ny: Optional[int] = None, ly: Optional[float] = None) -> "Topography":
        """Flat cylindrical punch: h = 0 on the face (radius, centred in the cell), -depth beside it.

        depth defaults to the radius (the body meets only the face while its deflection beside the
        punch stays below depth). Boussinesq: stiffness 2 radius E*, p = F / (2 pi a sqrt(a^2 - r^2)).
        """
        keys = {"radius": radius} if depth is None else {"radius": radius, "depth": depth}
        return cls.indenter("flatpunch", nx, lx, ny=ny, ly=ly, **keys)

    @classmethod
    def indenter(cls, type: str, nx: int, lx: float, *, ny: Optional[int] = None, ly: Optional[float] = None,
                 **keys) -> "Topography":
        """Any indenter type a case file names (gfmd.indenter_types()), its keys as keywords:
        Topography.indenter("flatpunch", 256, 8.0, radius=0.5) is [indenter] type = "flatpunch",
        radius = 0.5 on that grid, read and checked as the case file's section is."""
        nx, ny, lx, ly = cls._grid(nx, lx, ny, ly)
        keys = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in keys.items()}  # numpy scalars
        for k, v in keys.items():
            if isinstance(v, numbers.Real) and not isinstance(v, bool) and not math.isfinite(v):
                raise InputError(f"indenter.{k}: must be a finite number, got {v!r}")
        h = _core.make_indenter(str(type), nx, ny, lx, ly, keys)
        return _warn_implausible(cls(h, lx, ly, str(type)), f"the keys of the {type} indenter against lx, ly")

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
                    ny: Optional[int] = None, ly: Optional[float] = None, generator: str = "gfmd",
                    peklenik: float = 1.0) -> "Topography":
        """Random self-affine surface, spectrum C q^(-2-2 hurst) between 2 pi/lambda_long and 2 pi/lambda_short.

        Give exactly one of rms_height and rms_gradient (the realised value is exact). Defaults:
        lambda_long = lx/2, lambda_short = lambda_long/128. The same seed gives the same bits everywhere.
        generator="contmech" draws the surface of the paper authors' code for their seed (randSeed;
        the paper's is 4711): the same phases on the same wave vectors (case key indenter.generator).
        peklenik (gamma): anisotropy, wavelengths along x sqrt(gamma) times and along y 1/sqrt(gamma)
        times the isotropic ones (indenter.peklenik; 1: isotropic).
        """
        nx, ny, lx, ly = cls._grid(nx, lx, ny, ly)
        if (rms_height is None) == (rms_gradient is None):
            raise InputError("rms_height: give exactly one of rms_height and rms_gradient")
        if generator not in ("gfmd", "contmech"):
            raise InputError(f"generator: unknown generator {generator!r}; one of gfmd (ours), contmech (the paper "
                             "authors' code)")
        ll = lx / 2 if lambda_long is None else _positive("lambda_long", lambda_long)
        ls = ll / 128 if lambda_short is None else _positive("lambda_short", lambda_short)
        if lambda_short is None:
            # The default, lambda_long/128, needs 2 grid spacings: on a coarse grid say so (the
            # check below would blame a lambda_short the caller never gave).
            gamma = _positive("peklenik", peklenik)
            spacing = max(lx / nx / math.sqrt(gamma), ly / ny * math.sqrt(gamma))
            if ls < 2 * spacing * (1 - 1e-12):
                raise InputError(f"lambda_short: the default, lambda_long/128 = {ls:.4g}, is shorter than twice the "
                                 f"grid spacing ({2 * spacing:.4g}) on {nx} x {ny} points: give lambda_short (at "
                                 f"least {2 * spacing:.4g}) or more points")
        if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or not 0 <= seed < 2 ** 64:
            raise InputError(f"seed: must be an integer in [0, 2^64) (got {seed!r})")
        h = _core.make_selfaffine(
            nx, ny, lx, ly, float(hurst), ll, ls, 0.0 if rms_height is None else _positive("rms_height", rms_height),
            0.0 if rms_gradient is None else _positive("rms_gradient", rms_gradient),
            0.0 if lambda_rolloff is None else _positive("lambda_rolloff", lambda_rolloff), int(seed), str(generator),
            _positive("peklenik", peklenik))
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
        (metres when the file states units and none is named), ``lx``/``ly`` the size of the
        map as it is used: after ``crop`` (the piece kept) and before ``periodize`` doubles the
        cell, as grid.lx/2 of a case with a periodized map (wins over the file's size, which is
        the whole file's and shrinks with a crop), ``crop=(ix0, iy0, nx, ny)`` (integers),
        ``missing`` ("error", "mean",
        "interpolate"), ``detrend`` ("none", "mean", "plane"), ``periodize`` ("none",
        "mirror", "pad"), ``nx``/``ny`` a grid to resample onto. What was done is in
        ``preprocessing`` (the summary.json record).
        """
        h, lx2, ly2, report = _core.load_height_map(
            str(path), case_unit or "", unit or "",
            0.0 if lx is None else _positive("lx", lx), 0.0 if ly is None else _positive("ly", ly),
            [] if crop is None else _crop(crop), missing, detrend, periodize,
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
