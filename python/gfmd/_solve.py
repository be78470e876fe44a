"""Elastic bodies, ContactSolver / solve() / load_path on a Topography, and case files run as
`gfmd run` does."""
from __future__ import annotations

import math
import os
import numbers
import warnings
from dataclasses import dataclass
from typing import Callable, Iterable, Iterator, Optional

from . import _core
from ._core import InputError
from ._checks import _flag, _sets
from ._result import Result
from ._topography import Topography


@dataclass(frozen=True)
class ElasticBody:
    """An elastic layer of the given thickness on a rigid base, or a half-space (thickness = inf).

    contact_modulus: E* = E / (1 - nu^2), the unit of pressures and stresses. poisson: nu in
    (-1, 0.5] (0.5 only for a half-space); checked on construction (InputError). coupling = False drops the normal/in-plane coupling
    (the usual uncoupled approximation) for comparison.

    A coating (a layer of finite thickness) on an elastic substrate: substrate_contact_modulus and
    substrate_poisson (the half-space it is bonded to; inf: a rigid base). layers: further bonded
    layers beneath the top one, top to bottom, as (contact_modulus, poisson, thickness) tuples:

        body = gfmd.ElasticBody(contact_modulus=10.0, poisson=0.2, thickness=0.05,
                                substrate_contact_modulus=1.0, substrate_poisson=0.3)
    """

    contact_modulus: float = 1.0
    poisson: float = 0.25
    thickness: float = math.inf
    coupling: bool = True
    substrate_contact_modulus: float = math.inf
    substrate_poisson: float = 0.25
    layers: tuple = ()

    def __post_init__(self):
        # Checked here, as [elastic] is in a case file, not only when a solve uses the body.
        for name in ("contact_modulus", "poisson", "thickness", "substrate_contact_modulus", "substrate_poisson"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real):
                raise InputError(f"ElasticBody.{name}: must be a number, got {v!r}")
        if not isinstance(self.coupling, bool):
            raise InputError(f"ElasticBody.coupling: must be True or False, got {self.coupling!r}")
        layers = []
        for i, layer in enumerate(self.layers):
            if (not isinstance(layer, (tuple, list)) or len(layer) != 3
                    or any(isinstance(v, bool) or not isinstance(v, numbers.Real) for v in layer)):
                raise InputError(f"ElasticBody.layers[{i}]: must be (contact_modulus, poisson, thickness), "
                                 f"got {layer!r}")
            layers.append(tuple(float(v) for v in layer))
        object.__setattr__(self, "layers", tuple(layers))
        try:
            _core.check_elastic(float(self.contact_modulus), float(self.poisson), float(self.thickness),
                                float(self.substrate_contact_modulus), float(self.substrate_poisson), layers)
        except InputError as e:
            raise InputError(f"ElasticBody.{e}") from None


def _check_model(owner: str, m) -> None:
    """One viscoelastic model given, of a gfmd.ViscoelasticBody or a gfmd.ViscoelasticPart."""
    given = [m.high_frequency_modulus is not None or m.relaxation_time is not None,
             bool(m.prony_moduli or m.prony_times), m.master_curve is not None]
    if sum(given) != 1:
        raise InputError(f"{owner}: give high_frequency_modulus and relaxation_time (a standard linear "
                         "solid), prony_moduli and prony_times (a Prony series) or master_curve (a file)")
    if m.shift is not None and m.master_curve is None:
        raise InputError(f"{owner}.shift: belongs to a master_curve")
    # The values are checked as [elastic] is (InputError naming the key) when a solve reads them.


def _model_name(m) -> str:
    if m.master_curve is not None:
        return "master_curve"
    return "sls" if m.high_frequency_modulus is not None or m.relaxation_time is not None else "prony"


@dataclass(frozen=True)
class ViscoelasticPart:
    """A further viscoelastic part of a layered gfmd.ViscoelasticBody, with a model of its own
    (one table of elastic.viscoelastic_parts): part is "top", "layers[i]" or "substrate" (its
    relaxed modulus that part's contact modulus), the model's keys as ViscoelasticBody's. A rubber
    coating on a polymer substrate of another relaxation:

        body = gfmd.ViscoelasticBody(thickness=0.05, substrate_contact_modulus=0.5,
                                     high_frequency_modulus=10.0, relaxation_time=1.0,
                                     parts=(gfmd.ViscoelasticPart("substrate", high_frequency_modulus=5.0,
                                                                  relaxation_time=30.0),))
    """

    part: str
    high_frequency_modulus: Optional[float] = None
    relaxation_time: Optional[float] = None
    prony_moduli: tuple = ()
    prony_times: tuple = ()
    master_curve: Optional[str] = None
    shift: Optional[dict] = None

    def __post_init__(self):
        if not isinstance(self.part, str):
            raise InputError(f"ViscoelasticPart.part: \"top\", \"layers[i]\" or \"substrate\", got {self.part!r}")
        _check_model("ViscoelasticPart", self)

    @property
    def model(self) -> str:
        return _model_name(self)


@dataclass(frozen=True)
class ViscoelasticBody(ElasticBody):
    """A viscoelastic body in steady sliding (elastic.viscoelastic): contact_modulus is the relaxed
    (low-frequency) modulus E0. Either a standard linear solid, high_frequency_modulus (the glassy
    E_inf >= E0) and relaxation_time (tau), or a Prony series, prony_moduli E_i and prony_times
    tau_i (E(omega) = E0 + sum E_i i omega tau_i / (1 + i omega tau_i)), or a measured
    master_curve (a file of omega, E', E''; its first E' is E0) with an optional temperature shift
    (shift = the [elastic] keys: temperature, reference_temperature, wlf_c1, wlf_c2 or
    activation_temperature). Poisson's ratio is constant. On a layered body part= says which part
    is viscoelastic: "top" (the default), "layers[i]", "substrate" (a hard coating on a polymer)
    or "all"; parts= adds further parts with models of their own (gfmd.ViscoelasticPart). The
    sliding speed is the solve's velocity= (length per time unit of tau):

        body = gfmd.ViscoelasticBody(poisson=0.5, high_frequency_modulus=10.0, relaxation_time=1.0)
        r = gfmd.solve(top, body, force=0.01, velocity=0.02)
        r.summary["hysteresis_friction"]   # the friction of the pressure's asymmetry
    """

    high_frequency_modulus: Optional[float] = None
    relaxation_time: Optional[float] = None
    prony_moduli: tuple = ()
    prony_times: tuple = ()
    master_curve: Optional[str] = None  # a file of omega, E', E'' (elastic.master_curve); sets contact_modulus
    shift: Optional[dict] = None  # the master curve's temperature shift: the [elastic] keys, e.g.
    # {"temperature": 30, "reference_temperature": 20, "wlf_c1": 8.86, "wlf_c2": 101.6}
    part: str = "top"  # of a layered body: "top" (the top layer), "layers[i]" (a layer beneath it, its
    # modulus the relaxed one), "substrate" (its relaxed modulus is substrate_contact_modulus; the
    # layers above elastic) or "all" (elastic.viscoelastic_part)
    parts: tuple = ()  # further parts, each a gfmd.ViscoelasticPart (elastic.viscoelastic_parts)

    def __post_init__(self):
        super().__post_init__()
        _check_model("ViscoelasticBody", self)
        for i, p in enumerate(self.parts):
            if not isinstance(p, ViscoelasticPart):
                raise InputError(f"ViscoelasticBody.parts[{i}]: must be a gfmd.ViscoelasticPart, got {p!r}")
        object.__setattr__(self, "parts", tuple(self.parts))
        # Its values checked here, by the case files' rules for [elastic] (as ElasticBody's are),
        # not only when a solve reads them.
        case = {"grid": {"nx": 8, "lx": 1.0}, "elastic": _elastic_table(self), "indenter": {"type": "array"},
                "load": {"approach": 0.0}}
        try:
            _core.CaseSolver(case, None, 1.0, 1.0)
        except InputError as e:
            raise InputError(f"ViscoelasticBody: {str(e).removeprefix('gfmd.solve: ')}") from None

    @property
    def model(self) -> str:
        return _model_name(self)


def _depths(value) -> list:
    """stress_depths: an iterable of depths (a single number is refused, naming the argument)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise InputError(f"stress_depths: a list of depths below the surface, e.g. [0.01] (got {value!r})")
    return list(value)


def _material_keys(body: ElasticBody) -> dict:
    """A body's material keys, [elastic]'s and an elastic indenter's alike: its top layer, then
    the substrate and layers beneath it."""
    keys = {"contact_modulus": _plain("contact_modulus", body.contact_modulus),
            "poisson": _plain("poisson", body.poisson), "thickness": _plain("thickness", body.thickness)}
    if math.isfinite(body.substrate_contact_modulus):
        keys["substrate_contact_modulus"] = _plain("substrate_contact_modulus", body.substrate_contact_modulus)
        keys["substrate_poisson"] = _plain("substrate_poisson", body.substrate_poisson)
    if body.layers:
        keys["layers"] = [{"contact_modulus": e, "poisson": nu, "thickness": h} for e, nu, h in body.layers]
    return keys


def _model_keys(m, owner: str, name_part: bool) -> dict:
    """A viscoelastic part's keys (elastic.viscoelastic and its model's, as in [elastic] and in each
    table of elastic.viscoelastic_parts); viscoelastic_part if name_part."""
    keys = {"viscoelastic": m.model}
    if name_part:
        keys["viscoelastic_part"] = _plain("viscoelastic_part", m.part)
    if m.model == "master_curve":
        keys["master_curve"] = _plain("master_curve", os.path.abspath(m.master_curve))
        keys.update({k: _plain(k, v) for k, v in (m.shift or {}).items()})
        return keys
    for k in (("high_frequency_modulus", "relaxation_time") if m.model == "sls" else ("prony_moduli", "prony_times")):
        v = getattr(m, k)
        if v is None:
            raise InputError(f"{owner}.{k}: is needed with a standard linear solid")
        keys[k] = _plain(k, list(v) if isinstance(v, (tuple, list)) else v)
    return keys


def _elastic_table(body: ElasticBody) -> dict:
    """The [elastic] table of a gfmd.ElasticBody or gfmd.ViscoelasticBody."""
    table = _material_keys(body)
    table["coupling"] = _plain("coupling", body.coupling)
    if isinstance(body, ViscoelasticBody):
        model = _model_keys(body, "ViscoelasticBody", body.part != "top")
        if body.model == "master_curve" and body.contact_modulus == 1.0:
            # The table sets the relaxed modulus: the default is left to it; another value given is
            # checked against the table's first E' (refused where it differs, as in a case file).
            del table["contact_modulus"]
        table.update(model)
        if body.parts:
            table["viscoelastic_parts"] = [_model_keys(p, f"ViscoelasticBody.parts[{i}]", True)
                                           for i, p in enumerate(body.parts)]
    return table


# The interaction models given by name (those without keys of their own: the repulsions), from the
# registry (contact/interaction.hpp).
_REPULSIONS = tuple(m["name"] for m in _core.interaction_models() if not m["keys"])
_KEYED_MODELS = {m["name"]: m["keys"] for m in _core.interaction_models() if m["keys"]}


@dataclass(frozen=True)
class Adhesive:
    """The adhesive interaction (interaction.model = "adhesive"): the Maugis-Dugdale cohesive law,
    a tensile stress work_of_adhesion / range wherever the gap is below range, on a repulsion
    ("hardwall", the default, or "harmonic"). work_of_adhesion: energy per area (E* L); range:
    a length (L). Pass it as interaction= to gfmd.solve or gfmd.ContactSolver:

        solver = gfmd.ContactSolver(top, interaction=gfmd.Adhesive(1e-3, 0.0113))
        for r in gfmd.load_path(solver, approaches=[0.01, 0.0, -0.005, -0.01]):
            r.summary["normal_force"]   # negative in tension; the path unloads along its branch
    """

    work_of_adhesion: float
    range: float
    repulsion: str = "hardwall"

    def __post_init__(self):
        for name in ("work_of_adhesion", "range"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v):
                raise InputError(f"Adhesive.{name}: must be a finite number, got {v!r}")
        if not self.work_of_adhesion >= 0:
            raise InputError(f"Adhesive.work_of_adhesion: must be zero or positive, got {self.work_of_adhesion!r}")
        if not self.range > 0:
            raise InputError(f"Adhesive.range: must be positive, got {self.range!r}")
        if self.repulsion not in _REPULSIONS:
            raise InputError(f"Adhesive.repulsion: one of {', '.join(_REPULSIONS)}, got {self.repulsion!r}")


def _interaction_table(interaction) -> dict:
    """The [interaction] table of a model name or a gfmd.Adhesive."""
    if isinstance(interaction, Adhesive):
        return {"model": "adhesive", "work_of_adhesion": _plain("work_of_adhesion", interaction.work_of_adhesion),
                "range": _plain("range", interaction.range), "repulsion": _plain("repulsion", interaction.repulsion)}
    names = ", ".join(f'"{n}"' for n in _REPULSIONS)
    if not isinstance(interaction, str):
        raise InputError(f"interaction: {names} or a gfmd.Adhesive (got {interaction!r})")
    if interaction in _KEYED_MODELS:  # a model with keys of its own is given as its object
        keys = ", ".join(_KEYED_MODELS[interaction])
        raise InputError(f'interaction: "{interaction}" needs its keys ({keys}): pass '
                         "gfmd.Adhesive(work_of_adhesion, range)")
    return {"model": interaction}


_SOLVER_KEYS = {"tolerance", "max_iterations", "max_outer", "max_tangential", "anderson", "mixing", "threads",
                "fft_planner", "backend", "viscoelastic_method"}
# The [friction] keys besides coefficient and direction; the laws' own keys come from the registry.
_FRICTION_KEYS = {"regularization", "creepage", "lateral_creepage", "slip_derivative", "stick_step",
                  "stick_acceleration", "reference", "law", "velocity"} | {k for law in _core.friction_laws() for k in law["keys"]}


def _plain(name: str, v):
    """v as a plain bool, int, float, str or list of them (what a case's keys hold); name: the
    argument, named in the error for anything else or NaN."""
    if isinstance(v, bool):
        return v
    if isinstance(v, numbers.Integral):
        return int(v)
    if isinstance(v, numbers.Real):
        f = float(v)
        if math.isnan(f):
            raise InputError(f"{name}: must not be NaN")
        return f
    if isinstance(v, str):
        return v
    if isinstance(v, (list, tuple)):
        return [_plain(name, x) for x in v]
    raise InputError(f"{name}: unsupported value {v!r}")


def _one_load(where: str, pressure, force, approach):
    """The one load given: ("pressure" | "force" | "approach", value)."""
    loads = [(k, v) for k, v in (("pressure", pressure), ("force", force), ("approach", approach)) if v is not None]
    if len(loads) != 1:
        raise InputError(f"pressure: give exactly one of pressure, force, approach ({where})")
    (kind, value), = loads
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"load.{kind}: must be a number, got {value!r}")
    return kind, float(value)


def _progress_arg(progress):
    """(callable or None, bar or None) from progress=None | False | True | callable."""
    if progress is True:
        return _progress_bar()
    if progress is None or progress is False:
        return None, None
    if not callable(progress):
        raise InputError("progress: True (a bar) or a callable (iteration, friction_step, change)")
    return progress, None


class ContactSolver:
    """A contact problem set up once and solved at one load after another, each solve starting
    from the previous one's solution (a warm start: fewer iterations along a load path).

        solver = gfmd.ContactSolver(top, gfmd.ElasticBody(poisson=0.49, thickness=0.2), friction=0.5)
        for p in (0.01, 0.02, 0.05):
            r = solver.solve(pressure=p)      # a Result; r.summary["iterations"]: this solve's

    The arguments are gfmd.solve's, without the load: friction (mu_c), direction (degrees from x),
    interaction ("harmonic" | "hardwall" | gfmd.Adhesive(work_of_adhesion, range)), stiffness (the harmonic
    repulsion's k_if), hardness, stress_depths, and the solver and friction options as
    keywords. They are checked here, once (InputError). solve(pressure=|force=|approach=,
    progress=, warm=True) returns a Result; warm=False (or reset()) starts from nothing.
    Every solve gives the numbers gfmd.solve gives from the same start.
    """

    def __init__(self, topography: Topography, body: Optional[ElasticBody] = None, *, friction: float = 0.0,
                 direction: float = 0.0, interaction="harmonic", hardness: float = math.inf,
                 stress_depths: Iterable[float] = (), indenter_body: Optional[ElasticBody] = None,
                 stiffness: float = 0.0, **options):
        if not isinstance(topography, Topography):
            raise InputError(f"topography: must be a gfmd.Topography (got {type(topography).__name__})")
        body = ElasticBody() if body is None else body
        if not isinstance(body, ElasticBody):
            raise InputError(f"body: must be a gfmd.ElasticBody (got {type(body).__name__})")
        indenter = {"type": "array"}  # an elastic indenter: its material keys too
        if indenter_body is not None:
            if type(indenter_body) is not ElasticBody:
                raise InputError("indenter_body: must be a gfmd.ElasticBody (an elastic indenter; got "
                                 f"{type(indenter_body).__name__})")
            if indenter_body.coupling != body.coupling:
                raise InputError("indenter_body.coupling: the pair has one coupling, the body's "
                                 f"({body.coupling}); give both the same")
            indenter.update(_material_keys(indenter_body))
        unknown = sorted(set(options) - _SOLVER_KEYS - _FRICTION_KEYS)
        if unknown:
            raise InputError(f"{unknown[0]}: unknown keyword argument of gfmd.solve (solver options: "
                             f"{', '.join(sorted(_SOLVER_KEYS))}; friction options: "
                             f"{', '.join(sorted(_FRICTION_KEYS))})")
        # The case as tables, read by the case file's rules (no text in between). The load is set
        # by each solve; approach = 0 stands in while the case is read.
        interaction_table = _interaction_table(interaction)
        if not (isinstance(hardness, numbers.Real) and not isinstance(hardness, bool) and hardness == math.inf):
            interaction_table["hardness"] = _plain("hardness", hardness)
        if not (isinstance(stiffness, numbers.Real) and not isinstance(stiffness, bool) and stiffness == 0):
            interaction_table["stiffness"] = _plain("stiffness", stiffness)
        case = {
            "grid": {"nx": topography.nx, "ny": topography.ny, "lx": float(topography.lx), "ly": float(topography.ly)},
            "elastic": _elastic_table(body),
            "indenter": indenter,
            "load": {"approach": 0.0},
            "friction": {"coefficient": _plain("friction", friction), "direction": _plain("direction", direction),
                         **{k: _plain(k, v) for k, v in options.items() if k in _FRICTION_KEYS}},
            "interaction": interaction_table,
            "solver": {k: _plain(k, v) for k, v in options.items() if k in _SOLVER_KEYS},
            "stress": {"depths": _plain("stress_depths", _depths(stress_depths))},
            "output": {"png": False},
        }
        self._case = _core.CaseSolver(case, topography.heights, topography.lx, topography.ly)
        self.topography = topography
        self.body = body
        self.last: Optional[Result] = None  # the previous solve's Result
        self._warned = False

    def solve(self, *, pressure: Optional[float] = None, force: Optional[float] = None,
              approach: Optional[float] = None, progress: Optional[Callable[[int, int, float], None]] = None,
              warm: bool = True) -> Result:
        """Solves at one load (exactly one of pressure, force, approach), starting from the
        previous solve's solution unless warm=False; returns a Result."""
        result = self._solve_quiet(pressure, force, approach, progress, warm)
        self._warn_once(result, stacklevel=3)
        return result

    def _solve_quiet(self, pressure, force, approach, progress, warm) -> Result:
        kind, value = _one_load("ContactSolver.solve", pressure, force, approach)
        progress, bar = _progress_arg(progress)
        try:
            solution = self._case.solve(kind, value, progress, _flag("warm", warm))
        finally:
            if bar is not None:
                bar.close()
        self.last = Result(solution, self.topography)
        return self.last

    def _warn_once(self, result: Result, stacklevel: int) -> None:
        # A Topography warns once, when made; a solver warns at its first solve otherwise.
        if self._warned or getattr(self.topography, "_warned", False):
            return
        self._warned = True
        for w in result.summary.get("warnings", []):
            warnings.warn(w, UserWarning, stacklevel=stacklevel + 1)

    def reset(self) -> None:
        """Forgets the previous solution: the next solve starts from nothing."""
        self._case.reset()
        self.last = None

    def __repr__(self) -> str:
        return (f"ContactSolver({self.topography!r}, {self.body!r}, "
                f"{'warm' if self._case.warm else 'cold'})")


def load_path(solver: ContactSolver, pressures: Optional[Iterable[float]] = None, *,
              forces: Optional[Iterable[float]] = None, approaches: Optional[Iterable[float]] = None,
              progress=None) -> Iterator[Result]:
    """Solves the loads in order with solver, each from the previous solution; yields one
    Result per load (a generator: stop iterating to stop the path)."""
    if not isinstance(solver, ContactSolver):
        raise InputError(f"solver: must be a gfmd.ContactSolver (got {type(solver).__name__})")
    given = [(k, v) for k, v in (("pressure", pressures), ("force", forces), ("approach", approaches))
             if v is not None]
    if len(given) != 1:
        raise InputError("pressures: give exactly one of pressures, forces, approaches")
    (kind, values), = given
    # A list of loads (a string or a lone number is not: a string would be walked character by
    # character).
    if isinstance(values, (str, bytes, numbers.Real)) or not isinstance(values, Iterable):
        name = {"pressure": "pressures", "force": "forces", "approach": "approaches"}[kind]
        raise InputError(f"{name}: a list of numbers, e.g. {name}=[0.01, 0.02] (got {values!r})")
    for v in values:
        yield solver.solve(**{kind: v}, progress=progress)


def solve(topography: Topography, body: Optional[ElasticBody] = None, *, pressure: Optional[float] = None,
          force: Optional[float] = None, approach: Optional[float] = None, friction: float = 0.0,
          direction: float = 0.0, interaction="harmonic", hardness: float = math.inf,
          stress_depths: Iterable[float] = (), progress: Optional[Callable[[int, int, float], None]] = None,
          indenter_body: Optional[ElasticBody] = None, stiffness: float = 0.0, **options) -> Result:
    """Presses (and, with friction > 0, slides) the topography on the body; returns a Result.

    Exactly one of pressure (mean, E*), force (E* L^2) or approach (L). friction: the local
    Coulomb coefficient mu_c; direction: sliding direction in degrees from x. interaction:
    "harmonic" (default), "hardwall" or gfmd.Adhesive(work_of_adhesion, range). hardness: the
    plastic cap H of the local pressure (interaction.hardness; inf: none). stiffness: the harmonic
    repulsion's k_if (interaction.stiffness, E*/L; 0: 2E*/dx). indenter_body: an
    elastic indenter (a gfmd.ElasticBody, coated or layered too; two deformable bodies, sliding
    or rolling; its stresses in summary["indenter_stress"]), rigid when None. options: the
    [solver] keys (tolerance, max_iterations, max_outer, max_tangential, anderson, mixing,
    threads, fft_planner, backend, viscoelastic_method) and the [friction] keys (regularization,
    creepage, lateral_creepage, slip_derivative, stick_step, stick_acceleration, reference, law and
    the law's keys: gfmd.friction_laws(); velocity: a gfmd.ViscoelasticBody's sliding speed v0). progress(iteration, friction_step, change) is called about every
    0.2 s; progress=True shows a tqdm bar (plain lines without tqdm). Ctrl-C raises KeyboardInterrupt within an iteration. The same case through
    gfmd.run or `gfmd run` gives the same numbers. One solve of a ContactSolver: to solve
    several loads, each from the last, keep a ContactSolver (or use gfmd.load_path).
    """
    if not isinstance(topography, Topography):
        raise InputError(f"topography: must be a gfmd.Topography (got {type(topography).__name__})")
    if body is not None and not isinstance(body, ElasticBody):
        raise InputError(f"body: must be a gfmd.ElasticBody (got {type(body).__name__})")
    _one_load("gfmd.solve", pressure, force, approach)
    _progress_arg(progress if progress is not True else None)
    solver = ContactSolver(topography, body, friction=friction, direction=direction, interaction=interaction,
                           hardness=hardness, stress_depths=stress_depths, indenter_body=indenter_body,
                           stiffness=stiffness, **options)
    result = solver._solve_quiet(pressure, force, approach, progress, True)
    solver._warn_once(result, stacklevel=2)
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


def run(case: str, set: Iterable[str] = (), output: str = "", force: bool = False, resume: bool = False) -> dict:
    """Solves a case file as `gfmd run` does: {'summary': dict, 'fields': {name: ndarray}}; with
    output, also writes the run directory there (a new or empty directory, or one gfmd made;
    force=True writes into any other, as --force; checked before the solve).
    resume=True (needs output) is `gfmd run --resume`: a finished result of the same case in
    output is reused and nothing is solved, an interrupted one continues from its checkpoint
    (written every minute); returns {'summary': dict, 'status': 'solved' or 'reused'}, the
    fields staying in output/fields.nc. SolveError where the solve does not converge (nothing is
    published; status.json says why), KeyboardInterrupt on Ctrl-C (with output, with or without
    resume, status.json says "interrupted" and the checkpoint is kept: resume=True continues)."""
    if _flag("resume", resume):
        if not output:
            raise InputError("resume: needs output (the run directory to reuse or continue)")
        return _core.run_directory(str(case), _sets(set), str(output), True, _flag("force", force))
    if output:
        # Into its directory as `gfmd run -o` (checkpoints, status.json), returning the fields too.
        return _core.run_directory(str(case), _sets(set), str(output), False, _flag("force", force), fields=True)
    return _core.run(str(case), _sets(set), "", _flag("force", force))


def run_toml(toml: str, set: Iterable[str] = ()) -> dict:
    """As run(), for a case given as TOML text."""
    return _core.run_toml(toml, _sets(set))
