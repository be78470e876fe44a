"""Elastic bodies, solve() on a Topography, and case files run as `gfmd run` does."""
from __future__ import annotations

import math
import numbers
import re
import warnings
from dataclasses import dataclass
from typing import Callable, Iterable, Optional

from . import _core
from ._core import InputError
from ._checks import _flag
from ._result import Result
from ._topography import Topography


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
