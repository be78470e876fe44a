"""Output directories from Python: the same refusal, force and staging as the command line
(RunDirectory): Result.save, gfmd.run(output=) and gfmd.sweep never lose a user's files and a
failed write leaves the previous result as it was."""
import json
import os

import pytest

import gfmd

HERTZ = """
[grid]
nx = 64
lx = 4.0
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[output]
png = false
analysis = false
"""


def _solve():
    return gfmd.solve(gfmd.Topography.hertz(64, 4.0, radius=1.0), force=0.01)


def test_save_refuses_a_foreign_directory_unless_forced(tmp_path):
    r = _solve()
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "spectrum.csv").write_text("mine\n")
    with pytest.raises(gfmd.InputError, match="force"):
        r.save(str(mine))
    assert (mine / "spectrum.csv").read_text() == "mine\n"
    assert not (mine / "summary.json").exists()
    r.save(str(mine), force=True)
    assert (mine / "summary.json").exists()
    assert not (mine / ".gfmd-staging").exists()
    # gfmd's own directory now: a second save needs no force.
    r.save(str(mine))
    with pytest.raises(gfmd.InputError, match="force"):
        r.save(str(mine), force="yes")


def test_save_refuses_the_working_directory(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(gfmd.InputError, match="working directory"):
        _solve().save(".")
    assert os.listdir(tmp_path) == []


def test_run_checks_the_directory_before_solving(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(HERTZ)
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("x")
    with pytest.raises(gfmd.InputError, match="not made by gfmd"):
        gfmd.run(str(case), output=str(foreign))
    out = tmp_path / "out"
    gfmd.run(str(case), output=str(out))
    before = (out / "summary.json").read_text()
    # A re-run that fails keeps the converged result, and status.json says so.
    with pytest.raises(gfmd.SolveError):
        gfmd.run(str(case), set=["solver.max_iterations=2", "load.force=0.02"], output=str(out))
    assert (out / "summary.json").read_text() == before


def test_sweep_publishes_its_points_and_plot_together(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(HERTZ)
    out = tmp_path / "s"
    j = gfmd.sweep(str(case), "load.force", [0.006, 0.01], str(out), plot="relative_contact_area")
    assert j["completed"] == 2
    assert (out / "sweep_relative_contact_area.png").exists()
    assert not (out / ".gfmd-staging").exists()
    status = json.loads((out / "status.json").read_text())
    assert status["status"] == "converged"
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "a.txt").write_text("a")
    with pytest.raises(gfmd.InputError, match="force"):
        gfmd.sweep(str(case), "load.force", [0.006], str(foreign))
    assert sorted(os.listdir(foreign)) == ["a.txt"]
