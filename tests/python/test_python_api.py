"""gfmd.run / gfmd.run_toml (case files through Python): results, fields as numpy arrays, errors.
The package comes from the build tree (conftest.py)."""
import os

import numpy as np
import pytest

import gfmd

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

HERTZ = """
[grid]
nx = 128
lx = 1.6
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[output]
png = false
"""


def test_hertz_matches_closed_form_and_cli_summary(tmp_path):
    r = gfmd.run_toml(HERTZ, set=["elastic.poisson=0.3"])
    s, f = r["summary"], r["fields"]
    p = f["pressure"]
    assert p.shape == (128, 128) and p.dtype == np.float64
    # Hertz: p0 = 3F/(2 pi a^2), a = (3FR/4E*)^(1/3), within 2 % at a/dx = 15.7.
    a = (3 * 0.01 / 4) ** (1 / 3)
    assert abs(p.max() / (3 * 0.01 / (2 * np.pi * a * a)) - 1) < 0.02
    assert abs(p.sum() * (1.6 / 128) ** 2 - 0.01) < 1e-12
    assert s["converged"] and s["input"]["elastic"]["poisson"] == 0.3
    # The same case through a file and the output directory gives the same summary numbers.
    case = tmp_path / "case.toml"
    case.write_text(HERTZ)
    r2 = gfmd.run(str(case), set=["elastic.poisson=0.3"], output=str(tmp_path / "out"))
    assert (tmp_path / "out" / "summary.json").exists()
    assert r2["summary"]["max_pressure"] == s["max_pressure"]
    # frictionless: the tractions are there (zeros), the slip fields are not (as in fields.nc)
    assert not f["traction_x"].any() and "slip_longitudinal" not in f and f["contact"].sum() > 0


def test_friction_fields_and_errors():
    r = gfmd.run_toml(HERTZ, set=["friction.coefficient=1", "elastic.poisson=0.25"])
    assert r["summary"]["friction_coefficient"] < 1.0
    assert np.all(r["fields"]["traction_x"] >= 0)
    assert r["fields"]["sigma_1"].max() > 0
    with pytest.raises(gfmd.InputError, match="elastic.poisson"):
        gfmd.run_toml(HERTZ, set=["elastic.poisson=0.7"])
    with pytest.raises(gfmd.SolveError, match="not converged"):
        gfmd.run_toml(HERTZ, set=["solver.max_iterations=2"])


def test_rolling_with_lateral_creepage_and_upwind_derivative():
    # Kalker's small-creepage limit, lateral: nearly all of the contact sticks, F_y > 0, and the
    # upwind derivative's own dissipation closes the energy balance (docs/solver.md).
    t = gfmd.Topography.hertz(64, 1.0, radius=1.0)
    body = gfmd.ElasticBody(poisson=0.5)
    r = gfmd.solve(t, body, force=0.0026041666666666665, friction=0.3, creepage=1e-8, lateral_creepage=1e-4,
                   slip_derivative="upwind2", reference=False)
    s = r.summary
    assert s["stick_fraction"] > 0.95
    assert s["tangential_force_y"] > 100 * abs(s["tangential_force_x"])
    assert s["energy_balance_error_exact"] < 1e-6
    assert s["numerical_dissipation_fraction"] > 0.9
    assert s["input"]["friction"]["slip_derivative"] == "upwind2"
    with pytest.raises(gfmd.InputError, match="friction.slip_derivative"):
        gfmd.solve(t, body, force=0.0026, friction=0.3, slip_derivative="central")


def test_ctrl_c_interrupts_a_solve_within_a_second():
    """SIGINT during a solve raises KeyboardInterrupt promptly (not after the solve) and the
    interpreter goes on. The case (thin nu = 0.49 layer, p = 0.3 E*, 512^2, stick) takes 20 s
    or more; the signal comes after 0.5 s."""
    import signal
    import threading
    import time

    case = os.path.join(ROOT, "examples", "fig2e_rough_layer_sweep.toml")
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    t0 = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        gfmd.run(case, set=["grid.nx=512", "indenter.lambda_short=0.03125", "elastic.thickness=0.05",
                            "load.pressure=0.3", "output.png=false"])
    elapsed = time.monotonic() - t0
    timer.cancel()
    assert elapsed < 3.0, f"KeyboardInterrupt came {elapsed:.1f} s after the start (signal at 0.5 s)"
    # Python's own handler is back: a later solve runs normally.
    assert gfmd.run_toml(HERTZ)["summary"]["converged"]


def test_write_error_raises_and_leaves_no_partial_outputs(tmp_path):
    """A file-size limit makes every write beyond 64 kB fail (EFBIG), as a full disk would:
    OSError naming the file, no summary.json, status failed, and the interpreter (and HDF5)
    still work afterwards."""
    import json
    import resource
    import signal

    old_limit = resource.getrlimit(resource.RLIMIT_FSIZE)
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    out = tmp_path / "out"
    case = tmp_path / "case.toml"
    case.write_text(HERTZ)
    try:
        resource.setrlimit(resource.RLIMIT_FSIZE, (64 * 1024, old_limit[1]))
        with pytest.raises(OSError, match="fields.nc"):
            gfmd.run(str(case), output=str(out))
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, old_limit)
        signal.signal(signal.SIGXFSZ, old_handler)
    assert not (out / "summary.json").exists()
    assert not any(p.name.startswith("fields.nc") for p in out.iterdir())
    assert json.loads((out / "status.json").read_text())["status"] == "failed"
    # Writing works again once space is back.
    gfmd.run(str(tmp_path / "case.toml"), output=str(out))
    assert (out / "summary.json").exists() and (out / "fields.nc").exists()
