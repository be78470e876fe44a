"""The PNG maps drawn by scripts/plot_maps.py (matplotlib): after `gfmd run`, after
`gfmd sweep`, redrawn by `gfmd plot DIR`, through a staging file when output.fields is off,
from Python's run(output=), and the Hertz zoom. The build directory is $GFMD_BUILD_DIR
(default build/)."""
import glob
import os
import subprocess
import sys

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
GFMD = os.path.join(BUILD, "gfmd")
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import plot_maps  # noqa: E402

# The children wait passively, without a GOMP_SPINCOUNT of the caller's: libgomp lets it override
# the policy (importing gfmd left one in this process's environment until 2026-12-07; with 3
# processes on 2 cores their spinning threads made an MPI test take 37 s instead of 3 s).
ENV = dict({k: v for k, v in os.environ.items() if k != "GOMP_SPINCOUNT"},
           OMP_WAIT_POLICY="PASSIVE")

HERTZ = """
[grid]
nx = 64
lx = 4.0
[elastic]
poisson = 0.25
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
"""
# Sliding with friction on a compressible half-space: slip, dissipation and stress maps.
SLIDING = HERTZ + """
[friction]
coefficient = 1.0
[stress]
profiles = false
"""
MAPS = ["pressure", "gap", "max_principal_stress", "von_mises"]
FRICTION_MAPS = MAPS + ["slip_longitudinal", "slip_transverse", "dissipation"]


def gfmd(*args, check=True):
    if not os.access(GFMD, os.X_OK):
        pytest.fail(f"{GFMD} is not built (set GFMD_BUILD_DIR)", pytrace=False)
    p = subprocess.run([GFMD, *args], capture_output=True, text=True, env=ENV)
    if check:
        assert p.returncode == 0, p.stdout + p.stderr
    return p


def assert_pngs(d, names):
    for n in names:
        img = matplotlib.image.imread(os.path.join(d, n + ".png"))
        assert img.ndim == 3 and img.shape[0] > 200 and img.shape[1] > 200, (n, img.shape)
        assert np.ptp(img[..., :3]) > 0.5, f"{n}.png is blank"
    assert not [f for f in os.listdir(d) if ".tmp." in f], os.listdir(d)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("maps")
    out = {}
    for name, text in (("hertz", HERTZ), ("sliding", SLIDING)):
        case = base / f"{name}.toml"
        case.write_text(text)
        gfmd("run", str(case), "-o", str(base / name), "-q")
        out[name] = str(base / name)
    return out


def test_run_draws_the_maps_and_profiles(runs):
    assert_pngs(runs["hertz"], MAPS + ["profiles"])
    assert_pngs(runs["sliding"], FRICTION_MAPS)
    # Frictionless: no slip maps; no flow: no current maps.
    assert not glob.glob(os.path.join(runs["hertz"], "slip_*.png"))
    assert not glob.glob(os.path.join(runs["sliding"], "current_*.png"))


def test_plot_redraws_deleted_maps(runs):
    d = runs["sliding"]
    for f in glob.glob(os.path.join(d, "*.png")):
        os.remove(f)
    p = gfmd("plot", d)
    assert "1 run directories" in p.stdout, p.stdout
    assert_pngs(d, FRICTION_MAPS)


def test_hertz_maps_are_zoomed_onto_the_contact(runs):
    data = plot_maps.read_netcdf(os.path.join(runs["hertz"], "fields.nc"))
    p = data["fields"]["pressure"][0]
    lx, ly = data["lx"], data["ly"]
    assert plot_maps.indenter_type(data["input_toml"], None) == "hertz"
    lim = plot_maps.map_limits(data, p, hertz=True)
    full = plot_maps.grid_extent(64, 64, lx, ly)
    box = plot_maps.contact_bbox(p, lx, ly)
    dx = lx / 64
    # Within the grid, around the contact's cells with a margin, and much smaller than the grid.
    assert full[0] <= lim[0] < box[0] - dx and box[1] + dx < lim[1] <= full[1]
    assert full[2] <= lim[2] < box[2] - dx and box[3] + dx < lim[3] <= full[3]
    assert lim[1] - lim[0] < 0.5 * lx and lim[3] - lim[2] < 0.5 * ly
    w = box[1] - box[0] + dx
    # 30 % of the contact's size on each side, at least 4 cells.
    assert lim[1] - lim[0] == pytest.approx(w + 2 * max(0.3 * w, 4 * dx))
    # The margin is at least a few cells, the grid the limit; no contact: the whole grid.
    one = np.zeros((64, 64))
    one[0, 0] = 1.0
    z = plot_maps.zoom_limits(one, lx, ly)
    assert z[0] == full[0] and z[1] >= dx * 4 and z[2] == full[2]
    assert plot_maps.zoom_limits(np.zeros((64, 64)), lx, ly) == full
    # A rough or sliding-with-a-non-Hertz case is drawn whole.
    assert plot_maps.map_limits(data, p, hertz=False) == full


def test_block_average_and_large_grid_view():
    a = np.arange(16.0).reshape(4, 4)
    b = plot_maps.block_average(a, 2)
    assert b.tolist() == [[2.5, 4.5], [10.5, 12.5]]
    c = plot_maps.block_average(np.ones((5, 5)), 2)  # padded with NaN, ignored
    assert c.shape == (3, 3) and np.all(c == 1)
    v = plot_maps.View(4096, 2048, 2.0, 1.0, plot_maps.grid_extent(4096, 2048, 2.0, 1.0))
    assert v.k == 4 and v.data(np.zeros((2048, 4096))).shape == (512, 1024)


def test_maps_without_fields_nc_use_a_staging_file(tmp_path):
    case = tmp_path / "c.toml"
    case.write_text(SLIDING)
    d = tmp_path / "out"
    gfmd("run", str(case), "-o", str(d), "-q", "--set", "output.fields=false")
    assert_pngs(str(d), FRICTION_MAPS)
    assert not (d / "fields.nc").exists() and not (d / plot_maps.STAGING).exists()
    # Nothing to redraw the maps from now: gfmd plot says so and does not fail.
    p = gfmd("plot", str(d))
    assert "no fields.nc" in p.stderr


def test_plot_refuses_a_directory_that_is_not_a_result(tmp_path):
    p = gfmd("plot", str(tmp_path), check=False)
    assert p.returncode == 2
    assert str(tmp_path) in p.stderr and "not a gfmd run, sweep, curve or study directory" in p.stderr
    assert os.listdir(tmp_path) == []


def test_script_reports_a_missing_fields_file(tmp_path):
    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "plot_maps.py"), str(tmp_path)],
                       capture_output=True, text=True)
    assert p.returncode == 2
    assert str(tmp_path / "fields.nc") in p.stderr and "no such file" in p.stderr
    (tmp_path / "fields.nc").write_text("not netcdf")
    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "plot_maps.py"), str(tmp_path)],
                       capture_output=True, text=True)
    assert p.returncode == 2 and "unreadable" in p.stderr, p.stderr


def test_sweep_points_and_flow_maps(tmp_path):
    case = tmp_path / "c.toml"
    case.write_text(HERTZ + "[stress]\nprofiles = false\n[flow]\ndirection = \"x\"\n")
    d = tmp_path / "sweep"
    gfmd("sweep", str(case), "-o", str(d), "-q", "--set", "load.force=0.005,0.01", "--plot", "mean_gap")
    for k in range(2):
        assert_pngs(str(d / f"point_{k:03d}"), MAPS + ["current_x"])
    for f in glob.glob(str(d / "point_*" / "*.png")):
        os.remove(f)
    os.utime(d / "sweep_mean_gap.png", (0, 0))
    gfmd("plot", str(d))
    assert (d / "sweep_mean_gap.png").stat().st_mtime > 0, "the sweep's plot was not redrawn"
    for k in range(2):
        assert_pngs(str(d / f"point_{k:03d}"), MAPS + ["current_x"])
    # gfmd flow draws the current maps of the direction it solved.
    gfmd("flow", str(d / "point_001"), "--direction", "y")
    assert_pngs(str(d / "point_001"), ["current_y"])


def test_python_run_with_output_draws_the_maps(tmp_path):
    if not glob.glob(os.path.join(BUILD, "python", "gfmd", "_core*.so")):
        pytest.skip("the Python module was not built")
    case = tmp_path / "c.toml"
    case.write_text(HERTZ)
    code = f"import gfmd; gfmd.run({str(case)!r}, output={str(tmp_path / 'out')!r})"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env=dict(ENV, PYTHONPATH=os.path.join(BUILD, "python")))
    assert p.returncode == 0, p.stderr
    assert "warning" not in p.stderr, p.stderr
    assert_pngs(str(tmp_path / "out"), MAPS + ["profiles"])


def test_a_line_contact_on_a_thin_cell_draws_its_maps_and_whole_profiles(tmp_path):
    """A cylinder on a cell a few points across its axis (a line contact) at a fine spacing
    (2048 x 4 points) averages to one row of blocks, where no outline can be drawn: the maps are
    drawn without it (plot_maps once failed there, 'Input z must be at least a (2, 2) shaped
    array'), and the
    profiles run along the long side, the whole cell (they once stopped at the short side's
    +-2 points)."""
    case = tmp_path / "line.toml"
    case.write_text("""
[grid]
nx = 2048
ny = 4
lx = 4.0
ly = 0.0078125
[indenter]
type = "cylinder"
radius = 1.0
[load]
pressure = 0.002
[output]
png = true
""")
    out = tmp_path / "out"
    p = gfmd("run", str(case), "-o", str(out), "-q")
    assert "not (all) drawn" not in p.stderr, p.stderr
    for name in MAPS + ["profiles"]:
        assert (out / f"{name}.png").is_file(), name
    # Drawn stretched (the zoomed view is about 41:1): axes an inch high, not a line (at true
    # aspect the figure was 232 pixels high in all, its map a few pixels).
    assert matplotlib.image.imread(str(out / "pressure.png")).shape[0] > 300
    lines = [ln for ln in (out / "profiles.csv").read_text().splitlines() if not ln.startswith("#")]
    cols = lines[0].split(",")
    table = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    s, p_long = table[:, cols.index("s")], table[:, cols.index("pressure_longitudinal")]
    assert s.max() - s.min() > 0.99 * 4.0
    # The whole contact (2a = 0.2 of the 4-long cell, about 100 points) and free surface on
    # either side of it.
    assert np.count_nonzero(p_long > 0) > 80
    assert p_long[0] == 0 and p_long[-1] == 0


def test_a_view_of_one_row_of_blocks_is_drawn_without_outlines(tmp_path):
    """A view block-averaged to one row (8192 x 4 points: blocks of 8 x 8) has no outline to
    draw; matplotlib's contour needs two rows (plot_maps once failed there: 'Input z must be at
    least a (2, 2) shaped array'). The map is drawn all the same."""
    nx, ny, lx, ly = 8192, 4, 4.0, 4.0 / 2048
    view = plot_maps.View(nx, ny, lx, ly, plot_maps.grid_extent(nx, ny, lx, ly))
    x = (np.arange(nx) - nx // 2) * lx / nx
    p = np.tile(np.clip(0.01 - x * x, 0, None), (ny, 1))
    assert view.data(p).shape[0] == 1
    path = tmp_path / "pressure.png"
    plot_maps.draw(str(path), view, p, "contact pressure", "p (E*)", "inferno", "positive", "L",
                   (p > 0).astype(float))
    assert path.is_file() and matplotlib.image.imread(str(path)).shape[0] > 300


def test_profiles_of_a_cell_with_unequal_spacings_stay_within_its_points(tmp_path):
    """64 x 64 points on a 1 x 0.01 cell (dy = dx / 100): the profiles step at the finer spacing
    but hold at most max(nx, ny) = 64 rows (over the longer side they would be 6 400)."""
    case = tmp_path / "flat.toml"
    case.write_text("""
[grid]
nx = 64
ny = 64
lx = 1.0
ly = 0.01
[indenter]
type = "cylinder"
radius = 1.0
[load]
pressure = 0.002
""")
    out = tmp_path / "out"
    gfmd("run", str(case), "-o", str(out), "-q", "--set", "output.png=false")
    rows = [ln for ln in (out / "profiles.csv").read_text().splitlines() if not ln.startswith("#")]
    assert 2 <= len(rows) - 1 <= 64
