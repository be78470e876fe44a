"""A pull_off study (studies/adhesion_coupling.toml's machinery): one unloading path per value of a
key, the pull-off and the contact there per row, the figure and its table; bad study files exit 2."""
import csv
import os
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
ENV = dict(os.environ, GFMD=os.path.join(BUILD, "gfmd"))
STUDY = ["/usr/bin/python3", os.path.join(ROOT, "scripts", "study.py")]
CASE = os.path.join(ROOT, "examples", "adhesive_sliding_sphere.toml")


def study_text(values="[1e-4, 0.03]", approaches='"0.004:-0.008:7"'):
    return f'''title = "pull-off"
kind = "pull_off"
x = "friction.shear_strength"
values = {values}
approaches = {approaches}

[second]
y = "pull_off_contact_radius"

[[series]]
label = "uncoupled"
case = "{CASE}"
y_scale = 318.30988618
set = ["elastic.poisson=0.5"]

[quick]
set = ["grid.nx=64"]
'''


def run(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path, subprocess.run(STUDY + [str(path), "--quick", "-o", str(tmp_path / "out")], capture_output=True,
                                text=True, env=ENV)


def test_pull_off_rows_per_value_and_the_uncoupled_shear_changes_nothing(tmp_path):
    _, p = run(tmp_path, study_text())
    assert p.returncode == 0, p.stderr
    out = tmp_path / "out" / "s" / "quick"
    assert (out / "s.png").is_file()
    rows = list(csv.reader(open(out / "s.csv")))
    body = [r for r in rows[1:] if r and not r[0].startswith("#")]
    # Two panels (the pull-off, scaled; the contact radius), one row per value each.
    assert len(body) == 4, rows
    pull = [float(r[3]) for r in body if r[-1] == "pull_off_force"]
    radius = [float(r[3]) for r in body if r[-1] == "pull_off_contact_radius"]
    assert len(pull) == 2 and len(radius) == 2
    # An incompressible half-space: the shear does not reach the normal problem (Menga, Carbone &
    # Dini), so the pull-off and the contact at it are the same at tau0 = 1e-4 and 0.03 E*; near
    # Maugis's -1.60 pi w R (64^2 on 1.5 R, a path in steps of 0.002 R: within 3 %).
    assert pull[1] == pytest.approx(pull[0], rel=1e-6)
    assert radius[1] == radius[0]
    assert pull[0] == pytest.approx(-1.60, rel=0.03)


@pytest.mark.parametrize("kw,says", [({"values": "[]"}, "values: must be a non-empty list of numbers"),
                                     ({"values": '["a"]'}, "values: must be a non-empty list of numbers"),
                                     ({"approaches": '"0.01:-0.01"'}, "approaches: must be FROM:TO:N"),
                                     ({"approaches": '"0.01:x:5"'}, "approaches: must be FROM:TO:N"),
                                     ({"approaches": '"inf:-0.01:5"'}, "approaches: must be FROM:TO:N"),
                                     ({"approaches": '"-0.01:0.01:5"'}, "approaches: must be FROM:TO:N, an unloading"),
                                     ({"extra": 'y = "pull_of_force"\n'}, "y: 'pull_of_force' is not a column"),
                                     ({"extra": '[published]\ndivide_by = "x"\n'}, "published: belongs to a sweep")])
def test_bad_pull_off_study_exits_2_naming_the_key(tmp_path, kw, says):
    text = study_text(**{k: v for k, v in kw.items() if k != "extra"})
    if "extra" in kw:
        text = kw["extra"] + text if kw["extra"].startswith("y") else text + kw["extra"]
    path, p = run(tmp_path, text)
    assert p.returncode == 2, p.stderr
    assert p.stderr.startswith(f"gfmd study: {path}: {says}"), p.stderr
    assert not (tmp_path / "out").exists()
