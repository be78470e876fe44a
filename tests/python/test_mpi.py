"""Distributed runs: `mpirun -np N gfmd run` against the same case in one process.

The solves run on slabs of rows (FFTW-MPI transforms, reductions gathered and added in row
order), so the results may differ from one process's only by the round-off of the
transforms: the observables must agree to 1e-12 relative and the iteration counts exactly
(the brief's rank-independence requirement). Odd process counts and grids whose rows do not
divide evenly are among the cases; a sliding case with stick and a leakage case too.
"""
import json
import os
import shutil
import subprocess

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
GFMD = os.path.join(BUILD, "gfmd")
MPIRUN = shutil.which("mpirun")
ENV = dict(os.environ, OMP_WAIT_POLICY="PASSIVE", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")

pytestmark = pytest.mark.skipif(MPIRUN is None, reason="mpirun not found (Debian package openmpi-bin)")

# Observables that must not depend on the number of processes (relative 1e-12).
OBSERVABLES = ["relative_contact_area", "normal_force", "mean_pressure", "max_pressure", "mean_gap", "approach",
               "friction_coefficient", "friction_coefficient_downhill", "stick_fraction", "max_tensile_stress",
               "max_von_mises"]

HERTZ = """[grid]
nx = 64
ny = 50
lx = 4.0
ly = 3.125
[elastic]
poisson = 0.3
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[solver]
threads = 1
[output]
png = false
"""

# The paper's thin layer (nu = 0.49, h = 0.05 lambda_l) at mu_c = 1 and 0.3 E*: part of the
# contact sticks. Subsurface stresses and the leakage along x and y are computed too.
THIN_STICK = """[grid]
nx = 128
ny = 126
lx = 2.0
ly = 1.96875
[elastic]
poisson = 0.49
thickness = 0.05
[indenter]
type = "selfaffine"
hurst = 0.8
lambda_long = 1.0
lambda_short = 0.0625
rms_height = 0.01
seed = 0
[load]
pressure = 0.3
[friction]
coefficient = 1.0
[stress]
depths = [0.01]
[solver]
threads = 1
[output]
png = false
"""

ROUGH_FLOW = """[grid]
nx = 96
lx = 1.0
[elastic]
poisson = 0.25
[indenter]
type = "selfaffine"
hurst = 0.7
lambda_long = 0.5
lambda_short = 0.04
rms_height = 0.01
seed = 1
[load]
pressure = 0.05
[friction]
coefficient = 0.5
[flow]
enabled = true
[solver]
threads = 1
[output]
png = false
"""


def run(case, out, ranks=0, extra=()):
    cmd = [GFMD, "run", str(case), "-o", str(out), "-q", *extra]
    if ranks:
        cmd = [MPIRUN, "-np", str(ranks), "--oversubscribe", "--bind-to", "none", *cmd]
    return subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=600)


def summary(d):
    with open(os.path.join(d, "summary.json")) as f:
        return json.load(f)


def fields(d):
    import netCDF4
    with netCDF4.Dataset(os.path.join(d, "fields.nc")) as nc:
        return {v: np.array(nc[v][:]) for v in ("pressure", "ux", "uz", "gap", "traction_x", "stick")
                if v in nc.variables}


def same_solution(serial, dist, ranks):
    a, b = summary(serial), summary(dist)
    assert b["mpi_ranks"] == ranks and a["mpi_ranks"] == 1
    assert b["mpi"]["ranks"] == ranks and len(b["mpi"]["solve_peak_memory_mib"]) == ranks
    assert b["iterations"] == a["iterations"]
    assert b.get("outer_iterations") == a.get("outer_iterations")
    for k in OBSERVABLES:
        if k in a:
            assert b[k] == pytest.approx(a[k], rel=1e-12, abs=1e-300), k
    for k in ("max_tensile_stress", "max_von_mises"):
        for x, y in zip(a.get("subsurface", []), b.get("subsurface", [])):
            assert y[k] == pytest.approx(x[k], rel=1e-12), k
    fa, fb = fields(serial), fields(dist)
    for v, x in fa.items():
        scale = np.max(np.abs(x))
        assert np.max(np.abs(fb[v] - x)) <= 1e-12 * scale, v
    return a, b


@pytest.mark.parametrize("ranks", [1, 2, 3, 4])
def test_hertz_frictionless_any_rank_count(tmp_path, ranks):
    case = tmp_path / "hertz.toml"
    case.write_text(HERTZ)
    p = run(case, tmp_path / "serial")
    assert p.returncode == 0, p.stderr
    p = run(case, tmp_path / "mpi", ranks)
    assert p.returncode == 0, p.stderr
    # One process prints the report, not every rank.
    assert p.stdout.count("relative contact area") == 1
    same_solution(tmp_path / "serial", tmp_path / "mpi", ranks)


@pytest.mark.parametrize("ranks", [2, 3])
def test_thin_layer_sliding_with_stick(tmp_path, ranks):
    case = tmp_path / "thin.toml"
    case.write_text(THIN_STICK)
    assert run(case, tmp_path / "serial").returncode == 0
    p = run(case, tmp_path / "mpi", ranks)
    assert p.returncode == 0, p.stderr
    a, b = same_solution(tmp_path / "serial", tmp_path / "mpi", ranks)
    assert a["stick_fraction"] > 0  # points stick: the stick-slip (Douglas-Rachford) solve ran
    assert b["tangential_iterations"] == a["tangential_iterations"]


def test_sliding_rough_with_leakage(tmp_path):
    case = tmp_path / "flow.toml"
    case.write_text(ROUGH_FLOW)
    assert run(case, tmp_path / "serial").returncode == 0
    p = run(case, tmp_path / "mpi", 3)
    assert p.returncode == 0, p.stderr
    same_solution(tmp_path / "serial", tmp_path / "mpi", 3)
    with open(tmp_path / "serial" / "flow.json") as f:
        fa = json.load(f)
    with open(tmp_path / "mpi" / "flow.json") as f:
        fb = json.load(f)
    for d in ("x", "y"):
        assert fb["percolates_" + d] == fa["percolates_" + d]
        assert fb["flow_factor_" + d] == pytest.approx(fa["flow_factor_" + d], rel=1e-8, abs=1e-300)


def test_more_ranks_than_rows_is_refused_by_rank_zero(tmp_path):
    case = tmp_path / "hertz.toml"
    case.write_text(HERTZ.replace("ny = 50", "ny = 2").replace("ly = 3.125", "ly = 4.0").replace("nx = 64", "nx = 2"))
    p = run(case, tmp_path / "out", 3)
    assert p.returncode == 2
    assert p.stderr.count("grid.ny") == 1 and "at most 2 processes" in p.stderr
    assert not (tmp_path / "out").exists()


def test_other_commands_refuse_mpirun(tmp_path):
    case = tmp_path / "hertz.toml"
    case.write_text(HERTZ)
    p = subprocess.run([MPIRUN, "-np", "2", "--oversubscribe", GFMD, "sweep", str(case), "--set",
                        "load.force=0.01,0.02", "-o", str(tmp_path / "sw")], capture_output=True, text=True, env=ENV,
                       timeout=120)
    assert p.returncode == 2
    assert p.stderr.count("only `gfmd run` runs under mpirun") == 1
    assert not (tmp_path / "sw").exists()
