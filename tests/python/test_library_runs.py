"""The command line's runs from the library (issue 43: a figure study runs in one process
through it): gfmd.run(resume=True) as `gfmd run --resume`, gfmd.sweep over the case's own
[sweep] as `gfmd sweep CASE`, gfmd.green as `gfmd green`, approach lists as `gfmd curve`
reads them, and SIGTERM stopping a solve where the program handles it in Python."""
import csv
import io
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import gfmd

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
GFMD = os.path.join(BUILD, "gfmd")

HERTZ = """
[grid]
nx = 64
lx = 4.0
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[friction]
coefficient = 0.5
[output]
png = false
analysis = false
"""

# A solve of about 20 s (thin nu = 0.49 layer, p = 0.3 E*, 512^2, stick; as in test_python_api).
SLOW = [os.path.join(ROOT, "examples", "fig2e_rough_layer_sweep.toml"), "grid.nx=512", "indenter.lambda_short=0.03125",
        "elastic.thickness=0.05", "load.pressure=0.3", "output.png=false"]


def cli(*args):
    p = subprocess.run([GFMD, *args], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return p


def test_run_resume_solves_once_then_reuses_as_the_command_line(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(HERTZ)
    out = tmp_path / "run"
    first = gfmd.run(str(case), output=str(out), resume=True)
    assert first["status"] == "solved" and first["summary"]["converged"]
    stamp = (out / "summary.json").stat().st_mtime_ns
    again = gfmd.run(str(case), output=str(out), resume=True)
    assert again["status"] == "reused"
    assert (out / "summary.json").stat().st_mtime_ns == stamp  # nothing was written
    assert again["summary"]["friction_coefficient"] == first["summary"]["friction_coefficient"]
    # The command line reuses the library's result, and solves the same numbers.
    p = cli("run", str(case), "-o", str(out), "--resume")
    assert "already solved" in p.stdout
    cli("run", str(case), "-o", str(tmp_path / "cli"))
    theirs = json.loads((tmp_path / "cli" / "summary.json").read_text())
    assert theirs["friction_coefficient"] == first["summary"]["friction_coefficient"]
    # Another setting is another case: solved again, into the same directory.
    other = gfmd.run(str(case), output=str(out), resume=True, set=["load.force=0.02"])
    assert other["status"] == "solved"
    assert other["summary"]["normal_force"] == pytest.approx(0.02, rel=1e-9)
    with pytest.raises(gfmd.InputError, match="resume: needs output"):
        gfmd.run(str(case), resume=True)


def test_run_resume_that_does_not_converge_publishes_nothing(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(HERTZ)
    out = tmp_path / "run"
    with pytest.raises(gfmd.SolveError, match=r"after \d+ iterations.*\[with set solver.max_iterations=2\]; "
                                               r"no results written"):
        gfmd.run(str(case), output=str(out), resume=True, set=["solver.max_iterations=2"])
    assert not (out / "summary.json").exists()
    assert json.loads((out / "status.json").read_text())["status"] == "failed"


@pytest.mark.parametrize("resume", [True, False])
def test_an_interrupted_run_keeps_nothing_half_done_and_its_checkpoint(tmp_path, resume):
    # With or without resume=True, a run into a directory that Ctrl-C stops leaves status.json
    # "interrupted" and the solve's checkpoint (without resume it once left no directory at all),
    # and resume=True continues from it.
    import signal
    import threading

    out = tmp_path / "run"
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        gfmd.run(SLOW[0], set=SLOW[1:], output=str(out), resume=resume)
    timer.cancel()
    assert json.loads((out / "status.json").read_text())["status"] == "interrupted"
    assert not (out / "summary.json").exists()
    assert not [f for f in os.listdir(out) if ".tmp" in f]
    assert (out / "checkpoint.bin").exists()
    if not resume:
        done = gfmd.run(SLOW[0], set=SLOW[1:], output=str(out), resume=True)
        assert done["status"] == "solved" and done["summary"]["resumed"]["iterations_before"] > 0


def test_run_into_a_directory_returns_the_fields_and_takes_one_override_string(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(HERTZ)
    a = gfmd.run(str(case), set="load.force=0.02", output=str(tmp_path / "out"))
    b = gfmd.run(str(case), set=["load.force=0.02"])
    assert a["summary"]["normal_force"] == pytest.approx(0.02, rel=1e-9)
    assert sorted(a["fields"]) == sorted(b["fields"])
    for name in b["fields"]:
        assert np.array_equal(a["fields"][name], b["fields"][name]), name
    assert json.loads((tmp_path / "out" / "status.json").read_text())["status"] == "converged"
    with pytest.raises(gfmd.InputError, match="set: each override"):
        gfmd.run(str(case), set=[3])


SIGTERM_DRIVER = """
import os, signal, sys, threading, time
sys.path.insert(0, {pydir!r})
import gfmd
seen = []
if {handled}:
    def on_term(signum, frame):
        seen.append(signum)
        raise KeyboardInterrupt
    signal.signal(signal.SIGTERM, on_term)
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGTERM)).start()
t0 = time.monotonic()
try:
    gfmd.run({case!r}, set={sets!r})
    print("finished")
except KeyboardInterrupt:
    print("interrupted", seen == [signal.SIGTERM], round(time.monotonic() - t0, 1))
"""


@pytest.mark.parametrize("handled", [True, False])
def test_sigterm_stops_a_solve_where_python_handles_it(handled):
    # With a Python handler for SIGTERM (a study driver's), the solve stops within a second, the
    # handler sees the signal and its exception ends the call; without one SIGTERM keeps its
    # default: the process ends at once.
    code = SIGTERM_DRIVER.format(pydir=os.path.join(BUILD, "python"), handled=handled, case=SLOW[0], sets=SLOW[1:])
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    if handled:
        assert p.returncode == 0, p.stderr
        word, saw, took = p.stdout.split()
        assert (word, saw) == ("interrupted", "True"), p.stdout
        assert float(took) < 3.0, p.stdout
    else:
        assert p.returncode == -15, (p.returncode, p.stdout, p.stderr)
        assert p.stdout == ""


def test_sweep_over_the_cases_own_sweep_table_as_the_command_line(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(HERTZ.replace("png = false", "png = true")
                    + '[sweep]\nparameter = "load.force"\nvalues = [0.005, 0.01]\n')
    table = gfmd.sweep(str(case), output=str(tmp_path / "lib"))
    assert (table["parameter"], table["values"], table["completed"]) == ("load.force", [0.005, 0.01], 2)
    cli("sweep", str(case), "-o", str(tmp_path / "cli"), "-q")
    ours = (tmp_path / "lib" / "sweep.csv").read_text().splitlines()
    theirs = (tmp_path / "cli" / "sweep.csv").read_text().splitlines()
    assert len(ours) == 3
    head = ours[0].split(",")
    keep = [i for i, k in enumerate(head) if "time" not in k]  # wall times differ
    assert [[r.split(",")[i] for i in keep] for r in ours] == [[r.split(",")[i] for i in keep] for r in theirs]
    # The points' maps are drawn as the command line draws them (output.png).
    for point in ("point_000", "point_001"):
        assert (tmp_path / "lib" / point / "pressure.png").stat().st_size > 1000
    plain = tmp_path / "plain.toml"
    plain.write_text(HERTZ)
    with pytest.raises(gfmd.InputError, match="nothing to sweep"):
        gfmd.sweep(str(plain), output=str(tmp_path / "none"))
    with pytest.raises(gfmd.InputError, match="values: give a parameter with its values"):
        gfmd.sweep(str(case), "load.force", output=str(tmp_path / "x"))


def test_green_is_the_command_lines_table():
    rows = gfmd.green(poisson=[0.0, 0.3], qh_from=0.1, qh_to=10.0, points=5)
    text = cli("green", "--poisson", "0,0.3", "--from", "0.1", "--to", "10", "--points", "5").stdout
    theirs = list(csv.DictReader(io.StringIO(text)))
    assert len(rows) == len(theirs) == 10
    for a, b in zip(rows, theirs):
        assert a == {k: float(v) for k, v in b.items()}
    with pytest.raises(gfmd.InputError, match="poisson"):
        gfmd.green(poisson=[0.6])
    with pytest.raises(gfmd.InputError, match="qh_to: must exceed qh_from"):
        gfmd.green(qh_from=1.0, qh_to=0.5)


def test_green_output_replaces_only_its_own_tables(tmp_path):
    # `gfmd green -o` once replaced any file (a run's summary.json): now only a green table, or
    # another file with --force (force=True); a directory or a missing folder is refused.
    other = tmp_path / "summary.json"
    other.write_text('{"normal_force": 1}\n')
    args = ["green", "--points", "3", "-o"]
    p = subprocess.run([GFMD, *args, str(other)], capture_output=True, text=True)
    assert p.returncode == 2 and "is not a table of gfmd green" in p.stderr and str(other) in p.stderr, p.stderr
    assert other.read_text() == '{"normal_force": 1}\n'
    with pytest.raises(gfmd.InputError, match="is not a table of gfmd green"):
        gfmd.green(points=3, output=str(other))
    table = tmp_path / "phi.csv"
    cli(*args, str(table))
    first = table.read_text()
    cli("green", "--points", "4", "-o", str(table))  # its own table: replaced
    assert table.read_text() != first and table.read_text().startswith("poisson,qh,")
    gfmd.green(points=3, output=str(other), force=True)
    assert other.read_text() == first
    for bad, why in ((tmp_path, "is a directory"), (tmp_path / "no" / "t.csv", "does not exist")):
        p = subprocess.run([GFMD, *args, str(bad)], capture_output=True, text=True)
        assert p.returncode == 2 and why in p.stderr, p.stderr


def test_approach_lists_read_as_the_command_line_reads_them():
    assert gfmd._core.parse_approaches("0.01:-0.01:3") == [0.01, 0.0, -0.01]
    assert gfmd._core.parse_approaches("0.02,0.01") == [0.02, 0.01]
    assert gfmd._core.parse_pressures("0.001:0.1:3") == pytest.approx([0.001, 0.01, 0.1], rel=1e-12)
    with pytest.raises(gfmd.InputError, match="approaches"):
        gfmd._core.parse_approaches("0.01,,0.02")


def test_curve_draws_its_figure_where_the_case_asks_for_figures(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(HERTZ.replace("png = false", "png = true"))
    j = gfmd.curve(str(case), pressures="0.001:0.004:2", output=str(tmp_path / "c"))
    assert [p["pressure"] for p in j["points"]] == pytest.approx([0.001, 0.004], rel=1e-12)
    assert (tmp_path / "c" / "curve.png").stat().st_size > 1000
    gfmd.curve(str(case), pressures=[0.001], output=str(tmp_path / "d"), set=["output.png=false"])
    assert not (tmp_path / "d" / "curve.png").exists()


def test_a_sweep_that_stops_publishes_its_finished_points_with_their_figures(tmp_path):
    # The second point cannot converge (two iterations): the first attempt publishes the first
    # point with its maps and the sweep plot (drawn before publication, by both front ends).
    case = tmp_path / "case.toml"
    case.write_text(HERTZ.replace("png = false", "png = true"))
    with pytest.raises(gfmd.SolveError, match="the 1 finished points are kept in"):
        gfmd.sweep(str(case), "solver.max_iterations", [1000, 2], output=str(tmp_path / "lib"),
                   plot="relative_contact_area")
    p = subprocess.run([GFMD, "sweep", str(case), "-o", str(tmp_path / "cli"), "-q", "--plot", "relative_contact_area",
                        "--set", "solver.max_iterations=1000,2"], capture_output=True, text=True)
    assert p.returncode == 3, p.stderr
    assert "the finished points are drawn in" in p.stderr, p.stderr
    for d in ("lib", "cli"):
        assert (tmp_path / d / "sweep_relative_contact_area.png").stat().st_size > 1000
        assert (tmp_path / d / "point_000" / "pressure.png").stat().st_size > 1000
        assert not (tmp_path / d / "point_001").exists()
        assert len((tmp_path / d / "sweep.csv").read_text().splitlines()) == 2


@pytest.mark.parametrize("resume", [False, True])
def test_ctrl_c_while_drawing_keeps_the_finished_solve(tmp_path, monkeypatch, resume):
    # The drawing interpreter (GFMD_PYTHON) stands in for a Ctrl-C that lands while the maps are
    # drawn: it sends SIGINT to this process. The solve had finished: its data files are
    # published without the maps (status.json says so) and KeyboardInterrupt goes on; a resumed
    # call finds the result. They were thrown away.
    case = tmp_path / "case.toml"
    case.write_text(HERTZ.replace("png = false", "png = true"))
    stopper = tmp_path / "stopper.sh"
    stopper.write_text("#!/bin/sh\nkill -INT $PPID\nsleep 5\n")
    stopper.chmod(0o755)
    monkeypatch.setenv("GFMD_PYTHON", str(stopper))
    out = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt):
        gfmd.run(str(case), output=str(out), resume=resume)
    status = json.loads((out / "status.json").read_text())
    assert status["status"] == "converged"
    assert "their figures may be missing" in status["reason"]
    assert (out / "summary.json").exists() and (out / "fields.nc").exists()
    assert not (out / "pressure.png").exists()
    monkeypatch.delenv("GFMD_PYTHON")
    assert gfmd.run(str(case), output=str(out), resume=True)["status"] == "reused"


def test_a_result_saves_the_case_that_solves_it_again(tmp_path):
    # Result.toml once named indenter.type = "array" with keys a case file refuses; save_case
    # writes the case and the given heights beside it, and gfmd.run solves it to the same bits.
    top = gfmd.Topography.hertz(64, 2.0, radius=1.0)
    r = gfmd.solve(top, gfmd.ElasticBody(poisson=0.3), force=0.005, friction=0.3)
    assert 'type = "file"' in r.toml and "heights.npy" in r.toml and "calling program" in r.toml
    r.save_case(str(tmp_path / "again.toml"))
    assert (tmp_path / "again_heights.npy").exists()
    again = gfmd.run(str(tmp_path / "again.toml"))
    for name in ("pressure", "traction_x", "uz"):
        assert np.array_equal(again["fields"][name], r.fields[name]), name
    assert again["summary"]["friction_coefficient"] == r.summary["friction_coefficient"]
    with pytest.raises(gfmd.InputError, match="ends in .toml"):
        r.save_case(str(tmp_path / "again.txt"))


def test_the_harmonic_stiffness_is_a_keyword():
    # interaction.stiffness could not be set from Python (an unknown keyword).
    top = gfmd.Topography.hertz(64, 2.0, radius=1.0)
    soft = gfmd.solve(top, force=0.005, stiffness=4.0)
    assert soft.summary["interaction_stiffness"] == 4.0
    assert soft.summary["input"]["interaction"]["stiffness"] == 4.0
    assert gfmd.solve(top, force=0.005).summary["interaction_stiffness"] == 64.0  # 2 E*/dx
    with pytest.raises(gfmd.InputError, match="stiffness: belongs to the harmonic repulsion"):
        gfmd.solve(top, force=0.005, interaction="hardwall", stiffness=4.0)


def test_python_arguments_are_refused_by_name_not_by_type_errors():
    # Each of these raised a TypeError (or blamed another argument) before.
    with pytest.raises(gfmd.InputError, match="lambda_short: the default, lambda_long/128"):
        gfmd.Topography.self_affine(128, 1.0, rms_height=0.01)
    with pytest.raises(gfmd.InputError, match="generator: unknown generator 'foo'"):
        gfmd.Topography.self_affine(128, 1.0, rms_height=0.01, lambda_short=0.05, generator="foo")
    with pytest.raises(gfmd.InputError, match="seed: must be an integer in"):
        gfmd.Topography.self_affine(128, 1.0, rms_height=0.01, lambda_short=0.05, seed=2 ** 70)
    spike = np.zeros((32, 32))
    spike[3, 4] = 1e200
    with pytest.raises(gfmd.InputError, match="rms gradient is not finite"):
        gfmd.Topography.from_array(spike, 1.0)
    top = gfmd.Topography.indenter("hertz", 32, 2.0, radius=np.int64(1))
    assert np.array_equal(top.heights, gfmd.Topography.hertz(32, 2.0, radius=1.0).heights)
    with pytest.raises(gfmd.InputError, match="stress_depths: a list of depths"):
        gfmd.solve(top, force=0.005, stress_depths=0.1)


def test_a_crop_is_whole_numbers(tmp_path):
    # crop=(0.5, ...) was truncated to 0 without a word.
    np.save(tmp_path / "m.npy", np.random.default_rng(1).normal(size=(32, 48)) * 0.01)
    piece = gfmd.Topography.read(str(tmp_path / "m.npy"), lx=1.0, crop=(0, 0, 16, 16))
    assert piece.lx == 1.0 and piece.heights.shape == (16, 16)  # lx: the piece kept
    with pytest.raises(gfmd.InputError, match="crop: .* four whole numbers"):
        gfmd.Topography.read(str(tmp_path / "m.npy"), lx=1.0, crop=(0.5, 0, 16, 16))
