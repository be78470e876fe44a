"""Figures a reader can trust (issue 41, item 5): every figure gfmd draws, built by the
drawing scripts' own functions (scripts/plot_*.py, study_figures.py) and by Result.plot, read
back as matplotlib artists (not pixels): every axes that shows data has x and y labels with a
unit in parentheses or the dimensionless mark "(–)", every colour bar a label, every title and
label inside the figure and clear of the colour bars, log x axes over log-spaced sweeps, legends
off the data; rolling maps show the traction coefficient, not μ; measured maps are not covered
by contact outlines; the two mean gaps have different names; CLI and Python write lengths as
"x (L)" or "x (µm)". And an interrupted drawing (item 3): exit 4, no traceback, no temporary,
no figure changed. Tiny grids (32² to 64²); the data come from $GFMD_BUILD_DIR/gfmd."""
import glob
import json
import os
import re
import signal
import subprocess
import sys
import time

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
GFMD = os.path.join(BUILD, "gfmd")
SCRIPTS = os.path.join(ROOT, "scripts")
sys.path.insert(0, SCRIPTS)
import figure_io  # noqa: E402
import plot_analysis  # noqa: E402
import plot_curve  # noqa: E402
import plot_maps  # noqa: E402
import plot_profiles  # noqa: E402
import plot_sweep  # noqa: E402
import study_figures  # noqa: E402

# The children wait passively, without a GOMP_SPINCOUNT of the caller's: libgomp lets it override
# the policy (importing gfmd left one in this process's environment until 2026-12-07; with 3
# processes on 2 cores their spinning threads made an MPI test take 37 s instead of 3 s).
ENV = dict({k: v for k, v in os.environ.items() if k != "GOMP_SPINCOUNT"},
           OMP_WAIT_POLICY="PASSIVE", OMP_NUM_THREADS="1")
UNIT = re.compile(r"\((?:[^()]|\([^()]*\))+\)\s*$")  # "... (unit)" at the end, "(–)" when dimensionless

SLIDING = """
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
[friction]
coefficient = 1.0
[output]
png = false
"""
# A measured map (text file with its size and units): many small contact patches, lengths in µm.
MEASURED = """
[grid]
unit = "um"
[elastic]
contact_modulus = 1.0
poisson = 0.3
[indenter]
type = "file"
path = "rough.txt"
[load]
pressure = 0.05
[friction]
coefficient = 0.3
[output]
png = false
"""


def gfmd(*args):
    if not os.access(GFMD, os.X_OK):
        pytest.fail(f"{GFMD} is not built (set GFMD_BUILD_DIR)", pytrace=False)
    p = subprocess.run([GFMD, *args], capture_output=True, text=True, env=ENV)
    assert p.returncode == 0, p.stdout + p.stderr
    return p


def rough_map(path, n=64):
    """A random rough surface (heights in µm on 64 µm), as a text map with its units."""
    rng = np.random.default_rng(7)
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.fftfreq(n)))
    spec = np.where((q > 0) & (q < 0.25), np.maximum(q, 1 / n) ** -1.8, 0.0)
    h = np.real(np.fft.ifft2(np.fft.fft2(rng.standard_normal((n, n))) * np.sqrt(spec)))
    h *= 1.0 / h.std()
    with open(path, "w") as fh:
        fh.write(f"# lx = {n} um\n# unit = um\n")
        for row in h:
            fh.write(" ".join(f"{v:.6g}" for v in row) + "\n")


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("figures")
    (base / "sliding.toml").write_text(SLIDING)
    rough_map(base / "rough.txt")
    (base / "measured.toml").write_text(MEASURED)
    out = {k: str(base / k) for k in ("sliding", "rolling", "measured", "sweep", "curve")}
    gfmd("run", str(base / "sliding.toml"), "-o", out["sliding"], "-q")
    gfmd("run", os.path.join(ROOT, "examples", "rolling_sphere.toml"), "-o", out["rolling"], "-q",
         "--set", "grid.nx=64", "--set", "output.png=false")
    gfmd("run", str(base / "measured.toml"), "-o", out["measured"], "-q")
    gfmd("sweep", str(base / "sliding.toml"), "-o", out["sweep"], "-q", "--set", "grid.nx=32",
         "--set", "load.pressure=0.001,0.01,0.1")
    gfmd("curve", os.path.join(ROOT, "examples", "eggcrate.toml"), "--pressures", "0.005:0.2:3", "-o", out["curve"],
         "-q", "--set", "grid.nx=32", "--set", "output.png=false")
    return out


class Collect:
    """A figure_io.Batch stand-in that keeps the figures (open) instead of writing them."""

    def __init__(self):
        self.figures = {}

    def save(self, fig, path, **savefig):
        self.figures[os.path.basename(path)] = fig
        return path


def map_figures(d, **kw):
    c = Collect()
    plot_maps.plot_dir(d, batch=c, **kw)
    return c.figures


# ---------------------------------------------------------------------------------------
# What every figure must satisfy


def colorbar_of(ax):
    return getattr(ax, "_colorbar", None)


def colorbar_label(cb):
    axis = cb.ax.yaxis if cb.orientation == "vertical" else cb.ax.xaxis
    return axis.get_label().get_text()


def shows_data(ax):
    if colorbar_of(ax) is not None or not ax.get_visible() or not ax.axison:
        return False
    lines = [ln for ln in ax.get_lines() if len(np.atleast_1d(ln.get_xdata())) > 2]
    return bool(ax.images or lines or ax.collections or ax.patches)


def labelled(ax, others, which):
    """The axes' own x (y) label, or that of an axes in the same column (row) of a grid."""
    get = (lambda a: a.get_xlabel()) if which == "x" else (lambda a: a.get_ylabel())
    if get(ax):
        return get(ax)
    p = ax.get_position()
    for o in others:
        q = o.get_position()
        same = abs(q.x0 - p.x0) < 1e-3 and abs(q.x1 - p.x1) < 1e-3 if which == "x" else \
            abs(q.y0 - p.y0) < 1e-3 and abs(q.y1 - p.y1) < 1e-3
        if same and get(o):
            return get(o)
    return ""


def overlaps(a, b, tol=0.5):
    return a.x0 < b.x1 - tol and b.x0 < a.x1 - tol and a.y0 < b.y1 - tol and b.y0 < a.y1 - tol


def check_figure(fig, name, given=()):
    """The rules every figure keeps; returns the axes that show data. given: labels a study
    file supplies (its own text: "x / R", "p / p_H"), taken as they are."""
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    data_axes = [ax for ax in fig.axes if shows_data(ax)]
    assert data_axes, f"{name}: no axes with data"
    for ax in data_axes:
        for which in "xy":
            text = labelled(ax, data_axes, which)
            assert text.strip(), f"{name}: an axes ({ax.get_title()!r}) has no {which} label"
            assert UNIT.search(text) or text in given, f"{name}: {which} label {text!r} has no (unit) or (–)"
    for ax in fig.axes:
        cb = colorbar_of(ax)
        if cb is not None:
            assert colorbar_label(cb).strip(), f"{name}: a colour bar without a label"
    # Nothing drawn past the figure's edge (titles, colour-bar labels, legends, tick labels).
    w, h = fig.get_size_inches()
    bb = fig.get_tightbbox(r)
    tol = 1.5 / fig.dpi
    assert bb.x0 >= -tol and bb.y0 >= -tol and bb.x1 <= w + tol and bb.y1 <= h + tol, \
        f"{name}: drawn past the figure's edge: {bb} in {w:.2f} x {h:.2f} in"
    # Titles inside the figure and clear of every other axes (e.g. a neighbour's colour bar) by
    # at least 0.04 in: a title that touches a colour bar reads as cut by it.
    fbox = fig.bbox
    for ax in fig.axes:
        for t in (ax.title, ax._left_title, ax._right_title):
            if not t.get_text():
                continue
            e = t.get_window_extent(r).padded(0.04 * fig.dpi)
            inner = t.get_window_extent(r)
            assert inner.x0 >= fbox.x0 - 1 and inner.x1 <= fbox.x1 + 1 and inner.y1 <= fbox.y1 + 1, \
                f"{name}: title {t.get_text()!r} cut by the figure's edge"
            for o in fig.axes:
                if o is not ax and o.get_visible() and o.axison:
                    assert not overlaps(e, o.get_window_extent(r)), \
                        f"{name}: title {t.get_text()!r} runs into another axes (a colour bar?)"
    # The figure's own title and keys clear of each other and of every axes.
    tops = [t for t in fig.texts if t.get_visible() and t.get_text()] + list(fig.legends)
    for i, t in enumerate(tops):
        e = t.get_window_extent(r)
        for o in tops[i + 1:]:
            assert not overlaps(e, o.get_window_extent(r)), f"{name}: {t} and {o} overlap"
        for ax in fig.axes:
            if ax.get_visible() and ax.axison:
                assert not overlaps(e, ax.get_window_extent(r)), f"{name}: {t} over an axes"
    # Legends off the data: no line vertex inside an axes' legend, no legend over an image.
    for ax in data_axes:
        leg = ax.get_legend()
        if leg is None:
            continue
        lb = leg.get_window_extent(r)
        if ax.images:
            assert not overlaps(lb, ax.get_window_extent(r)), f"{name}: the legend covers the map"
        for ln in ax.get_lines():
            xy = ln.get_transform().transform(np.column_stack([ln.get_xdata(), ln.get_ydata()]))
            inside = (xy[:, 0] > lb.x0) & (xy[:, 0] < lb.x1) & (xy[:, 1] > lb.y0) & (xy[:, 1] < lb.y1)
            assert not inside.any(), f"{name}: the legend covers data of {ln.get_label()!r}"
    return data_axes


def close(figs):
    for f in (figs.values() if isinstance(figs, dict) else figs):
        plt.close(f)


# ---------------------------------------------------------------------------------------
# The figures


def test_run_maps_have_units_labels_and_fit(runs):
    figs = map_figures(runs["sliding"])
    assert {"pressure.png", "gap.png", "slip_longitudinal.png", "slip_transverse.png", "dissipation.png",
            "max_principal_stress.png", "von_mises.png"} <= set(figs)
    for name, fig in figs.items():
        check_figure(fig, name)
    ax = figs["pressure.png"].axes[0]
    assert ax.get_xlabel() == "x (L)" and ax.get_ylabel() == "y (L)"  # no grid.unit: L
    assert colorbar_label(colorbar_of(figs["pressure.png"].axes[1])) == "$p$ (E*)"
    assert colorbar_label(colorbar_of(figs["slip_longitudinal.png"].axes[1])).endswith("(–)")
    # A Hertz contact is outlined, with its key below the map.
    assert ax.collections and ax.get_legend() is not None
    note = ax.get_title()
    assert "μ = " in note and "traction" not in note
    close(figs)


def test_profiles_panels_have_axis_labels(runs):
    fig = plot_profiles.figure(os.path.join(runs["sliding"], "profiles.csv"))
    axes = check_figure(fig, "profiles.png")
    assert len(axes) >= 10
    for ax in axes:
        assert ax.get_xlabel() == "distance s (L)", ax.get_xlabel()
    ylabels = {ax.get_title(): ax.get_ylabel() for ax in axes}
    assert ylabels["contact pressure"] == "$p$ (E*)"
    assert ylabels["normal surface displacement"] == "$u_z$ (L)"
    # One key for all panels, in a spare slot (no data there) or above the panels.
    keys = fig.legends + [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert len(keys) == 1 and all(ax.get_legend() is None for ax in axes)
    plt.close(fig)


def test_analysis_names_its_mean_gap(runs):
    fig = plot_analysis.figure(runs["measured"])
    axes = check_figure(fig, "analysis.png")
    gap = [ax for ax in axes if ax.get_title().startswith("gap distribution")][0]
    assert "out of contact" in gap.get_title() and "mean gap out of contact" in gap.get_title()
    assert gap.get_xlabel() == "gap g (µm)"
    with open(os.path.join(runs["measured"], "summary.json")) as fh:
        s = json.load(fh)
    # Two different numbers, two different names: the gap PDF's mean is over the open points,
    # summary.json's mean_gap over the whole cell (contact counting 0).
    mean_open = s["analysis"]["gap"]["mean"]
    assert f"{mean_open:.4g}" in gap.get_title()
    assert s["mean_gap"] < mean_open * (1 - 1e-6)
    assert figure_io.quantity("mean_gap")[0] != "mean gap out of contact"
    assert "over the cell" in figure_io.quantity_label("mean_gap", "um")
    assert figure_io.quantity_label("mean_gap", "um").endswith("(µm)")
    plt.close(fig)


def test_rolling_maps_show_the_traction_coefficient(runs):
    figs = map_figures(runs["rolling"], only={"pressure", "slip_longitudinal", "slip_transverse"})
    for name, fig in figs.items():
        check_figure(fig, name)
        note = fig.axes[0].get_title()
        assert "μ = " not in note, f"{name}: shows μ for rolling: {note!r}"
        assert "traction coefficient" in note, note
    with open(os.path.join(runs["rolling"], "summary.json")) as fh:
        tc = json.load(fh)["traction_coefficient"]
    assert f"{tc:.4g}" in figs["slip_longitudinal.png"].axes[0].get_title()
    close(figs)


def test_measured_maps_are_not_hidden_by_outlines(runs):
    figs = map_figures(runs["measured"], only={"pressure", "gap"})
    for name, fig in figs.items():
        check_figure(fig, name)
        ax = fig.axes[0]
        assert ax.get_xlabel() == "x (µm)" and ax.get_ylabel() == "y (µm)"
        assert not ax.collections, f"{name}: contact outlines drawn over a rough contact"
    # The rule: a contact of many small patches is not outlined, a Hertz disc is.
    with open(os.path.join(runs["measured"], "summary.json")) as fh:
        assert json.load(fh)["analysis"]["patches"]["count"] > 10
    disc = np.zeros((64, 64))
    yy, xx = np.mgrid[:64, :64]
    disc[(xx - 32) ** 2 + (yy - 32) ** 2 < 100] = 1
    assert not plot_maps.outline_hides_data(disc)
    assert plot_maps.outline_hides_data((np.random.default_rng(1).random((64, 64)) > 0.7).astype(float))
    close(figs)


def test_sweep_plot_uses_names_units_and_a_log_axis(runs):
    table = os.path.join(runs["sweep"], "sweep.csv")
    fig = plot_sweep.figure(table, "friction_coefficient")
    (ax,) = check_figure(fig, "sweep_friction_coefficient.png")
    assert ax.get_xscale() == "log", "log-spaced pressures on a linear axis"
    assert ax.get_xlabel() == "mean pressure p̄ (E*)"
    assert "load.pressure" not in ax.get_xlabel() and "friction_coefficient" not in ax.get_ylabel()
    plt.close(fig)
    fig = plot_sweep.figure(table, "mean_gap")
    check_figure(fig, "sweep_mean_gap.png")
    assert fig.axes[0].get_ylabel() == "mean gap over the cell ⟨g⟩ (L)"
    plt.close(fig)
    # Less than a decade, doubling: log too (ticks at the values); evenly spaced values: linear.
    narrow = os.path.join(os.path.dirname(table), "..", "narrow")
    os.makedirs(narrow, exist_ok=True)
    for name, values, scale in (("doubling", "0.01 0.02 0.04 0.08", "log"), ("even", "1 2 3 4", "linear")):
        path = os.path.join(narrow, f"{name}.csv")
        with open(path, "w") as fh:
            fh.write("elastic.thickness,relative_contact_area\n")
            fh.writelines(f"{v},{0.1 * (k + 1)}\n" for k, v in enumerate(values.split()))
        fig = plot_sweep.figure(path, "relative_contact_area")
        (ax,) = check_figure(fig, name)
        assert ax.get_xscale() == scale and ax.get_xlabel() == "layer thickness h (L)"
        plt.close(fig)
    # The rule: closer to geometric than to arithmetic progression.
    assert figure_io.log_spaced([0.01, 0.02, 0.04, 0.08])
    assert figure_io.log_spaced([0.001, 0.01])
    assert not figure_io.log_spaced([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0])
    assert not figure_io.log_spaced([-1.0, 0.0, 1.0])


def test_curve_panels(runs):
    fig = plot_curve.figure(os.path.join(runs["curve"], "curve.csv"))
    axes = check_figure(fig, "curve.png")
    assert len(axes) == 4 and all(ax.get_xscale() == "log" for ax in axes)
    assert all(ax.get_xlabel() == "mean pressure p̄ (E*)" for ax in axes)
    gap = [ax for ax in axes if "mean gap" in ax.get_title()][0]
    assert "whole cell" in gap.get_title() and gap.get_ylabel().endswith("(L)")
    plt.close(fig)


def study_series(runs):
    # fig2a's first series, then two of fig3ad's (long: wrapped to their maps' width).
    labels = ["reference: ν = 0.49, h = ∞", "compressible: ν = 0.25, h = ∞, p = 0.02 E*",
              "confined: ν = 0.49, h = 0.05 λ_l, p = 0.04 E*"]
    return [({"label": lab}, runs["sliding"]) for lab in labels]


def captured(monkeypatch):
    figs = []
    monkeypatch.setattr(study_figures, "save", lambda fig, base: figs.append(fig))
    monkeypatch.setattr(study_figures, "write_csv", lambda *a: None)
    return figs


def test_study_maps_titles_clear_of_the_colour_bars(runs, monkeypatch):
    import tomllib

    with open(os.path.join(ROOT, "studies", "fig2a.toml"), "rb") as fh:
        study = tomllib.load(fh)
    figs = captured(monkeypatch)
    study_figures.draw_maps(study, study_series(runs), "unused")
    (fig,) = figs
    given = {m["label"] for m in study["maps"]}
    check_figure(fig, "fig2a", given)
    labels = [colorbar_label(colorbar_of(ax)) for ax in fig.axes if colorbar_of(ax) is not None]
    assert len(labels) == 12 and set(labels) == {m["label"] for m in study["maps"]}
    plt.close(fig)


def test_study_profiles_and_cross_section(runs, monkeypatch):
    import tomllib

    with open(os.path.join(ROOT, "studies", "smfig2.toml"), "rb") as fh:
        study = tomllib.load(fh)
    figs = captured(monkeypatch)
    study_figures.draw_profiles(study, study_series(runs), "unused")
    study_figures.draw_cross_section({"title": "cross-section"}, study_series(runs)[:1], "unused")
    given = {study["xlabel"]} | {p["label"] for p in study["profiles"]}
    check_figure(figs[0], "smfig2", given)
    (ax,) = check_figure(figs[1], "cross-section")
    assert ax.get_xlabel() == "x (L)" and ax.get_ylabel() == "z (L)"
    close(figs)


def test_python_plot_uses_the_cli_notation_and_fits(runs):
    if not glob.glob(os.path.join(BUILD, "python", "gfmd", "_core*.so")):
        pytest.skip("the Python module was not built")
    import gfmd

    r = gfmd.solve(gfmd.Topography.hertz(32, 4.0, 1.0), gfmd.ElasticBody(poisson=0.25), force=0.01, friction=1.0)
    for field in ("dissipation", "pressure", "slip_longitudinal"):
        fig, ax = plt.subplots()
        r.plot(field, ax=ax)
        check_figure(fig, f"r.plot({field!r})")
        assert ax.get_xlabel() == "x (L)" and ax.get_ylabel() == "y (L)"  # as gfmd run's maps
        plt.close(fig)
    fig = plt.figure()
    ax = r.plot("pressure")
    assert colorbar_label(colorbar_of(ax.figure.axes[1])) == "pressure (E*)"
    plt.close("all")


def test_unit_notation():
    assert figure_io.label("x", "length") == "x (L)"
    assert figure_io.label("x", "um") == "x (µm)"
    assert figure_io.label("K", "um^3") == "K (µm³)"
    assert figure_io.label("F", "E* length^2") == "F (E* L²)"
    assert figure_io.label("A/A0", "1") == "A/A0 (–)"
    assert figure_io.quantity_label("load.force") == "normal force F (E* L²)"
    assert figure_io.quantity_label("some.unknown_key") == "some.unknown_key"


# ---------------------------------------------------------------------------------------
# Interrupted drawing: exit 4, no traceback, no temporary, no figure changed


def png_state(dirs):
    """(inode, mtime) of every PNG in dirs."""
    out = {}
    for d in dirs:
        for p in glob.glob(os.path.join(d, "*.png")):
            st = os.stat(p)
            out[p] = (st.st_ino, st.st_mtime_ns)
    return out


def temporaries(dirs):
    return [f for d in dirs for f in os.listdir(d) if ".tmp." in f]


SOME = ["--only", "pressure,gap,dissipation"]


def draw_all(dirs):
    """Draws the maps of dirs (the "old" figures), stamped with a time of their own."""
    p = subprocess.run([sys.executable, os.path.join(SCRIPTS, "plot_maps.py"), *SOME, *dirs],
                       capture_output=True, text=True, env=ENV)
    assert p.returncode == 0, p.stderr
    for d in dirs:
        for f in glob.glob(os.path.join(d, "*.png")):
            os.utime(f, ns=(10**18, 10**18))


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_interrupted_plot_maps_changes_nothing(runs, sig):
    # SIGINT: two directories, drawn by a pool of workers; SIGTERM: one, drawn in the process.
    dirs = [runs["sliding"]] if sig == signal.SIGTERM else sorted(glob.glob(os.path.join(runs["sweep"], "point_*")))[:2]
    draw_all(dirs)
    before = png_state(dirs)
    assert len(before) == 3 * len(dirs)
    # The signal's default disposition in the script (a background job of a shell without job
    # control would pass SIG_IGN for SIGINT on, which the script keeps, as a program should).
    p = subprocess.Popen([sys.executable, os.path.join(SCRIPTS, "plot_maps.py"), *SOME, *dirs],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV,
                         preexec_fn=lambda: signal.signal(sig, signal.SIG_DFL))
    # Once the first figure is drawn (its temporary appears), the rest are still to come.
    while not temporaries(dirs):
        assert p.poll() is None, "finished before it was interrupted: " + p.stderr.read()
        time.sleep(0.005)
    p.send_signal(sig)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 4, (p.returncode, err)
    assert "Traceback" not in err and "interrupted" in err, err
    assert temporaries(dirs) == []
    assert png_state(dirs) == before, "a figure changed although the drawing was interrupted"


def test_interrupt_in_process_discards_the_batch(runs, monkeypatch, capsys):
    d = runs["sliding"]
    draw_all([d])
    before = png_state([d])
    calls = []
    real = plot_maps.draw

    def draw(*a, **kw):
        calls.append(a[0])
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(*a, **kw)

    monkeypatch.setattr(plot_maps, "draw", draw)
    handlers = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        with pytest.raises(SystemExit) as e:
            figure_io.run_main(lambda: plot_maps.main([*SOME, d]), "plot_maps.py")
    finally:
        for s, h in handlers.items():
            signal.signal(s, h)
    assert e.value.code == 4
    err = capsys.readouterr().err
    assert "Traceback" not in err and "plot_maps.py: interrupted" in err
    assert len(calls) == 3 and temporaries([d]) == [] and png_state([d]) == before


def test_batch_publishes_all_or_nothing(tmp_path):
    b = figure_io.Batch()
    for k in range(3):
        fig, ax = plt.subplots()
        ax.plot([0, 1], [0, k])
        b.save(fig, str(tmp_path / f"f{k}.png"))
    assert sorted(os.listdir(tmp_path)) == [f"f{k}.png.tmp.{os.getpid()}" for k in range(3)]
    assert b.publish() == [str(tmp_path / f"f{k}.png") for k in range(3)]
    assert sorted(os.listdir(tmp_path)) == ["f0.png", "f1.png", "f2.png"]
    b = figure_io.Batch()
    fig, ax = plt.subplots()
    b.save(fig, str(tmp_path / "g.png"))
    b.discard()
    assert sorted(os.listdir(tmp_path)) == ["f0.png", "f1.png", "f2.png"]
