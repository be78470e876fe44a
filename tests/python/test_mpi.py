"""Distributed runs: `mpirun -np N gfmd run` against the same case in one process.

The solves run on slabs of rows: the transforms line by line with FFTW-MPI's transposes between
the row and the column passes (each line through the plan one process uses), the reductions
gathered and added in row order. So a distributed run gives one process's results bit for bit,
on any grid and any process count: every observable, field and iteration count is compared
exactly (the leakage alone is solved by another solver, BoomerAMG over the processes: its flow
factors to 1e-8). Odd process counts and grids whose rows do not divide evenly are among the
cases; a sliding case with stick and a leakage case too.
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
# The children wait passively, without a GOMP_SPINCOUNT of the caller's: libgomp lets it override
# the policy (importing gfmd left one in this process's environment until 2026-12-07; with 3
# processes on 2 cores their spinning threads made an MPI test take 37 s instead of 3 s).
ENV = dict({k: v for k, v in os.environ.items() if k != "GOMP_SPINCOUNT"}, OMP_WAIT_POLICY="PASSIVE",
           OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")

pytestmark = pytest.mark.skipif(MPIRUN is None, reason="mpirun not found (Debian package openmpi-bin)")

# Observables that must not depend on the number of processes (bit for bit).
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
nx = 128
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


def run(case, out, ranks=0, extra=(), quiet=True):
    cmd = [GFMD, "run", str(case), "-o", str(out), *(["-q"] if quiet else []), *extra]
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
            assert b[k] == a[k], k
    for k in ("max_tensile_stress", "max_von_mises"):
        for x, y in zip(a.get("subsurface", []), b.get("subsurface", [])):
            assert y[k] == x[k], k
    fa, fb = fields(serial), fields(dist)
    for v, x in fa.items():
        assert np.array_equal(fb[v], x), v
    return a, b


def serial_and_distributed(tmp_path, text, ranks):
    """The case `text` run serially and on `ranks` processes: both summaries, checked as one
    solution (same_solution)."""
    case = tmp_path / "case.toml"
    case.write_text(text)
    for out, np_ in (("serial", 0), ("mpi", ranks)):
        p = run(case, tmp_path / out, np_)
        assert p.returncode == 0, p.stderr
    return same_solution(tmp_path / "serial", tmp_path / "mpi", ranks)


@pytest.mark.parametrize("ranks", [1, 2, 3, 4])
def test_hertz_frictionless_any_rank_count(tmp_path, ranks):
    case = tmp_path / "hertz.toml"
    case.write_text(HERTZ)
    p = run(case, tmp_path / "serial")
    assert p.returncode == 0, p.stderr
    # One process prints the report, not every rank (without -q, which prints only errors).
    p = run(case, tmp_path / "mpi", ranks, quiet=False)
    assert p.returncode == 0, p.stderr
    assert p.stdout.count("relative contact area") == 1
    same_solution(tmp_path / "serial", tmp_path / "mpi", ranks)


ADHESIVE = HERTZ.replace("force = 0.01", "approach = 0.002").replace(
    "[solver]", "[interaction]\nmodel = \"adhesive\"\nwork_of_adhesion = 2e-3\nrange = 0.02\n[solver]")


@pytest.mark.parametrize("ranks,friction", [(2, ""), (3, ""), (3, "[friction]\ncoefficient = 0.3\n")])
def test_adhesive_hertz_any_rank_count(tmp_path, ranks, friction):
    # The adhesive steps (the cell law's spectral gradient, the traction's Anderson mixing summed by
    # grid row) give the serial bits on slabs, the adhesive figures and fields included; sliding too
    # (the friction loop around the adhesive solve, its law reading the repulsion).
    a, b = serial_and_distributed(tmp_path, ADHESIVE.replace("[solver]", friction + "[solver]"), ranks)
    assert a["adhesive_force"] > 0 and a["normal_force"] < a["repulsive_force"]
    keys = ["adhesive_force", "repulsive_force", "attraction_area_fraction", "cohesive_zone_fraction",
            "adhesion_steps", "energy"]
    if friction:
        assert a["converged"] and a["tangential_force"] > 0
        keys += ["tangential_force", "friction_force", "outer_iterations"]
    for k in keys:
        assert b[k] == a[k], k
    import netCDF4
    with netCDF4.Dataset(tmp_path / "serial" / "fields.nc") as x, netCDF4.Dataset(tmp_path / "mpi" / "fields.nc") as y:
        assert np.array_equal(np.array(x["adhesive_traction"][:]), np.array(y["adhesive_traction"][:]))


VISCO = HERTZ.replace("poisson = 0.3", "poisson = 0.3\nviscoelastic = \"sls\"\nhigh_frequency_modulus = 10.0\n"
                      "relaxation_time = 1.0").replace("[solver]", "[friction]\nvelocity = 0.02\ndirection = 30\n[solver]")


@pytest.mark.parametrize("ranks,friction", [(2, ""), (3, ""), (3, "coefficient = 0.3\nregularization = 0.01\n"),
                                            (3, "coefficient = 0.3\ncreepage = 0.001\n"),
                                            (3, "coefficient = 0.3\ncreepage = 0.001\n# pair\n"),
                                            (3, "coefficient = 0.3\ncreepage = 0.001\n# coated\n"),
                                            (3, "coefficient = 0.3\ncreepage = 0.001\n# two parts\n"),
                                            (3, "coefficient = 0.3\nregularization = 0.01\n# active set\n")])
def test_viscoelastic_sliding_any_rank_count(tmp_path, ranks, friction):
    # The response factors on each slab's rows of the spectrum (the y Nyquist row on one of them),
    # the normal solve's sums by grid row (the active set's contact set and GMRES without friction
    # and with "# active set", the splitting's mixing in the friction loop) and the spectral
    # dissipation (with friction, of the
    # tangential tractions too): the serial bits. Rolling with stick: the stick-slip splitting's
    # resolvent with the response, too; under an elastic indenter ("# pair") with the pair's complex
    # response; on a viscoelastic coating over a substrate ("# coated") with its transfer matrices';
    # over a substrate of another relaxation ("# two parts") with each part's factors per slab.
    case = VISCO.replace("[friction]\n", "[friction]\n" + friction)
    if "# pair" in friction:
        case = case.replace("[indenter]\n", "[indenter]\ncontact_modulus = 2.0\npoisson = 0.45\n")
    if "# coated" in friction:  # a viscoelastic coating: its complex transfer matrices per slab
        case = case.replace("[elastic]\n", "[elastic]\nthickness = 0.05\nsubstrate_contact_modulus = 2.0\n")
    if "# active set" in friction:
        case = case.replace("[solver]\n", "[solver]\nviscoelastic_method = \"active_set\"\n")
    if "# two parts" in friction:
        case = case.replace("[elastic]\n", "[elastic]\nthickness = 0.05\nsubstrate_contact_modulus = 2.0\n"
                            "viscoelastic_parts = [{viscoelastic = \"sls\", viscoelastic_part = \"substrate\", "
                            "high_frequency_modulus = 8.0, relaxation_time = 30.0}]\n")
    a, b = serial_and_distributed(tmp_path, case, ranks)
    assert a["hysteresis_friction"] > 0 and a["hysteresis_balance_error"] < 1e-9
    keys = ["hysteresis_force", "hysteresis_dissipation", "viscoelastic_steps", "centroid_shift"]
    if "creepage" in friction:
        assert a["converged"] and a["stick_fraction"] > 0.1
        keys += ["stick_fraction", "tangential_force", "outer_iterations"]
    for k in keys:
        assert b[k] == a[k], k


def test_adhesive_viscoelastic_sliding_any_rank_count(tmp_path):
    # Adhesion on the sliding viscoelastic body: the adhesive steps around the splitting give the
    # serial bits on three slabs.
    case = VISCO.replace("[solver]", "[interaction]\nmodel = \"adhesive\"\nwork_of_adhesion = 2e-3\n"
                         "range = 0.02\n[solver]")
    a, b = serial_and_distributed(tmp_path, case, 3)
    assert a["adhesive_force"] > 0 and a["hysteresis_friction"] > 0 and a["hysteresis_balance_error"] < 1e-9
    for k in ("adhesive_force", "adhesion_steps", "viscoelastic_steps", "hysteresis_force", "hysteresis_dissipation",
              "centroid_shift", "relative_contact_area"):
        assert b[k] == a[k], k


COATED = HERTZ.replace("poisson = 0.3", "poisson = 0.3\nthickness = 0.05\nsubstrate_contact_modulus = 0.2\n"
                       "layers = [{contact_modulus = 3.0, poisson = 0.2, thickness = 0.02}]").replace(
    "[solver]", "[friction]\ncoefficient = 0.4\ndirection = 30\n[stress]\ndepths = [0.05, 0.2]\n[solver]")


@pytest.mark.parametrize("ranks", [2, 3])
def test_coated_sliding_any_rank_count(tmp_path, ranks):
    # A coating and an interlayer on a substrate: each slab's rows of the layered compliance and of
    # the planes below the surface (one on the interface, one in the substrate) give the serial bits.
    a, b = serial_and_distributed(tmp_path, COATED, ranks)
    assert len(a["subsurface"]) == 2 and a["subsurface"][0]["max_von_mises"] > 0


TWO_BODIES = HERTZ.replace("[load]", "contact_modulus = 0.5\npoisson = 0.45\nthickness = 0.3\n[load]").replace(
    "[solver]", "[friction]\ncoefficient = 0.4\ndirection = 30\n[stress]\ndepths = [0.05]\n[solver]")


@pytest.mark.parametrize("ranks", [2, 3])
def test_elastic_indenter_sliding_any_rank_count(tmp_path, ranks):
    # Two deformable bodies: the pair's compliance and the body's own on each slab, the indenter's
    # deformed face in the downhill force and its stresses give the serial bits.
    a, b = serial_and_distributed(tmp_path, TWO_BODIES, ranks)
    assert a["indenter_stress"]["max_von_mises"] > 0 and a["energy_balance_error_exact"] < 1e-3
    assert b["indenter_stress"] == a["indenter_stress"]
    assert b["downhill_friction"] == a["downhill_friction"]


@pytest.mark.parametrize("ranks", [3])
def test_two_bodies_rolling_with_a_static_peak(tmp_path, ranks):
    """examples/rolling_static_peak.toml under a coated elastic indenter, on uneven slabs: the pair's
    slip operators (both bodies roll), the velocity law's resolvent and its step raised from the
    largest pressure over all slabs give the serial bits."""
    text = open(os.path.join(ROOT, "examples", "rolling_static_peak.toml")).read()
    text = text.replace("nx = 64", "nx = 64\nny = 62\nly = 1.55").replace("velocity_scale = 0.05", "velocity_scale = 0.2").replace(
        "[load]", "contact_modulus = 2.0\npoisson = 0.3\nthickness = 0.2\nsubstrate_contact_modulus = 1.5\n[load]")
    a, b = serial_and_distributed(tmp_path, text + "\n[output]\npng = false\n", ranks)
    assert 0 < a["stick_fraction"] < 1
    assert b["tangential_iterations"] == a["tangential_iterations"]


@pytest.mark.parametrize("ranks", [2, 3])
def test_thin_layer_sliding_with_stick(tmp_path, ranks):
    a, b = serial_and_distributed(tmp_path, THIN_STICK, ranks)
    assert a["stick_fraction"] > 0  # points stick: the stick-slip (Douglas-Rachford) solve ran
    assert b["tangential_iterations"] == a["tangential_iterations"]


@pytest.mark.parametrize("ranks", [3])  # uneven slabs (21, 21, 20 rows); two even ones cost 25 s more in CI
def test_rolling_with_the_upwind_derivative(tmp_path, ranks):
    """Kalker's small-creepage rolling (examples/rolling_sphere.toml on 64 x 62 cells, uneven
    slabs, with lateral creepage too): the upwind slip symbols read the global wave numbers on
    every slab."""
    text = open(os.path.join(ROOT, "examples", "rolling_sphere.toml")).read()
    a, b = serial_and_distributed(tmp_path, text.replace("nx = 128", "nx = 64\nny = 62\nly = 0.96875")
                                  .replace("[stress]", "[output]\npng = false\n\n[stress]")
                                  .replace("creepage = 1e-4", "creepage = 1e-4\nlateral_creepage = 3e-5"), ranks)
    assert a["stick_fraction"] > 0.9
    assert b["tangential_iterations"] == a["tangential_iterations"]
    assert b["numerical_dissipation"] == a["numerical_dissipation"]


@pytest.mark.parametrize("ranks", [2, 3, 4])
def test_sliding_rough_with_leakage(tmp_path, ranks):
    """The leakage of a distributed run: the Reynolds system assembled on the slabs and solved
    by HYPRE's BoomerAMG over the processes, the components labelled slab by slab and merged
    across the slabs' edges (the same percolation flags; 128 rows over 3 processes: 43, 43, 42).
    The gap has one process's bits and the flow factors agree to the solvers' tolerance
    (1e-10 relative residual here, our AMG in one process)."""
    serial_and_distributed(tmp_path, ROUGH_FLOW, ranks)
    with open(tmp_path / "serial" / "flow.json") as f:
        fa = json.load(f)
    with open(tmp_path / "mpi" / "flow.json") as f:
        fb = json.load(f)
    for d in ("x", "y"):
        assert fb["percolates_" + d] == fa["percolates_" + d]
        assert fb["flow_factor_" + d] == pytest.approx(fa["flow_factor_" + d], rel=1e-8, abs=1e-300)


@pytest.mark.parametrize("ranks,grid", [(3, "nx = 64"), (4, "nx = 64"), (3, "nx = 75\nny = 60\nly = 0.8")])
def test_surface_made_on_slabs_has_the_serial_bits(tmp_path, ranks, grid):
    """Every process makes only its rows of the self-affine surface (its phases from the one
    random sequence, its slab of the synthesis): the heights rank 0 gathers, the surface
    statistics and the whole solution equal one process's to the last bit, on a power-of-two
    grid (64 rows over 3 processes: slabs of 22, 22 and 20 rows) and on a 75 x 60 grid (odd rows)."""
    case = tmp_path / "rough.toml"
    case.write_text(ROUGH_FLOW.replace("nx = 128", grid).replace("[flow]\nenabled = true\n", ""))
    assert run(case, tmp_path / "serial").returncode == 0
    p = run(case, tmp_path / "mpi", ranks)
    assert p.returncode == 0, p.stderr
    a, b = same_solution(tmp_path / "serial", tmp_path / "mpi", ranks)
    assert b["topography"] == a["topography"]
    for k in ("friction_coefficient", "relative_contact_area", "mean_gap", "centroid_shift", "pressure_max_shift",
              "contact_extent_longitudinal", "contact_extent_transverse", "max_slip_velocity"):
        assert b[k] == a[k], k
    import netCDF4
    with netCDF4.Dataset(tmp_path / "serial" / "fields.nc") as x, netCDF4.Dataset(tmp_path / "mpi" / "fields.nc") as y:
        for v in ("topography", "pressure", "traction_x", "uz"):
            assert np.array_equal(np.array(x[v][:]), np.array(y[v][:])), v


LEAN = """[grid]
nx = 64
ny = 50
lx = 1.0
ly = 0.78125
[elastic]
poisson = 0.45
thickness = 0.2
[indenter]
type = "selfaffine"
hurst = 0.7
lambda_long = 0.5
lambda_short = 0.05
rms_height = 0.01
seed = 3
[load]
pressure = 0.05
[friction]
coefficient = 0.5
[flow]
enabled = true
[stress]
post_analysis = ["consistent", "paper"]
depths = [0.01, 0.05]
profiles = true
[solver]
threads = 1
[output]
fields = false
png = false
analysis = true
"""

TIMINGS = ("wall_time_s", "fft_time_s", "time_per_iteration_s", "stress_time_s", "setup_seconds_x",
           "setup_seconds_y", "solve_seconds_x", "solve_seconds_y", "mpi_ranks", "mpi")


def same_numbers(a, b, rel, path=""):
    """Every number of a (a summary.json or flow.json) in b to rel, but the timings and the MPI
    block; strings and lists element by element."""
    if isinstance(a, dict):
        for k, v in a.items():
            if k not in TIMINGS:
                assert k in b, path + k
                same_numbers(v, b[k], rel, path + k + ".")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            same_numbers(x, y, rel, path + str(i) + ".")
    elif isinstance(a, float) and rel > 0:
        assert b == pytest.approx(a, rel=rel, abs=1e-300), path
    else:
        assert b == a, path


def same_summary(a, b):
    """summary.json of a distributed run against one process's: every figure bit for bit but the
    leakage's, which BoomerAMG over the processes and our AMG in one process both solve to the
    relative residual 1e-10: its flow factors and conductivities to 1e-8 (absolute 1e-12 for a
    net flow that is zero up to round-off; iterations and residuals differ)."""
    fa, fb = a.pop("flow"), b.pop("flow")
    same_numbers(a, b, 0)
    for k, v in fa.items():
        if k.startswith(("flow_factor", "conductivity", "percolates", "mean_gap")):
            assert fb[k] == pytest.approx(v, rel=1e-8, abs=1e-12), k


@pytest.mark.parametrize("analysis", ["true", "false"])
def test_post_processing_on_slabs_matches_serial(tmp_path, analysis):
    """Without field outputs every process post-processes its slab (observables, surface,
    subsurface and both post-analysis stresses, the profiles through the pressure maximum, the
    leakage) and rank 0 gathers only the pressure, gap and heights for the analysis: every
    figure of summary.json as in one process, the tables alike."""
    case = tmp_path / "lean.toml"
    case.write_text(LEAN.replace("analysis = true", "analysis = " + analysis))
    assert run(case, tmp_path / "serial").returncode == 0
    p = run(case, tmp_path / "mpi", 3)
    assert p.returncode == 0, p.stderr
    a, b = summary(tmp_path / "serial"), summary(tmp_path / "mpi")
    assert len(a["subsurface"]) == 2 and "post_analysis_paper" in a and ("analysis" in a) == (analysis == "true")
    assert b["topography"]["kind"] == "selfaffine"
    same_summary(a, b)
    tables = ["profiles.csv"] + (["patches.csv", "distributions.csv", "spectrum.csv", "bands.csv"]
                                 if analysis == "true" else [])
    for name in tables:
        x = np.genfromtxt(tmp_path / "serial" / name, delimiter=",", skip_header=1)
        y = np.genfromtxt(tmp_path / "mpi" / name, delimiter=",", skip_header=1)
        assert x.shape == y.shape and x.size > 0, name
        assert np.array_equal(y, x, equal_nan=True), name
    assert not (tmp_path / "mpi" / "fields.nc").exists()


@pytest.mark.parametrize("fields", ["false", "true"])
def test_a_process_without_rows_takes_part(tmp_path, fields):
    """9 rows over 4 processes: FFTW-MPI's blocks of 3 rows leave the last process none. It
    still takes part in every transform and reduction of the solve, the post-processing and
    the distributed flow solve (no unknowns of its own)."""
    case = tmp_path / "tiny.toml"
    case.write_text(LEAN.replace("nx = 64\nny = 50\nlx = 1.0\nly = 0.78125", "nx = 16\nny = 9\nlx = 4.0\nly = 2.25")
                    .replace('type = "selfaffine"', 'type = "hertz"\nradius_x = 1.0\nradius_y = 1.0')
                    .replace("hurst = 0.7\nlambda_long = 0.5\nlambda_short = 0.05\nrms_height = 0.01\nseed = 3\n", "")
                    .replace("pressure = 0.05", "pressure = 0.02").replace("fields = false", "fields = " + fields))
    assert run(case, tmp_path / "serial").returncode == 0
    p = run(case, tmp_path / "mpi", 4)
    assert p.returncode == 0, p.stderr
    same_summary(summary(tmp_path / "serial"), summary(tmp_path / "mpi"))
    if fields == "true":
        same_solution(tmp_path / "serial", tmp_path / "mpi", 4)


def test_more_ranks_than_rows_is_refused_by_rank_zero(tmp_path):
    case = tmp_path / "hertz.toml"
    case.write_text(HERTZ.replace("ny = 50", "ny = 2").replace("ly = 3.125", "ly = 4.0").replace("nx = 64", "nx = 2"))
    p = run(case, tmp_path / "out", 3)
    assert p.returncode == 2
    assert p.stderr.count("grid.ny") == 1 and "at most 2 processes" in p.stderr
    assert not (tmp_path / "out").exists()


def mpi_cmd(ranks, *args):
    return subprocess.run([MPIRUN, "-np", str(ranks), "--oversubscribe", "--bind-to", "none", GFMD, *map(str, args)],
                          capture_output=True, text=True, env=ENV, timeout=600)


def serial_cmd(*args):
    return subprocess.run([GFMD, *map(str, args)], capture_output=True, text=True, env=ENV, timeout=600)


def test_sweep_under_mpirun_matches_serial(tmp_path):
    """Every process solves every point (warm-started from the previous one, which rank 0
    holds and scatters); rank 0 alone writes. Same iterations, the same observables bit for bit."""
    case = tmp_path / "thin.toml"
    case.write_text(THIN_STICK.replace("[stress]\ndepths = [0.01]\n", ""))
    sets = ["--set", "load.pressure=0.05,0.1,0.3", "-q"]
    assert serial_cmd("sweep", case, "-o", tmp_path / "serial", *sets).returncode == 0
    # Without -q (which prints only errors): rank 0 alone reports.
    p = mpi_cmd(3, "sweep", case, "-o", tmp_path / "mpi", *sets[:-1])
    assert p.returncode == 0, p.stderr
    assert p.stdout.count("sweep of load.pressure") == 1
    with open(tmp_path / "serial" / "sweep.json") as f:
        a = json.load(f)["points"]
    with open(tmp_path / "mpi" / "sweep.json") as f:
        b = json.load(f)["points"]
    assert len(a) == len(b) == 3
    for x, y in zip(a, b):
        assert y["iterations"] == x["iterations"] and y["mpi_ranks"] == 3
        for k in OBSERVABLES:
            if k in x:
                assert y[k] == x[k], k
    assert summary(tmp_path / "mpi" / "point_002")["mpi_ranks"] == 3


def percolation_serial_and_mpi(tmp_path, case, direction, ranks):
    """percolation.json of `gfmd percolation` in one process and under mpirun."""
    assert serial_cmd("percolation", case, "--direction", direction, "-o", tmp_path / "p1", "-q").returncode == 0
    p = mpi_cmd(ranks, "percolation", case, "--direction", direction, "-o", tmp_path / "pn", "-q")
    assert p.returncode == 0, p.stderr
    found = []
    for d in ("p1", "pn"):
        with open(tmp_path / d / "percolation.json") as f:
            found.append(json.load(f))
    return found


def test_percolation_along_y_over_four_slabs(tmp_path):
    """Percolation along y is decided by components that cross every slab's edge (four slabs of
    15-17 rows of a 62-row cell): the flags merged from the slabs' edge rows take the serial
    bisection's path, verdict for verdict."""
    case = tmp_path / "flow.toml"
    case.write_text(ROUGH_FLOW.replace("nx = 128", "nx = 64\nny = 62").replace("lx = 1.0", "lx = 1.0\nly = 0.96875"))
    a, b = percolation_serial_and_mpi(tmp_path, case, "y", 4)
    verdicts = [h["percolates"] for h in a["history"]]
    assert len(verdicts) >= 4 and True in verdicts and False in verdicts
    assert [h["percolates"] for h in b["history"]] == verdicts
    assert b["critical_relative_contact_area"] == pytest.approx(a["critical_relative_contact_area"], rel=1e-8)


def test_percolation_and_ensemble_under_mpirun_match_serial(tmp_path):
    case = tmp_path / "flow.toml"
    case.write_text(ROUGH_FLOW.replace("nx = 128", "nx = 64"))
    a, b = percolation_serial_and_mpi(tmp_path, case, "x", 3)
    # The same bisection: the same pressures, the same verdicts, areas to 1e-12.
    assert [h["pressure"] for h in b["history"]] == [h["pressure"] for h in a["history"]]
    assert [h["percolates"] for h in b["history"]] == [h["percolates"] for h in a["history"]]
    assert b["critical_relative_contact_area"] == pytest.approx(a["critical_relative_contact_area"], rel=1e-12)

    assert serial_cmd("ensemble", case, "--seeds", "0..1", "-o", tmp_path / "e1", "-q").returncode == 0
    p = mpi_cmd(2, "ensemble", case, "--seeds", "0..1", "-o", tmp_path / "e2")
    assert p.returncode == 0, p.stderr
    assert p.stdout.count("ensemble.json") == 1
    with open(tmp_path / "e1" / "ensemble.json") as f:
        a = json.load(f)
    with open(tmp_path / "e2" / "ensemble.json") as f:
        b = json.load(f)
    for x, y in zip(a["seeds"], b["seeds"]):
        assert y["relative_contact_area"] == x["relative_contact_area"]
        # BoomerAMG over the processes and our AMG each stop at their tolerance.
        for k in ("conductivity_x", "conductivity_y"):
            assert y[k] == pytest.approx(x[k], rel=1e-6), k
    assert (tmp_path / "e2" / "seed_1" / "flow.json").exists()

    # A load curve (a sweep with leakage and the threshold read from its points' files).
    pressures = ["--pressures", "0.02,0.05,0.1", "--no-png", "-q"]
    assert serial_cmd("curve", case, "-o", tmp_path / "c1", *pressures).returncode == 0
    p = mpi_cmd(2, "curve", case, "-o", tmp_path / "c2", *pressures)
    assert p.returncode == 0, p.stderr
    with open(tmp_path / "c1" / "curve.json") as f:
        a = json.load(f)["percolation"]
    with open(tmp_path / "c2" / "curve.json") as f:
        b = json.load(f)["percolation"]
    assert b["status"] == a["status"] and b["pressure"] == pytest.approx(a["pressure"], rel=1e-12)


def test_other_commands_refuse_mpirun(tmp_path):
    case = tmp_path / "hertz.toml"
    case.write_text(HERTZ)
    assert serial_cmd("run", case, "-o", tmp_path / "one", "-q").returncode == 0
    p = mpi_cmd(2, "flow", tmp_path / "one", "--direction", "x")
    assert p.returncode == 2
    assert p.stderr.count("under mpirun") == 1
    assert not (tmp_path / "one" / "flow.json").exists()
    # A bad option: one message (rank 0's), exit 2.
    p = mpi_cmd(2, "run", case, "-o", tmp_path / "r", "--checkpoint-interval", "0.01")
    assert p.returncode == 2
    assert p.stderr.count("--checkpoint-interval") == 1
