"""gfmd: steady sliding and rolling contacts with full elastic coupling.

Rigid indenters (Hertz, egg-crate, self-affine rough, measured height maps) pressed on and
sliding over an elastic layer or half-space of any Poisson ratio, with the normal/in-plane
coupling kept (Müller, Müser, Carbone & Menga, PRL 131, 156201, 2023).

Units: lengths in any unit L (that of the topography's lx), pressures and stresses in the unit
of the contact modulus E* (ElasticBody.contact_modulus), forces in E* L^2. Fields are numpy
arrays of shape (ny, nx): row iy is y = iy * ly / ny, column ix is x = ix * lx / nx.

    import gfmd
    top = gfmd.Topography.hertz(nx=256, lx=1.6, radius=1.0)
    body = gfmd.ElasticBody(poisson=0.49, thickness=0.2)
    r = gfmd.solve(top, body, force=0.01, friction=0.5)
    r.summary["friction_coefficient"], r.pressure.shape

Case files work as with the command line: gfmd.run("case.toml", set=["grid.nx=512"]).
"""
import os as _os

# OpenMP threads waiting at a barrier spin 300 000 times by default before they sleep: where
# other programs share the cores that is many times slower (the CLI does the same; README).
# Only effective if this is the first library of the process to load libgomp.
_SET_SPIN = "OMP_WAIT_POLICY" not in _os.environ and "GOMP_SPINCOUNT" not in _os.environ
if _SET_SPIN:
    _os.environ["GOMP_SPINCOUNT"] = "10000"  # = gfmd::kSpinCount, _core.spin_count (tested)

from ._core import InputError, SolveError, __version__  # noqa: E402

# libgomp has read it as the core loaded (and the core has recorded it for summary.json's
# omp_wait): taken out again, so that the programs this process starts get the caller's
# environment (a GOMP_SPINCOUNT overrides their OMP_WAIT_POLICY).
if _SET_SPIN:
    _os.environ.pop("GOMP_SPINCOUNT", None)

from ._api import (Adhesive, ContactSolver, ElasticBody, Result, Topography, body_types, curve, ensemble, friction_laws, green,  # noqa: E402
                   indenter_types, interaction_models, load_path, percolation, run, run_toml, solve, study, sweep, ViscoelasticBody,
                   ViscoelasticPart)

__all__ = [
    "Adhesive",
    "ContactSolver",
    "ElasticBody",
    "InputError",
    "Result",
    "SolveError",
    "Topography",
    "ViscoelasticBody",
    "ViscoelasticPart",
    "__version__",
    "curve",
    "ensemble",
    "body_types",
    "friction_laws",
    "green",
    "indenter_types",
    "interaction_models",
    "load_path",
    "percolation",
    "run",
    "run_toml",
    "solve",
    "study",
    "sweep",
]
