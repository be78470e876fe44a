"""The Python package's API (gfmd.Topography, ElasticBody, solve, Result): values against closed
forms, the same numbers as case files and the command line, bad input, progress and Ctrl-C."""
import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import gfmd

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
# The children wait passively, without a GOMP_SPINCOUNT of the caller's: libgomp lets it override
# the policy (importing gfmd left one in this process's environment until 2026-12-07; with 3
# processes on 2 cores their spinning threads made an MPI test take 37 s instead of 3 s).
ENV = dict({k: v for k, v in os.environ.items() if k != "GOMP_SPINCOUNT"},
           OMP_WAIT_POLICY="PASSIVE", PYTHONPATH=os.path.join(BUILD, "python"))

HERTZ_TOML = """[grid]
nx = 128
lx = 1.6
[elastic]
poisson = 0.3
thickness = 0.4
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[friction]
coefficient = 0.5
[output]
png = false
"""


def hertz_case():
    return (gfmd.Topography.hertz(nx=128, lx=1.6, radius=1.0), gfmd.ElasticBody(poisson=0.3, thickness=0.4))


# --- topographies ------------------------------------------------------------------------

def test_hertz_topography_is_the_paraboloid():
    t = gfmd.Topography.hertz(nx=64, lx=2.0, radius=0.5, ny=32, ly=1.0)
    assert t.shape == (32, 64) and t.nx == 64 and t.ny == 32 and t.kind == "hertz"
    h = t.heights
    assert h.max() == 0.0 and h[16, 32] == 0.0  # apex on node (nx/2, ny/2)
    dx = 2.0 / 64
    assert h[16, 32 + 5] == pytest.approx(-(5 * dx) ** 2 / (2 * 0.5), rel=1e-14)
    assert not h.flags.writeable


def test_eggcrate_peak_and_default_amplitude():
    t = gfmd.Topography.eggcrate(nx=64, lx=1.0, wavelength=0.5)
    a = 0.5 / (4 * math.pi ** 2)  # peak radius of curvature = wavelength (SPEC §3)
    assert t.heights.max() == pytest.approx(2 * a, rel=1e-12)
    with pytest.raises(gfmd.InputError, match="wavelength"):
        gfmd.Topography.eggcrate(nx=64, lx=1.0, wavelength=0.3)


def test_self_affine_statistics_seed_and_spectrum():
    kw = dict(nx=256, lx=1.0, hurst=0.7, lambda_long=0.5, lambda_short=1 / 32, rms_height=0.01)
    t = gfmd.Topography.self_affine(seed=3, **kw)
    assert t.rms_height() == pytest.approx(0.01, rel=1e-12)
    assert np.array_equal(t.heights, gfmd.Topography.self_affine(seed=3, **kw).heights)
    assert not np.array_equal(t.heights, gfmd.Topography.self_affine(seed=4, **kw).heights)
    g = gfmd.Topography.self_affine(nx=256, lx=1.0, rms_gradient=0.1, lambda_short=1 / 32)
    assert g.rms_gradient() == pytest.approx(0.1, rel=1e-12)
    # C(q) ~ q^(-2-2H) inside the band: fitted slope within 0.15 of -3.4
    q, c = t.psd(bins=40)
    band = (q > 2 * math.pi / 0.5 * 1.3) & (q < 2 * math.pi * 32 / 1.3)
    slope = np.polyfit(np.log(q[band]), np.log(c[band]), 1)[0]
    assert slope == pytest.approx(-2 - 2 * 0.7, abs=0.15)
    # The same numbers as an independent numpy evaluation of the definition (full complex
    # transform, logarithmic bins between the smallest and largest |q|, geometric centres).
    h = t.heights
    spec = np.fft.fft2(h - h.mean())
    qq = 2 * math.pi * np.fft.fftfreq(256, d=1 / 256)
    qm = np.hypot(*np.meshgrid(qq, qq))
    cm = 1.0 / (2 * math.pi) ** 2 * np.abs(spec) ** 2 / 256 ** 4
    on = qm > 0
    edges = np.geomspace(qm[on].min(), qm[on].max() * (1 + 1e-12), 41)
    idx = np.digitize(qm[on], edges) - 1
    sums, counts = np.bincount(idx, weights=cm[on], minlength=40)[:40], np.bincount(idx, minlength=40)[:40]
    keep = counts > 0
    np.testing.assert_allclose(q, np.sqrt(edges[:-1] * edges[1:])[keep], rtol=1e-12)
    np.testing.assert_allclose(c, sums[keep] / counts[keep], rtol=1e-9, atol=1e-12 * c.max())  # zero bands: round-off
    with pytest.raises(gfmd.InputError, match="bins"):
        t.psd(bins=0)


def test_from_array_converts_or_refuses_naming_the_argument():
    ints = np.arange(12, dtype=np.int32).reshape(3, 4)
    t = gfmd.Topography.from_array(ints, lx=2.0)
    assert t.heights.dtype == np.float64 and t.ly == pytest.approx(1.5)
    mine = np.zeros((4, 4))
    gfmd.Topography.from_array(mine, 1.0)
    assert mine.flags.writeable  # the caller's array is left as it was
    base = np.random.default_rng(0).random((8, 16))
    view = base[:, ::2]  # not C-contiguous
    assert np.array_equal(gfmd.Topography.from_array(view, 1.0).heights, view)
    for bad, what in [(np.array([[1.0, np.nan], [0, 0]]), "non-finite"), (np.zeros(5), "2-D"),
                      (np.zeros((3, 3), dtype=complex), "real"), (np.zeros((1, 4)), "2 x 2"),
                      (np.array([["a", "b"], ["c", "d"]]), "real")]:
        with pytest.raises(gfmd.InputError, match="heights") as e:
            gfmd.Topography.from_array(bad, 1.0)
        assert what in str(e.value)
    for lx in (0.0, -1.0, float("inf"), "1"):
        with pytest.raises(gfmd.InputError, match="lx"):
            gfmd.Topography.from_array(np.zeros((4, 4)), lx)
    with pytest.raises(gfmd.InputError, match="radius"):
        gfmd.Topography.hertz(nx=64, lx=1.0, radius=-1.0)
    with pytest.raises(gfmd.InputError, match="nx"):
        gfmd.Topography.hertz(nx=1, lx=1.0, radius=1.0)
    with pytest.raises(gfmd.InputError, match="lambda_long"):  # from the library: names the parameter
        gfmd.Topography.self_affine(nx=64, lx=1.0, lambda_long=2.0, rms_height=0.01)


def test_read_a_text_height_map(tmp_path):
    h = np.random.default_rng(1).random((6, 8))
    path = tmp_path / "h.txt"
    np.savetxt(path, h, fmt="%.17g")
    t = gfmd.Topography.read(path, lx=2.0, ly=1.5)
    assert np.array_equal(t.heights, h) and (t.lx, t.ly) == (2.0, 1.5) and t.kind == "file"
    with pytest.raises(gfmd.InputError, match="nothere"):
        gfmd.Topography.read(tmp_path / "nothere.txt", lx=1.0)


# --- solve and Result --------------------------------------------------------------------

def strip(summary):
    s = {k: v for k, v in summary.items() if "time" not in k and k != "input"}
    return s


def test_solve_equals_the_case_file_and_fields_are_views():
    top, body = hertz_case()
    r = gfmd.solve(top, body, force=0.01, friction=0.5)
    ref = gfmd.run_toml(HERTZ_TOML)
    for k, v in strip(ref["summary"]).items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            assert r.summary[k] == v, k  # same numbers, bit for bit
    assert r.summary["input"]["indenter"]["type"] == "array"
    assert np.array_equal(r.pressure, ref["fields"]["pressure"])
    assert np.array_equal(r["traction_x"], ref["fields"]["traction_x"])
    # run / run_toml return every field of fields.nc too (copies), with the same numbers
    assert set(ref["fields"]) == set(r.field_names)
    for name in r.field_names:
        assert np.array_equal(r[name], ref["fields"][name]), name
    # every field of fields.nc, read-only views of the result (no copies)
    for name in ["topography", "pressure", "gap", "ux", "uy", "uz", "contact", "traction_x", "traction_y",
                 "slip_longitudinal", "slip_transverse", "dissipation", "sigma_1", "von_mises"]:
        assert name in r.field_names
    a, b = r.pressure, r.fields["pressure"]
    assert np.shares_memory(a, b) and not a.flags.writeable and a.shape == (128, 128)
    desc, units = r.field_info("pressure")
    assert units == "E*" and "pressure" in desc
    with pytest.raises(AttributeError):
        r.no_such_field
    del r
    assert a.sum() > 0  # the view keeps the result alive


def test_save_writes_what_gfmd_run_writes_and_flow_matches_the_cli(tmp_path):
    top, body = hertz_case()
    r = gfmd.solve(top, body, force=0.01, friction=0.5)
    d = tmp_path / "run"
    r.save(str(d))
    with open(d / "summary.json") as f:
        saved = json.load(f)
    assert saved["friction_coefficient"] == r.summary["friction_coefficient"]
    assert (d / "fields.nc").is_file()
    assert not (d / "pressure.png").exists()  # maps only when asked for
    r.save(str(tmp_path / "drawn"), png=True)  # ... as gfmd run draws them
    for png in ("pressure.png", "gap.png", "slip_longitudinal.png", "profiles.png"):
        assert (tmp_path / "drawn" / png).stat().st_size > 1000, png
    fl = r.flow(("x", "y"))
    p = subprocess.run([os.path.join(BUILD, "gfmd"), "flow", str(d)], capture_output=True, text=True, env=ENV)
    assert p.returncode == 0, p.stderr
    with open(d / "flow.json") as f:
        cli = json.load(f)
    for k in ("flow_factor_x", "flow_factor_y", "conductivity_x", "mean_gap"):
        assert fl["summary"][k] == pytest.approx(cli[k], rel=1e-12), k
    assert fl["fields"]["current_x"].shape == (128, 128)
    with pytest.raises(gfmd.InputError, match="directions"):
        r.flow(("z",))


def test_rough_layer_with_depths_and_options():
    t = gfmd.Topography.self_affine(nx=64, lx=1.0, lambda_long=0.5, lambda_short=1 / 16, rms_height=0.01)
    r = gfmd.solve(t, gfmd.ElasticBody(poisson=0.49, thickness=0.1), pressure=0.02, friction=1.0,
                   stress_depths=[0.01], tolerance=1e-9, backend="serial", threads=1)
    s = r.summary
    assert s["converged"] and s["mean_pressure"] == pytest.approx(0.02, rel=1e-12)
    assert s["subsurface"][0]["depth"] == 0.01 and "von_mises_depth_0" in r.field_names
    assert s["backend"] == "serial"


def test_bad_arguments_name_themselves():
    top, body = hertz_case()
    cases = [(dict(force=0.01, frobnicate=1), "frobnicate"), (dict(), "pressure"),
             (dict(force=0.01, pressure=0.1), "pressure"), (dict(force=0.01, friction=float("nan")), "friction"),
             (dict(force=0.01, tolerance="tight"), "tolerance"), (dict(force=-1.0), "load.force")]
    for kw, what in cases:
        with pytest.raises(gfmd.InputError, match=what) as err:
            gfmd.solve(top, body, **kw)
        assert "<gfmd.solve>" not in str(err.value)  # no line numbers of the generated case text
    with pytest.raises(gfmd.InputError, match="topography"):
        gfmd.solve(np.zeros((4, 4)), body, force=0.01)
    with pytest.raises(gfmd.InputError, match="poisson"):
        gfmd.solve(top, gfmd.ElasticBody(poisson=0.7), force=0.01)
    # The body is checked when it is made, as [elastic] is (not only when a solve uses it).
    for kw, what in [(dict(poisson=0.6), "ElasticBody.poisson"), (dict(thickness=-1.0), "ElasticBody.thickness"),
                     (dict(poisson=0.5, thickness=0.1), "ElasticBody.poisson.*singular"),
                     (dict(contact_modulus=0.0), "ElasticBody.contact_modulus"),
                     (dict(thickness="thin"), "ElasticBody.thickness: must be a number"),
                     (dict(coupling=1), "ElasticBody.coupling")]:
        with pytest.raises(gfmd.InputError, match=what):
            gfmd.ElasticBody(**kw)
    assert gfmd.ElasticBody(poisson=0.5).thickness == float("inf")  # incompressible half-space: fine
    with pytest.raises(gfmd.SolveError):
        gfmd.solve(top, body, force=0.01, max_iterations=2)


def test_progress_callback_and_its_exception():
    t = gfmd.Topography.self_affine(nx=256, lx=1.0, lambda_long=0.5, lambda_short=1 / 32, rms_height=0.01)
    body = gfmd.ElasticBody(poisson=0.49, thickness=0.05)
    calls = []
    gfmd.solve(t, body, pressure=0.05, friction=1.0, progress=lambda *a: calls.append(a))
    assert calls and all(len(c) == 3 for c in calls)

    def boom(*_):
        raise ValueError("stop here")

    with pytest.raises(ValueError, match="stop here"):
        gfmd.solve(t, body, pressure=0.05, friction=1.0, progress=boom)
    r = gfmd.solve(t, body, pressure=0.05, friction=1.0, progress=True)  # a bar (tqdm) or lines
    assert r.summary["converged"]
    with pytest.raises(gfmd.InputError, match="progress"):
        gfmd.solve(t, body, pressure=0.05, progress="yes")


def test_ctrl_c_raises_keyboard_interrupt_quickly():
    code = ("import gfmd, sys, time\n"
            "t = gfmd.Topography.self_affine(nx=1024, lx=1.0, lambda_long=0.5, lambda_short=1/256, rms_height=0.01)\n"
            "print('ready', flush=True)\n"
            "try:\n"
            "    gfmd.solve(t, gfmd.ElasticBody(poisson=0.49, thickness=0.05), pressure=0.05, friction=1.0)\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted', flush=True); sys.exit(7)\n")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, env=ENV)
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    t0 = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 7, out
    assert "interrupted" in out
    assert time.monotonic() - t0 < 5.0


def test_openmp_spin_is_bounded_unless_the_user_chose_a_policy(tmp_path):
    # The package sets GOMP_SPINCOUNT to the command line's value before its core loads libgomp,
    # and a run's summary records it; then it takes it out of the environment again, so that the
    # programs the script starts do not inherit it (it overrode their OMP_WAIT_POLICY: MPI tests
    # with passive children spun). A policy the user set is left alone.
    code = ("import os, json, subprocess, sys, gfmd\n"
            "assert os.environ.get('GOMP_SPINCOUNT') is None, os.environ.get('GOMP_SPINCOUNT')\n"
            "child = subprocess.run([sys.executable, '-c', 'import os; print(os.environ.get(\"GOMP_SPINCOUNT\"))'],\n"
            "                       capture_output=True, text=True).stdout.strip()\n"
            "assert child == 'None', child\n"
            "r = gfmd.solve(gfmd.Topography.hertz(nx=32, lx=1.0, radius=1.0), gfmd.ElasticBody(), pressure=0.01)\n"
            "print(r.summary['omp_wait'])\n")
    env = {k: v for k, v in ENV.items() if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")}
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "GOMP_SPINCOUNT=" + gfmd._core.spin_count
    p = subprocess.run([sys.executable, "-c", "import os, gfmd; print(os.environ.get('GOMP_SPINCOUNT'))"],
                       capture_output=True, text=True, env=dict(env, OMP_WAIT_POLICY="active"))
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "None"


def test_python_m_gfmd_is_the_program():
    exe = os.path.join(BUILD, "gfmd")
    a = subprocess.run([exe, "--version"], capture_output=True, text=True, env=ENV)
    b = subprocess.run([sys.executable, "-m", "gfmd", "--version"], capture_output=True, text=True, env=ENV)
    assert b.returncode == 0, b.stderr
    assert a.stdout == b.stdout and a.stdout.strip()


def test_the_tutorial_runs_top_to_bottom(tmp_path):
    script = os.path.join(ROOT, "examples", "python", "tutorial.py")
    p = subprocess.run([sys.executable, script], cwd=tmp_path, capture_output=True, text=True, env=ENV, timeout=600)
    assert p.returncode == 0, p.stderr[-3000:]
    out = tmp_path / "out" / "tutorial"
    for f in ("hertz_pressure.png", "rough_psd.png", "rough_dissipation.png", "rough_sigma1.png",
              "rough_current.png", "rough_run/summary.json"):
        assert (out / f).is_file(), f
    # Hertz contact radius within 3 % of (3FR/4E*)^(1/3) at a/dx = 32
    line = next(l for l in p.stdout.splitlines() if l.startswith("contact radius"))
    num, ref = float(line.split()[3].rstrip(",")), float(line.split()[5])
    assert abs(num / ref - 1) < 0.03, line


ROUGH_TOML = """[grid]
nx = 64
lx = 1.0
[elastic]
poisson = 0.3
[indenter]
type = "selfaffine"
hurst = 0.8
lambda_long = 0.5
lambda_short = 0.0625
rms_height = 0.01
seed = 2
[load]
pressure = 0.05
[output]
png = false
"""


def cli(*args):
    p = subprocess.run([os.path.join(BUILD, "gfmd"), *args], capture_output=True, text=True, env=ENV)
    assert p.returncode == 0, p.stderr
    return p


def numbers_equal(a, b, skip=("time", "seconds", "elapsed", "omp_wait")):
    """Recursively: the same keys and the same numbers, except timings and how threads waited."""
    if isinstance(a, dict):
        assert set(a) == set(b)
        for k in a:
            if not any(s in k for s in skip):
                numbers_equal(a[k], b[k], skip)
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            numbers_equal(x, y, skip)
    else:
        assert a == b


def test_sweep_percolation_ensemble_match_the_cli(tmp_path):
    case = tmp_path / "rough.toml"
    case.write_text(ROUGH_TOML)
    # sweep: the same sweep.json as gfmd sweep
    py = gfmd.sweep(str(case), "load.pressure", [0.02, 0.05], output=str(tmp_path / "py_sweep"),
                    plot="relative_contact_area")
    assert (tmp_path / "py_sweep" / "sweep_relative_contact_area.png").stat().st_size > 1000
    with pytest.raises(gfmd.InputError, match="no column 'area'"):  # the finished points are reused
        gfmd.sweep(str(case), "load.pressure", [0.02, 0.05], output=str(tmp_path / "py_sweep"), plot="area")
    cli("sweep", str(case), "--set", "load.pressure=0.02,0.05", "-o", str(tmp_path / "cli_sweep"), "-q")
    with open(tmp_path / "cli_sweep" / "sweep.json") as f:
        numbers_equal(py, json.load(f))
    # percolation along x
    py = gfmd.percolation(str(case), "x")
    cli("percolation", str(case), "--direction", "x", "-o", str(tmp_path / "cli_perc"), "-q")
    with open(tmp_path / "cli_perc" / "percolation.json") as f:
        numbers_equal(py, json.load(f))
    assert 0 < py["critical_relative_contact_area"] < 1
    # ensemble over two seeds
    py = gfmd.ensemble(str(case), output=str(tmp_path / "py_ens"), seeds=(0, 1))
    cli("ensemble", str(case), "--seeds", "0..1", "-o", str(tmp_path / "cli_ens"), "-q")
    with open(tmp_path / "cli_ens" / "ensemble.json") as f:
        numbers_equal(py, json.load(f))
    with pytest.raises(gfmd.InputError, match="direction"):
        gfmd.percolation(str(case), "z")
    with pytest.raises(gfmd.InputError, match="seeds"):
        gfmd.ensemble(str(case), output=str(tmp_path / "e2"), seeds=(3,))


def test_study_matches_gfmd_study(tmp_path, monkeypatch):
    # A small sweep study (Hertz, two loads at 64^2) through gfmd.study and through `gfmd study`:
    # the same plotted data; a missing file is an InputError.
    case = tmp_path / "case.toml"
    case.write_text(open(os.path.join(ROOT, "examples", "hertz_nu025.toml")).read()
                    + "\n[sweep]\nparameter = \"load.force\"\nvalues = [0.005, 0.01]\n"
                    + "plot = \"relative_contact_area\"\n")
    st = tmp_path / "small.toml"
    st.write_text(f'title = "small"\nkind = "sweep"\nx = "load.force"\ny = "relative_contact_area"\n\n'
                  f'[[series]]\nlabel = "s"\ncase = "{case}"\n\n[quick]\nset = ["grid.nx=64"]\n')
    # gfmd.study runs the study in this process (issue 43: a figure study is one process through
    # the library): it does not start gfmd (the runs are gfmd.sweep's, in process; drawing the
    # sweep's own plot may start a plotting script), and its figure is drawn without pyplot, so
    # the process's matplotlib backend stays what it was.
    import matplotlib

    started = []
    popen = subprocess.Popen

    def record(args, *a, **k):
        started.append(list(args) if not isinstance(args, str) else [args])
        return popen(args, *a, **k)

    monkeypatch.setattr(subprocess, "Popen", record)
    try:
        matplotlib.use("svg")
        rep = gfmd.study(str(st), quick=True, output=str(tmp_path / "py"))
        assert matplotlib.get_backend() == "svg"
    finally:
        matplotlib.use("agg")  # these tests run headless
    assert not [a for a in started if os.path.basename(a[0]) == "gfmd"], started
    assert started, "the sweep's plot is drawn by a plotting script (plot_maps.py)"
    assert rep["series"] == ["s"] and not rep["incomplete_series"]
    monkeypatch.undo()
    cli("study", str(st), "--quick", "-o", str(tmp_path / "cli"))
    py_csv = (tmp_path / "py" / "small" / "quick" / "small.csv").read_text()
    cli_csv = (tmp_path / "cli" / "small" / "quick" / "small.csv").read_text()
    assert py_csv == cli_csv and len(py_csv.splitlines()) == 3
    assert os.path.isfile(rep["figure"])
    # A setting for every run (--set / set=): it reaches each run's input, and the runs of
    # the same settings are reused by the other front end.
    rep = gfmd.study(str(st), quick=True, output=str(tmp_path / "set"), set=["solver.tolerance=1e-7"])
    point = tmp_path / "set" / "small" / "quick" / "series_00" / "point_001" / "summary.json"
    with open(point) as f:
        assert json.load(f)["input"]["solver"]["tolerance"] == 1e-7
    before = os.stat(point).st_mtime_ns
    cli("study", str(st), "--quick", "-o", str(tmp_path / "set"), "--set", "solver.tolerance=1e-7")
    assert os.stat(point).st_mtime_ns == before
    cli("study", str(st), "--quick", "-o", str(tmp_path / "set"), "--set", "solver.tolerance=1e-9")
    with open(point) as f:
        assert json.load(f)["input"]["solver"]["tolerance"] == 1e-9
    with pytest.raises(gfmd.InputError, match="no such file"):
        gfmd.study(str(tmp_path / "nothere.toml"))
