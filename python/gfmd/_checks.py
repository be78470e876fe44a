"""Argument checks of the Python API: numbers, flags, grid sizes, height arrays, plausibility."""
from __future__ import annotations

import math
import numbers
import warnings
from typing import TYPE_CHECKING

import numpy as np

from . import _core
from ._core import InputError

if TYPE_CHECKING:
    from ._topography import Topography


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


def _sets(value) -> list:
    """The `set` overrides: one 'section.key=value' string or an iterable of them."""
    if isinstance(value, str):
        return [value]
    try:
        items = list(value)
    except TypeError:
        raise InputError(f"set: must be 'section.key=value' or a list of them, got {value!r}") from None
    for v in items:
        if not isinstance(v, str):
            raise InputError(f"set: each override must be a 'section.key=value' string, got {v!r}")
    return items


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
    if g is None or not math.isfinite(g):
        raise InputError(f"heights: the {topography.kind} topography's rms gradient is not finite (heights too "
                         f"large to square and sum; check {check})")
    if g > limit:
        warnings.warn(f"{topography.kind} topography: rms gradient {g:.3g}, above {limit:g} (slopes steeper than "
                      f"79 degrees): heights and lateral lengths are likely in different units; check {check}",
                      UserWarning, stacklevel=3)
        topography._warned = True
    return topography
