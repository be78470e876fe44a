"""The Python module (build/python/gfmd*.so): results, fields as numpy arrays, errors."""
import glob
import os
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "build", "python"))
if not glob.glob(os.path.join(ROOT, "build", "python", "gfmd*.so")):
    pytest.fail("the Python module was not built (pybind11-dev and python3-dev are needed)", pytrace=False)
import gfmd  # noqa: E402

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


def test_friction_fields_and_errors():
    r = gfmd.run_toml(HERTZ, set=["friction.coefficient=1", "elastic.poisson=0.25"])
    assert r["summary"]["friction_coefficient"] < 1.0
    assert np.all(r["fields"]["traction_x"] >= 0)
    assert r["fields"]["sigma_1"].max() > 0
    with pytest.raises(gfmd.InputError, match="elastic.poisson"):
        gfmd.run_toml(HERTZ, set=["elastic.poisson=0.7"])
    with pytest.raises(gfmd.SolveError, match="not converged"):
        gfmd.run_toml(HERTZ, set=["solver.max_iterations=2"])
