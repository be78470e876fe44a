"""End-to-end checks of the quick studies (paper Fig. 2d and Fig. 3 j-m): key numbers against
stated tolerances, and a re-run that recomputes nothing."""
import csv
import math
import os
import subprocess
import time

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STUDY = [os.path.join("/usr/bin/python3"), os.path.join(ROOT, "scripts", "study.py")]


def run_study(name, out):
    t = time.time()
    subprocess.run(STUDY + [os.path.join(ROOT, "studies", name + ".toml"), "--quick", "-o", str(out)],
                   check=True, capture_output=True, text=True)
    return time.time() - t


def rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def study_curves(out, name):
    """A quick sweep study's table as {(series, quantity): [y in the order of x]} (with seeds:
    their mean)."""
    table = rows(out / name / "quick" / (name + ".csv"))
    points = {}
    for r in table[1:]:
        d = dict(zip(table[0], r))
        if d.get("seed", "mean") == "mean":
            points.setdefault((d["series"], d["quantity"]), {})[float(d["x"])] = float(d["y"])
    return {k: [c[x] for x in sorted(c)] for k, c in points.items()}


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    return tmp_path_factory.mktemp("studies")


def test_fig2d_quick_signs_and_cube_root_law(out):
    first = run_study("fig2d", out)
    table = rows(out / "fig2d" / "quick" / "fig2d.csv")[1:]
    comp = [(float(x), float(y)) for _, s, x, y in table if s.startswith("ν = 0.25")]
    conf = [(float(x), float(y)) for _, s, x, y in table if s.startswith("ν = 0.49")]
    assert len(comp) == 5 and len(conf) == 5
    # Paper Fig. 2(d): compressible coupling lowers friction, confinement raises it.
    assert all(y < 0 for _, y in comp)
    assert all(y > 0 for _, y in conf)
    # |Delta mu| ~ F^(1/3) for the compressible half-space (least-squares slope within 0.05).
    lx = [math.log(x) for x, _ in comp]
    ly = [math.log(-y) for _, y in comp]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    slope = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)
    assert abs(slope - 1 / 3) < 0.05, slope
    # Re-running recomputes nothing and redraws the same data.
    before = (out / "fig2d" / "quick" / "fig2d.csv").read_text()
    second = run_study("fig2d", out)
    assert (out / "fig2d" / "quick" / "fig2d.csv").read_text() == before
    assert second < 0.25 * first + 5.0, (first, second)
    assert (out / "fig2d" / "quick" / "fig2d.png").stat().st_size > 10000
    assert (out / "fig2d" / "quick" / "fig2d.pdf").exists()


def test_fig3jm_quick_percolation_shifts(out):
    run_study("fig3jm", out)
    table = rows(out / "fig3jm" / "quick" / "fig3jm.csv")
    head, data = table[0], table[1:]
    r = {d[0]: dict(zip(head[1:], map(float, d[1:]))) for d in data}
    comp = r["ν = 0.25, h = ∞"]
    conf = r["ν = 0.49, h = λ/10"]
    # Dapp & Mueser: a_c* = 0.405 (half-space); ~0.5 for the confined layer (paper).
    assert abs(comp["a_c*_frictionless"] - 0.405) < 0.01
    assert abs(conf["a_c*_frictionless"] - 0.5) < 0.01
    # Friction + coupling enlarge the contact at the same pressure: 0.405 -> 0.416, 0.5 -> 0.556.
    assert 0.005 < comp["a_c_sliding_at_p*"] - comp["a_c_static_at_p*"] < 0.03
    assert 0.03 < conf["a_c_sliding_at_p*"] - conf["a_c_static_at_p*"] < 0.09
    # Constrictions open along the sliding direction and close across it.
    for m in (comp, conf):
        assert m["a_c*_friction_along_sliding"] > m["a_c*_frictionless"] > m["a_c*_friction_across_sliding"]


def test_sweep_series_that_stops_early_is_drawn_and_reported(tmp_path):
    # Point 0 converges; point 1 asks for an unreachable tolerance within 60 iterations and
    # stops (also after the cold-start retry). The study keeps point 0, draws the series as
    # stopped, lists it in study.json and exits non-zero.
    case = tmp_path / "case.toml"
    case.write_text(open(os.path.join(ROOT, "examples", "hertz_nu025.toml")).read()
                    + "\n[solver]\nmax_iterations = 60\n"
                    + "\n[sweep]\nparameter = \"solver.tolerance\"\nvalues = [1e-4, 1e-30]\n"
                    + "plot = \"relative_contact_area\"\n")
    study = tmp_path / "partial.toml"
    study.write_text(f'title = "partial"\nkind = "sweep"\nx = "solver.tolerance"\n'
                     f'y = "relative_contact_area"\n\n[[series]]\nlabel = "s"\ncase = "{case}"\n\n'
                     f'[quick]\nset = ["grid.nx=64"]\n')
    p = subprocess.run(STUDY + [str(study), "--quick", "-o", str(tmp_path / "out")],
                       capture_output=True, text=True)
    assert p.returncode == 3  # not converged
    assert "stopped early" in p.stderr
    d = tmp_path / "out" / "partial" / "quick"
    table = rows(d / "partial.csv")[1:]
    assert [r[1] for r in table] == ["s (stopped: not converged)"]
    assert 0.0 < float(table[0][3]) < 1.0
    assert (d / "partial.png").exists()
    import json
    report = json.load(open(d / "study.json"))
    assert report["incomplete_series"][0]["series"] == "s"
    assert "not converged" in report["incomplete_series"][0]["reason"]


def test_fig3ad_quick_paper_post_analysis_ratios(out):
    """Paper Fig. 3(a-d): against the paper's post-analysis (the frictionless solution with
    sigma_xz = mu_c p written in) the full solution's sigma_I^max is larger by factors
    "easily surpassing two to four" (paper); against the consistent post-analysis (the
    friction's strain included) it is not. Quick resolution: 256^2, lambda_s = lambda_l/16."""
    run_study("fig3ad", out)
    d = out / "fig3ad" / "quick"
    table = rows(d / "fig3ad_ratios.csv")
    head, body = table[0], table[1:]
    ratio = {(r[0].split(":")[0], r[1]): float(r[head.index("full_over_post_sigma_I_max")]) for r in body}
    assert set(ratio) == {(b, k) for b in ("compressible", "confined") for k in ("paper", "consistent")}
    assert ratio[("compressible", "paper")] > 4.0
    assert ratio[("confined", "paper")] > 2.0
    assert 0.7 < ratio[("compressible", "consistent")] < 1.4
    assert 0.7 < ratio[("confined", "consistent")] < 1.4
    assert (d / "fig3ad.png").stat().st_size > 10000


# ---------------------------------------------------------------------------------------
# Bad input (exit 2, one line naming the file and the key) and interruption (exit 4, one
# line, no traceback, no temporary file; the same command then finishes, reusing the runs).

BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
ENV = dict(os.environ, GFMD=os.path.join(BUILD, "gfmd"))
INTERRUPTED = "gfmd: study interrupted; run the same command again to continue"


def small_sweep_study(tmp_path, points=2):
    """Two series of `points` Hertz loads at 64^2 (about a second per point), no maps."""
    case = tmp_path / "case.toml"
    loads = ", ".join(repr(0.004 + 0.002 * k) for k in range(points))
    case.write_text(open(os.path.join(ROOT, "examples", "hertz_nu025.toml")).read()
                    + f"\n[sweep]\nparameter = \"load.force\"\nvalues = [{loads}]\n"
                    + "plot = \"relative_contact_area\"\n")
    study = tmp_path / "small.toml"
    study.write_text(f'title = "small"\nkind = "sweep"\nx = "load.force"\ny = "relative_contact_area"\n\n'
                     f'[[series]]\nlabel = "a"\ncase = "{case}"\n\n'
                     f'[[series]]\nlabel = "b"\ncase = "{case}"\nset = ["elastic.poisson=0.4"]\n\n'
                     f'[quick]\nset = ["grid.nx=64", "output.png=false"]\n')
    return study


def temporary_files(top):
    return [os.path.join(d, f) for d, _, files in os.walk(top) for f in files if ".tmp" in f]


@pytest.mark.parametrize("text, reason", [
    (None, "no such file"),
    ("case", "this is a case file ([grid]), use gfmd run"),
    ('title = "t"\nkind = "sweep"\nx = "load.force"\ny = "mu"\n', "no [[series]] table"),
    ('kind = "sweep"\nx = "load.force"\ny = "mu"\n[[series]]\nlabel = "a"\ncase = "CASE"\nset = "grid.nx=64"\n',
     "series[1].set: must be a list of strings"),
    ('kind = "sweep"\nx = "load.force"\ny = "mu"\n[[series]]\nlabel = "a"\ncase = "CASE"\n'
     '[[series]]\ncase = "CASE"\n', "series[2].label: missing"),
    ('kind = "sweep"\nx = "load.force"\ny = "mu"\n[[series]]\nlabel = "a"\ncase = "nothere.toml"\n',
     "series[1].case: nothere.toml: no such file"),
    ('kind = "sweeps"\n[[series]]\nlabel = "a"\ncase = "CASE"\n', "kind: must be one of"),
    ('kind = "sweep"\nx = "load.force"\n[[series]]\nlabel = "a"\ncase = "CASE"\n', "y: missing"),
    ('kind = "runs"\n[[series]]\nlabel = "a"\ncase = "CASE"\n', "no [[maps]] table"),
    ('kind = "sweep"\nx = "load.force"\ny = "mu"\nseries = 3\n', "series: must be an array of tables"),
    ('kind = "sweep"\nx = "load.force"\ny = "mu"\n[[series]]\nlabel = "a"\ncase = "CASE"\n[quick]\nset = ["grid.nx"]\n',
     'quick.set: "grid.nx" is not key=value'),
    ("kind = \n", "not valid TOML"),
])
def test_bad_study_file_exits_2_naming_file_and_key(tmp_path, text, reason):
    case = os.path.join(ROOT, "examples", "hertz_nu025.toml")
    if text is None:
        path = str(tmp_path / "nothere.toml")
    elif text == "case":
        path = case
    else:
        path = str(tmp_path / "bad.toml")
        with open(path, "w") as f:
            f.write(text.replace("CASE", case))
    out = tmp_path / "out"
    p = subprocess.run(STUDY + [path, "--quick", "-o", str(out)], capture_output=True, text=True, env=ENV)
    assert p.returncode == 2, p.stderr
    assert p.stderr.splitlines() == [p.stderr.strip()], p.stderr  # one line
    assert p.stderr.startswith(f"gfmd study: {path}: {reason}"), p.stderr
    assert not out.exists()  # nothing written


def test_setting_a_run_refuses_exits_2_naming_the_series(tmp_path):
    study = small_sweep_study(tmp_path, points=2)
    p = subprocess.run(STUDY + [str(study), "--quick", "-o", str(tmp_path / "out"), "--set", "grid.nx=\"many\""],
                       capture_output=True, text=True, env=ENV)
    assert p.returncode == 2, p.stderr
    assert p.stderr.startswith(f"gfmd study: {study}: series[1] (a): "), p.stderr
    assert "grid.nx" in p.stderr and "Traceback" not in p.stderr


def wait_for(path, proc, what):
    """Polls until path exists (the study is still running then, or the test fails)."""
    for _ in range(1200):
        if os.path.exists(path):
            return
        assert proc.poll() is None, f"the study ended before {what}: {proc.communicate()}"
        time.sleep(0.05)
    proc.kill()
    raise AssertionError(f"no {what} after 60 s")


# Runs study.py in a Python that records every program it starts (the audit event
# subprocess.Popen) and prints them as its last line on standard output.
RECORDING_DRIVER = """
import json, runpy, sys
started = []
sys.addaudithook(lambda e, a: started.append(str(a[0])) if e == "subprocess.Popen" else None)
sys.argv = sys.argv[1:]
try:
    runpy.run_path(sys.argv[0], run_name="__main__")
except SystemExit as e:
    code = e.code
else:
    code = 0
print(json.dumps(started))
sys.exit(code)
"""


def test_a_study_solves_its_runs_in_its_own_process(tmp_path):
    # Issue 43: the figure study runs in one process through the library; it starts no gfmd
    # program. GFMD_STUDY_RUNS=process (the way for a program without its package) starts one
    # per series, and both make the same table to the last digit.
    import json

    study = small_sweep_study(tmp_path)
    tables, started = {}, {}
    for mode in ("library", "process"):
        out = tmp_path / mode
        p = subprocess.run(["/usr/bin/python3", "-c", RECORDING_DRIVER, STUDY[1], str(study), "--quick", "-o", str(out)],
                           capture_output=True, text=True, env=dict(ENV, GFMD_STUDY_RUNS=mode))
        assert p.returncode == 0, p.stderr
        started[mode] = [os.path.basename(x) for x in json.loads(p.stdout.strip().splitlines()[-1])]
        tables[mode] = (out / "small" / "quick" / "small.csv").read_text()
        for series in ("series_00", "series_01"):
            assert (out / "small" / "quick" / series / "sweep_relative_contact_area.png").stat().st_size > 1000
    assert "gfmd" not in started["library"], started
    assert started["process"].count("gfmd") == 2, started  # one gfmd sweep per series
    assert tables["library"] == tables["process"]
    assert len(tables["library"].splitlines()) == 5  # the header and 2 x 2 points


def test_a_study_refuses_an_unknown_way_of_running(tmp_path):
    study = small_sweep_study(tmp_path)
    p = subprocess.run(STUDY + [str(study), "--quick", "-o", str(tmp_path / "out")], capture_output=True, text=True,
                       env=dict(ENV, GFMD_STUDY_RUNS="threads"))
    assert p.returncode == 2, p.stderr
    assert "GFMD_STUDY_RUNS: must be library or process" in p.stderr, p.stderr


@pytest.mark.parametrize("how", ["ctrl-c", "sigterm"])
def test_interrupted_study_exits_4_cleanly_and_continues(tmp_path, how):
    # Ctrl-C reaches the whole foreground process group (study.py and the gfmd sweep it
    # runs); a SIGTERM sent to study.py alone is passed on to the sweep by study.py (and the
    # same command is not run again: that is the same for both).
    import signal

    study = small_sweep_study(tmp_path)
    out = tmp_path / "out"
    cmd = STUDY + [str(study), "--quick", "-o", str(out)]
    series = out / "small" / "quick" / "series_00"
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV,
                         start_new_session=True)
    # After the first point of the first series has finished: its run is reused below.
    first = series / "point_000" / "summary.json"
    wait_for(first, p, "a finished point")
    if how == "ctrl-c":
        os.killpg(p.pid, signal.SIGINT)
    else:
        p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 4, err
    assert "Traceback" not in err, err
    assert [ln for ln in err.splitlines() if "interrupted" in ln] == [INTERRUPTED], err
    assert not temporary_files(out), temporary_files(out)
    assert not (out / "small" / "quick" / "small.png").exists()  # stopped, not finished
    if how != "ctrl-c":
        return
    stamp = os.stat(first).st_mtime_ns
    # The same command finishes and recomputes nothing that was finished.
    q = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
    assert q.returncode == 0, q.stderr
    assert os.stat(first).st_mtime_ns == stamp
    table = rows(out / "small" / "quick" / "small.csv")[1:]
    assert len(table) == 4
    assert not temporary_files(out)
    # It names where the figure and the table went.
    assert f"figure: {out / 'small' / 'quick' / 'small.png'}" in q.stderr, q.stderr
    assert str(out / "small" / "quick" / "small.csv") in q.stderr, q.stderr


def test_python_study_bad_file_is_an_input_error(tmp_path):
    # `gfmd study` passes study.py's exit status 2 on: InputError (a ValueError) naming the
    # file and the key, nothing written.
    import gfmd

    bad = tmp_path / "bad.toml"
    bad.write_text('title = "t"\n')
    with pytest.raises(ValueError, match=r"bad.toml: no \[\[series\]\] table"):
        gfmd.study(str(bad), output=str(tmp_path / "out"))
    with pytest.raises(gfmd.InputError, match="this is a case file"):
        gfmd.study(os.path.join(ROOT, "examples", "hertz_nu025.toml"), output=str(tmp_path / "out"))
    assert not (tmp_path / "out").exists()


def test_python_study_interrupted_raises_keyboard_interrupt(tmp_path):
    # gfmd.study in a Python process that is interrupted alone (as a notebook's kernel is):
    # KeyboardInterrupt once the study's runs have stopped, no traceback, no temporary file.
    import signal

    study = small_sweep_study(tmp_path)
    out = tmp_path / "out"
    # Ctrl-C raises KeyboardInterrupt there even where this test runs with SIGINT ignored (a
    # background job of a shell without job control passes SIG_IGN on, and Python keeps it).
    script = (
        "import signal, sys, gfmd\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "try:\n"
        f"    gfmd.study({str(study)!r}, quick=True, output={str(out)!r})\n"
        "except KeyboardInterrupt:\n"
        "    print('KeyboardInterrupt', flush=True)\n"
        "    sys.exit(0)\n"
        "sys.exit(1)\n")
    env = dict(os.environ, PYTHONPATH=os.path.join(BUILD, "python"))
    p = subprocess.Popen(["/usr/bin/python3", "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=env)
    wait_for(out / "small" / "quick" / "series_00" / "point_000" / "summary.json", p, "a finished point")
    p.send_signal(signal.SIGINT)
    stdout, err = p.communicate(timeout=120)
    assert (p.returncode, stdout) == (0, "KeyboardInterrupt\n"), (stdout, err)
    assert "Traceback" not in err, err
    assert not temporary_files(out), temporary_files(out)
    assert not (out / "small" / "quick" / "small.png").exists()  # stopped, not finished


def test_visco_coupling_rough_quick_signs(out):
    # Issue 45, item 5: on the confined nearly incompressible layer coupling raises the total
    # friction at every speed, on the compressible half-space it lowers it (the elastic Fig. 2(e)
    # signs, kept on a rubber); the hysteresis part peaks between the relaxed and glassy ends.
    # Measured (full, 256^2, four seeds): +0.0106 at the relaxed end to +0.0042 at the glassy one
    # for h = 0.05 lambda_l, -0.0082 to -0.0042 on the half-space; the hysteresis peaks at 0.05.
    # This quick run (128^2, two seeds): +0.016 ... +0.0046 and -0.0082 ... -0.0041; peak 0.055.
    run_study("visco_coupling_rough", out)
    curves = study_curves(out, "visco_coupling_rough")

    def curve(series, q="total_friction_coefficient"):
        return curves[(series, q)]
    thin_c, thin_u = curve("ν = 0.49, h = 0.05 λ_l, coupled"), curve("ν = 0.49, h = 0.05 λ_l, uncoupled")
    half_c, half_u = curve("ν = 0.25, half-space, coupled"), curve("ν = 0.25, half-space, uncoupled")
    assert len(thin_c) == 5
    assert all(c > u for c, u in zip(thin_c, thin_u)), (thin_c, thin_u)
    assert all(c < u for c, u in zip(half_c, half_u)), (half_c, half_u)
    hyst = curve("ν = 0.49, h = 0.05 λ_l, coupled", "hysteresis_friction")
    k = hyst.index(max(hyst))
    assert 0 < k < len(hyst) - 1 and max(hyst) > 5 * max(hyst[0], hyst[-1]), hyst


def test_visco_rolling_quick(out):
    # Issue 45: tractive rolling with stick over a standard linear solid (studies/visco_rolling.toml).
    # The rolling resistance peaks between the relaxed and glassy ends and barely moves with the
    # coupling (full, 128^2: 0.0438 against 0.0436 at the peak; this quick run within 4 %); the
    # traction follows the creepage where the coupling is absent (incompressible or dropped), and
    # rises from the relaxed to the glassy end (the body ten times stiffer); on the compressible
    # body the coupling's own slip drives it the other way (full: -0.134 relaxed, -0.117 glassy).
    run_study("visco_rolling", out)
    curves = study_curves(out, "visco_rolling")

    def curve(series, q):
        return curves[(series, q)]
    names = ["ν = 0.5, half-space", "ν = 0.3, half-space, coupled", "ν = 0.3, half-space, uncoupled"]
    for name in names:
        h = curve(name, "hysteresis_friction")
        assert len(h) == 5 and max(h) > 10 * max(h[0], h[-1]), (name, h)
    coupled, uncoupled = (curve(n, "hysteresis_friction") for n in names[1:])
    assert all(abs(c / u - 1) < 0.1 for c, u in zip(coupled, uncoupled)), (coupled, uncoupled)
    for name in (names[0], names[2]):
        t = curve(name, "traction_coefficient")
        assert all(x > 0 for x in t) and t[-1] > 2 * t[0], (name, t)
    assert all(x < 0 for x in curve(names[1], "traction_coefficient"))


def test_visco_film_quick(out):
    # A hard film (E* = 10 E0) on a viscoelastic substrate (studies/visco_film.toml): the thicker
    # the film, the less the substrate's hysteresis at every speed (full, 128^2: peaks 0.0468,
    # 0.0410, 0.0321, 0.0067 for h = 1e-6, 0.01, 0.03, 0.1 R), each with a peak between the relaxed
    # and glassy ends; at slow sliding the thinnest film carries the largest tension (the relaxed
    # substrate strains it most: 0.34 E0 against 0.08-0.12 E0).
    run_study("visco_film", out)
    curves = study_curves(out, "visco_film")
    names = ["film h = 1e-6 R (the bare substrate)", "film h = 0.01 R", "film h = 0.03 R", "film h = 0.1 R"]
    h = [curves[(n, "hysteresis_friction")] for n in names]
    for c in h:
        assert len(c) == 5 and max(c) > 3 * max(c[0], c[-1]), c
    for thin, thick in zip(h, h[1:]):
        assert all(a > b for a, b in zip(thin, thick)), (thin, thick)
    t = [curves[(n, "max_tensile_stress")] for n in names]
    assert all(t[0][0] > 2 * other[0] for other in t[1:]), t


def test_a_study_stops_when_a_case_file_changes_between_its_runs(tmp_path):
    # study.py makes one run (a sweep, a curve) per series; each run reads its case once. A case file edited
    # between two runs of one study ends it (exit status 1) instead of mixing two cases.
    import sys
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    import study_runs as study
    case = tmp_path / "c.toml"
    case.write_text("[grid]\nnx = 32\n")
    study.check_case_unchanged(str(case))
    study.check_case_unchanged(str(case))  # the same text: nothing happens
    case.write_text("[grid]\nnx = 64\n")
    with pytest.raises(SystemExit) as e:
        study.check_case_unchanged(str(case))
    assert e.value.code == 1


def test_a_study_stops_when_a_height_file_changes_between_its_runs(tmp_path):
    # The files a case reads besides itself (a height file, a master curve; a run's --set of
    # indenter.path in their place) are held to their first content too.
    import sys
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    import study_runs as study
    (tmp_path / "h.csv").write_text("0 1\n1 0\n")
    (tmp_path / "other.csv").write_text("0 0\n0 0\n")
    (tmp_path / "e.txt").write_text("1 1 0.1\n10 5 1\n")
    case = tmp_path / "c.toml"
    case.write_text('[indenter]\ntype = "file"\npath = "h.csv"\n[elastic]\nviscoelastic = "sls"\n'
                    '[[elastic.viscoelastic_parts]]\nmaster_curve = "e.txt"\n')
    cmd = []  # the run's settings
    assert [(os.path.basename(p), w) for p, w in study.input_files(str(case), cmd)] == [
        ("h.csv", "height file"), ("e.txt", "master curve file")]
    other = cmd + ['indenter.path="other.csv"']
    assert [os.path.basename(p) for p, _ in study.input_files(str(case), other)] == ["other.csv", "e.txt"]
    for p, w in study.input_files(str(case), cmd):
        study.check_case_unchanged(p, w)
    (tmp_path / "h.csv").write_text("0 2\n1 0\n")
    with pytest.raises(SystemExit) as e:
        study.check_case_unchanged(str(tmp_path / "h.csv"), "height file")
    assert e.value.code == 1
