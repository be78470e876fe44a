"""Studies over case files (the same C++ studies as the command line): sweep, percolation,
curve, ensemble, figure studies."""
from __future__ import annotations

import json
import os
from typing import Iterable, Optional

from . import _core
from ._core import InputError, SolveError
from ._checks import _count, _flag, _positive, _sets


def sweep(case: str, parameter: Optional[str] = None, values: Optional[Iterable[float]] = None,
          output: str = "", set: Iterable[str] = (), plot: Optional[str] = None, force: bool = False) -> dict:
    """A load sweep as `gfmd sweep CASE --set parameter=v1,v2,...`: points solved in order, each
    warm-started from the previous one, into output/point_NNN/; returns sweep.json (one row of
    scalar summary keys per point). Points already solved with the same input are reused.
    parameter and values both None: the case's own [sweep] table (as `gfmd sweep CASE`).
    plot: a column (summary key) to draw against the parameter into output/sweep_<plot>.png, as
    `gfmd sweep --plot` does (InputError if the summaries have no such column). The points'
    maps are drawn where the case asks for them (output.png), as by the command line."""
    if not output:
        raise InputError("output: give the sweep's directory")
    if (parameter is None) != (values is None):
        raise InputError("values: give a parameter with its values, or neither (the case's [sweep])")
    if parameter is None:
        parameter, vals = "", []
    else:
        try:
            vals = [float(v) for v in values]
        except (TypeError, ValueError):
            raise InputError(f"values: a list of numbers (got {values!r})") from None
        if not isinstance(parameter, str) or "." not in parameter:
            raise InputError(f"parameter: a config key section.key (got {parameter!r})")
    if plot is not None and (not isinstance(plot, str) or not plot):
        raise InputError(f"plot: a summary key such as 'friction_coefficient' (got {plot!r})")
    _core.sweep_case(str(case), parameter, vals, _sets(set), str(output), plot or "", _flag("force", force))
    with open(os.path.join(str(output), "sweep.json")) as f:
        return json.load(f)


def green(poisson: Iterable[float] = (0.0, 0.25, 0.49), qh_from: float = 1e-2, qh_to: float = 1e2,
          points: int = 121, output: str = "", force: bool = False) -> list:
    """The dimensionless Green's tensor of a layer on a rigid base (SPEC §2, q along axis 1) as
    `gfmd green`: `points` values of qh, log spaced from qh_from to qh_to, per Poisson ratio.
    Returns the rows as dicts of floats (poisson, qh, phi11, phi22, phi33, im_phi13); output: also
    the CSV file there (written whole or not at all; an existing file that is not such a table is
    kept and InputError raised, unless force=True)."""
    try:
        nus = [float(v) for v in poisson]
    except (TypeError, ValueError):
        raise InputError(f"poisson: a list of Poisson ratios (got {poisson!r})") from None
    lo = _positive("qh_from", qh_from)
    hi = _positive("qh_to", qh_to)
    if not hi > lo:
        raise InputError(f"qh_to: must exceed qh_from (got {qh_to!r} <= {qh_from!r})")
    text = _core.green_table(nus, lo, hi, _count("points", points), str(output), _flag("force", force))
    lines = text.strip().splitlines()
    names = lines[0].split(",")
    return [dict(zip(names, (float(x) for x in ln.split(",")))) for ln in lines[1:]]


def percolation(case: str, direction: str = "x", set: Iterable[str] = (), area_tolerance: float = 0.002,
                output: str = "", force: bool = False) -> dict:
    """The critical relative contact area at which flow along direction ("x" or "y") stops, as
    `gfmd percolation`; returns percolation.json's contents (and writes it into output if given)."""
    return _core.percolation_case(str(case), str(direction), _sets(set), _positive("area_tolerance", area_tolerance),
                                  str(output), _flag("force", force))


def curve(case: str, pressures=None, output: str = "", set: Iterable[str] = (), force: bool = False, *,
          approaches=None, unload: bool = False) -> dict:
    """Load curves as `gfmd curve`: the case solved at each mean pressure (/E*, sorted, warm
    started, leakage on) into output/points/; writes output/curve.csv and curve.json (and the
    figure curve.png where the case asks for figures, output.png) and returns curve.json (rows under "points",
    the percolation threshold under "percolation"). approaches=[...] instead of pressures: an
    approach path in the order given (gfmd curve --approaches), unload=True going back through
    it (--unload); curve.json then has "pull_off_force" (adhesion: the most tensile force).
    Either list may also be the command line's text ("V1,V2,..." or "FROM:TO:N")."""
    if (pressures is None) == (approaches is None):
        raise InputError("pressures: give one of pressures and approaches")
    name = "pressures" if approaches is None else "approaches"
    values = pressures if approaches is None else approaches
    if isinstance(values, str):  # as the command line's option: "V1,V2,..." or "FROM:TO:N"
        vs = (_core.parse_pressures if approaches is None else _core.parse_approaches)(values)
    else:
        try:
            vs = [float(p) for p in values]
        except (TypeError, ValueError):
            raise InputError(f"{name}: a list of numbers (got {values!r})") from None
    if not output:
        raise InputError("output: give the curve's directory")
    if unload and approaches is None:
        raise InputError("unload: only with approaches (an approach path)")
    return _core.curve_case(str(case), vs, _sets(set), str(output), _flag("force", force), approaches is not None,
                            _flag("unload", unload))


def ensemble(case: str, output: str, seeds=(0, 7), set: Iterable[str] = (), force: bool = False) -> dict:
    """Flow over roughness seeds seeds[0]..seeds[1] (inclusive) as `gfmd ensemble --seeds A..B`,
    into output/seed_N/; returns ensemble.json (per seed, mean, spread, Bruggeman value)."""
    try:
        first, last = (int(seeds[0]), int(seeds[1]))
    except (TypeError, ValueError, IndexError):
        raise InputError(f"seeds: (first, last) integers (got {seeds!r})") from None
    return _core.ensemble_case(str(case), first, last, _sets(set), str(output), _flag("force", force))


def _package_file(*parts: str) -> str:
    """A file shipped with the package (installed: gfmd/bin/gfmd) or, in the build tree
    (build/python/gfmd), the build's. "" if absent."""
    here = os.path.dirname(os.path.abspath(__file__))
    for base in (here, os.path.dirname(os.path.dirname(here))):
        path = os.path.join(base, *parts)
        if os.path.exists(path):
            return path
    return ""


def _study_driver():
    """scripts/study.py of this package (installed: gfmd/share/gfmd/scripts; in the build tree,
    the build's), imported once; its folder goes on sys.path for its own modules."""
    import importlib.util
    import sys

    name = "gfmd._study_driver"
    if name in sys.modules:
        return sys.modules[name]
    path = _package_file("share", "gfmd", "scripts", "study.py")
    if not path:
        raise InputError("study: the study scripts (share/gfmd/scripts/study.py) are not installed with the package")
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)  # inserts its folder in sys.path (study_file, study_runs, ...)
    sys.modules[name] = module
    return module


def study(study_file: str, quick: bool = False, output: str = os.path.join("out", "studies"),
          set: Iterable[str] = (), draw_only: bool = False, runs_only: bool = False) -> dict:
    """Runs a figure study (studies/*.toml) as `gfmd study` does: its sweeps or runs (reusing
    finished results), then its figure (PNG, PDF) and the plotted data (CSV) in
    output/<name>/<quick|full>/. Returns study.json (figure path, series, wall time, series
    that stopped early). The study's case paths are relative to the folder above the study
    file's (the repository root for studies/*.toml). Raises SolveError if a series stopped
    early (its finished points are drawn), InputError (a ValueError) for a missing or malformed
    study file or a case file given as a study, naming the file and the key. `set`: settings
    for every run of the study, after its own (e.g. 'solver.backend="cuda"'). `draw_only`: draw a
    sweep study from the runs on disk and run nothing (gfmd study --draw-only: a point that did not
    converge is not retried, a series or seed without runs is left out). `runs_only`: run (or
    reuse) every series and draw nothing (gfmd study --runs-only; no figure, and study.json is
    not written: returns {"study": name, "runs": the output folder}).
    It runs in this process: the runs are this package's (gfmd.run, sweep, curve, ...), the
    figures are drawn on figures of their own (the process's matplotlib backend is not touched);
    progress and where the results went are printed to standard error. KeyboardInterrupt (Ctrl-C,
    or a notebook's interrupt) stops the run in progress, removes the study's temporary files
    and is raised again; the finished runs are reused by the next call."""
    import sys

    path = os.path.abspath(str(study_file))
    if not os.path.isfile(path):
        raise InputError(f"study_file: {study_file}: no such file")
    if draw_only and runs_only:
        raise InputError("runs_only: draw_only and runs_only exclude each other")
    argv = [path, "-o", str(output)] + (["--quick"] if quick else [])
    if draw_only:
        argv.append("--draw-only")
    if runs_only:
        argv.append("--runs-only")
    for kv in set:
        argv += ["--set", str(kv)]
    driver = _study_driver()
    program = _package_file("bin", "gfmd") or _package_file("gfmd")
    try:
        code = driver.main(argv, library=sys.modules[__package__], program=program or None)
    except SystemExit as e:  # the driver's fail(): a run that did not converge (3), another error (1)
        code = e.code if isinstance(e.code, int) else 1
    last = (driver.study_runs.LAST_LOG or [f"exit status {code}"])[-1]
    name = os.path.splitext(os.path.basename(path))[0]
    if code == 4:  # interrupted
        raise KeyboardInterrupt(f"study {name} interrupted; the same call continues it")
    if code == 2:  # bad input: the study file, a setting
        raise InputError(last[len("gfmd study: "):] if last.startswith("gfmd study: ") else last)
    if code != 0:
        raise SolveError(f"study {name}: {last}")
    report = os.path.join(str(output), name, "quick" if quick else "full", "study.json")
    if runs_only:
        return {"study": name, "runs": os.path.dirname(report)}
    with open(report) as f:
        return json.load(f)
