"""Studies over seeds (a series' `seeds`), reference curves and a [second] panel
(studies/fig2e.toml's machinery), and the paper authors' surface generator from Python."""
import csv
import os
import subprocess

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
ENV = dict(os.environ, GFMD=os.path.join(BUILD, "gfmd"))
STUDY = ["/usr/bin/python3", os.path.join(ROOT, "scripts", "study.py")]
CASE = os.path.join(ROOT, "examples", "fig2e_rough_layer_sweep.toml")


def study_text(seeds='"0..2"', extra=""):
    return f'''title = "seeds"
kind = "sweep"
x = "load.pressure"
y = "downhill_friction"
table_columns = ["relative_contact_area"]

[[series]]
label = "coupled"
seeds = {seeds}
y_scale = 2.0
case = "{CASE}"
set = ["friction.coefficient=0.5"]

[[series]]
label = "one seed"
case = "{CASE}"
set = ["friction.coefficient=0.5"]

[quick]
set = ["grid.nx=32", "indenter.lambda_short=0.25", "sweep.points=2", "sweep.from=0.01", "sweep.to=0.1", "output.png=false"]

[published]
divide_by = "topography.rms_gradient"

[second]
y = "delta_mu_over_mu_c"
{extra}'''


def run(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path, subprocess.run(STUDY + [str(path), "--quick", "-o", str(tmp_path / "out")], capture_output=True,
                                text=True, env=ENV)


def test_seeded_series_table_every_seed_and_its_statistics(tmp_path):
    ref = tmp_path / "ref.csv"
    ref.write_text("a,b,c\n1,0.001,0.1\n1,0.01,0.2\n2,0.01,0.3\n")
    _, p = run(tmp_path, study_text(extra=f'''
[[reference]]
label = "published"
file = "{ref}"
x = "b"
y = "c"
where = ["a=1"]
'''))
    assert p.returncode == 0, p.stderr
    d = tmp_path / "out" / "s" / "quick"
    with open(d / "s.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert list(table[0]) == ["panel", "series", "x", "y", "relative_contact_area", "seed", "quantity"]
    pub = [r for r in table if r["panel"] == "published" and r["series"] == "coupled"]
    per_seed = {s: [r for r in pub if r["seed"] == s] for s in ("0", "1", "2")}
    assert all(len(v) == 2 for v in per_seed.values())  # every seed, both loads
    # The seeds are different surfaces: their values differ.
    assert len({r["y"] for r in pub if r["seed"] in ("0", "1", "2")}) == 6
    for k in range(2):
        ys = np.array([float(per_seed[s][k]["y"]) for s in ("0", "1", "2")])
        stat = {r["seed"]: float(r["y"]) for r in pub if r["seed"] in ("mean", "std", "min", "max")
                and abs(float(r["x"]) - np.mean([float(per_seed[s][k]["x"]) for s in per_seed])) < 1e-12}
        assert stat["mean"] == pytest.approx(ys.mean(), rel=1e-12)
        assert stat["std"] == pytest.approx(ys.std(ddof=1), rel=1e-12)
        assert (stat["min"], stat["max"]) == (ys.min(), ys.max())
    # Each seed's sweep is its own directory with its seed; y_scale and the division by the
    # realised rms gradient are applied per seed.
    for s in ("0", "1", "2"):
        with open(d / "series_00" / f"seed_{s}" / "sweep.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        for r, t in zip(rows, per_seed[s]):
            g = float(r["topography.rms_gradient"])
            assert float(t["y"]) == pytest.approx(2.0 * float(r["downhill_friction"]) / g, rel=1e-12)
    # The second panel draws delta_mu_over_mu_c (not scaled by y_scale); the unseeded series has
    # an empty seed.
    sec = [r for r in table if r["panel"] == "second" and r["series"] == "one seed"]
    assert sec and all(r["quantity"] == "delta_mu_over_mu_c" and r["seed"] == "" for r in sec)
    assert (d / "s.png").stat().st_size > 10000
    # --draw-only draws from the runs on disk and runs nothing (no gfmd to run here): a seed whose
    # runs are gone is left out of the mean, a series without runs out of the figure.
    import shutil
    shutil.rmtree(d / "series_00" / "seed_2")
    shutil.rmtree(d / "series_01")
    (d / "s.png").unlink()
    p = subprocess.run(STUDY + [str(tmp_path / "s.toml"), "--quick", "-o", str(tmp_path / "out"), "--draw-only"],
                       capture_output=True, text=True, env=dict(ENV, GFMD="/nonexistent/gfmd"))
    assert p.returncode == 0, p.stderr
    assert "seed 2 has no runs" in p.stderr and "series[2] (one seed): no runs" in p.stderr
    assert (d / "s.png").stat().st_size > 10000
    with open(d / "s.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert {r["series"] for r in table} == {"coupled"}
    assert {r["seed"] for r in table} == {"0", "1", "mean", "std", "min", "max"}
    assert not (d / "series_01").exists()
    p = subprocess.run(STUDY + [str(tmp_path / "s.toml"), "--quick", "-o", str(tmp_path / "out"), "--draw-only",
                                "--runs-only"], capture_output=True, text=True, env=ENV)
    assert p.returncode == 2 and "exclude each other" in p.stderr
    # Nothing on disk to draw from (a mistyped -o): refused, no empty figure, nothing made.
    p = subprocess.run(STUDY + [str(tmp_path / "s.toml"), "--quick", "-o", str(tmp_path / "typo"), "--draw-only"],
                       capture_output=True, text=True, env=ENV)
    assert p.returncode == 2 and "no runs of this study" in p.stderr, p.stderr
    assert not (tmp_path / "typo").exists()
    # The same from gfmd study and from Python.
    (d / "s.png").unlink()
    p = subprocess.run([ENV["GFMD"], "study", str(tmp_path / "s.toml"), "--quick", "-o", str(tmp_path / "out"),
                        "--draw-only"], capture_output=True, text=True, env=ENV)
    assert p.returncode == 0, p.stderr
    assert (d / "s.png").stat().st_size > 10000
    import gfmd
    j = gfmd.study(str(tmp_path / "s.toml"), quick=True, output=str(tmp_path / "out"), draw_only=True)
    assert j["series"] == ["coupled"]
    # gfmd study --runs-only (and Python's runs_only=True) runs the missing series and draws
    # nothing; with --draw-only it is refused.
    (d / "s.png").unlink()
    p = subprocess.run([ENV["GFMD"], "study", str(tmp_path / "s.toml"), "--quick", "-o", str(tmp_path / "out"),
                        "--runs-only"], capture_output=True, text=True, env=ENV)
    assert p.returncode == 0, p.stderr
    assert (d / "series_01" / "sweep.csv").exists() and (d / "series_00" / "seed_2" / "sweep.csv").exists()
    assert not (d / "s.png").exists()
    p = subprocess.run([ENV["GFMD"], "study", str(tmp_path / "s.toml"), "--quick", "--runs-only", "--draw-only"],
                       capture_output=True, text=True, env=ENV)
    assert p.returncode != 0 and "--draw-only" in p.stderr
    assert gfmd.study(str(tmp_path / "s.toml"), quick=True, output=str(tmp_path / "out"),
                      runs_only=True) == {"study": "s", "runs": str(d)}
    with pytest.raises(gfmd.InputError, match="exclude each other"):
        gfmd.study(str(tmp_path / "s.toml"), quick=True, draw_only=True, runs_only=True)
    assert not (d / "s.png").exists()


@pytest.mark.parametrize("seeds,says", [('"3..1"', 'series[1].seeds: "3..1" is not FIRST..LAST'),
                                        ("[1, 1]", "series[1].seeds: a seed is listed twice"),
                                        ('"0..99"', "series[1].seeds: 100 seeds; at most 64")])
def test_bad_seeds_exit_2_naming_the_key(tmp_path, seeds, says):
    path, p = run(tmp_path, study_text(seeds=seeds))
    assert p.returncode == 2, p.stderr
    assert p.stderr.strip() == f"gfmd study: {path}: {says}" or p.stderr.startswith(f"gfmd study: {path}: {says}")
    assert not (tmp_path / "out").exists()


def test_reference_without_its_column_exits_2(tmp_path):
    ref = tmp_path / "ref.csv"
    ref.write_text("a,b\n1,2\n")
    path, p = run(tmp_path, study_text(extra=f'[[reference]]\nlabel = "r"\nfile = "{ref}"\nx = "a"\ny = "z"\n'))
    assert p.returncode == 2, p.stderr
    assert "reference[1]" in p.stderr and "no column 'z'" in p.stderr, p.stderr


def test_authors_generator_from_python():
    import gfmd

    # The peak-to-valley height the paper authors' code printed for their seed 4711 at 2048^2
    # (params.out of their published runs): the same surface, drawn here.
    t = gfmd.Topography.self_affine(2048, 2.0, lambda_long=1.0, lambda_short=0.0078125, rms_height=0.01,
                                    seed=4711, generator="contmech")
    h = np.asarray(t.heights)
    assert h.max() - h.min() == pytest.approx(0.0658367, abs=6e-8)
    with pytest.raises(gfmd.InputError, match="generator"):
        gfmd.Topography.self_affine(64, 2.0, lambda_long=1.0, lambda_short=0.125, rms_height=0.01,
                                    generator="contmek")
