"""The Python API: topographies as values, elastic bodies, solve() and its Result.

The code lives in _checks (argument checks), _topography (Topography), _result (Result),
_solve (ElasticBody, solve, run, run_toml) and _studies (sweep, percolation, curve, ensemble,
study); this module re-exports their names where they have always been reachable.
"""
from __future__ import annotations

from . import _core
from ._core import InputError, SolveError
from ._checks import _count, _flag, _heights, _positive, _warn_implausible
from ._result import Result
from ._solve import (_FRICTION_KEYS, _SOLVER_KEYS, Adhesive, ContactSolver, ElasticBody, ViscoelasticBody, ViscoelasticPart, _progress_bar, load_path,
                     run, run_toml, solve)
from ._studies import _package_file, curve, ensemble, green, percolation, study, sweep
from ._topography import Topography


def friction_laws() -> list:
    """The friction laws (friction.law; gfmd.solve(..., law=..., and its keys)): [{'name', 'purpose',
    'keys', 'set_valued_stick', 'on_device'}]; set_valued_stick False: the law needs regularization > 0 (none of today's)."""
    return _core.friction_laws()


def body_types() -> list:
    """The kinds of body under the surface ([{'name', 'purpose', 'keys'}]; keys: the [elastic] keys of
    that kind beside contact_modulus, poisson, thickness and coupling): which one a gfmd.ElasticBody is
    follows from its keys ("layered" with layers or a substrate, "homogeneous" otherwise)."""
    return _core.body_types()


def interaction_models() -> list:
    """The interaction models (interaction.model; gfmd.solve(..., interaction=...)): [{'name', 'purpose',
    'keys', 'repulsion_key', 'on_device'}], in the order the docs list them; a model with keys is
    given as an object (gfmd.Adhesive for "adhesive"), one without by its name."""
    return _core.interaction_models()


def indenter_types() -> list:
    """The indenter types a case file (indenter.type) and Topography.indenter take:
    [{'name', 'purpose', 'keys'}], in the order the docs list them."""
    return _core.indenter_types()

__all__ = [
    "Adhesive", "ContactSolver", "ElasticBody", "ViscoelasticBody", "ViscoelasticPart", "InputError", "Result", "SolveError", "Topography", "_FRICTION_KEYS", "_SOLVER_KEYS",
    "_core", "_count", "_flag", "_heights", "_package_file", "_positive", "_progress_bar",
    "_warn_implausible", "body_types", "curve", "ensemble", "friction_laws", "green", "indenter_types", "interaction_models", "load_path", "percolation", "run", "run_toml", "solve", "study", "sweep",
]
