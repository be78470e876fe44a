#!/usr/bin/python3
"""Draws the PNG maps of gfmd run directories from their fields (matplotlib).

    plot_maps.py DIR [DIR ...] [--fields FILE] [--only NAME[,NAME...]] [--profiles]

The fields come from DIR/fields.nc (or FILE; else DIR/.maps.tmp.nc, the staging file gfmd
writes when output.png is on but output.fields is off); the flow current magnitudes from
DIR/flow.nc when there is one. One PNG per field present, written atomically into DIR:

    pressure.png              p (contact outlined)
    gap.png                   g (contact outlined)
    slip_longitudinal.png     v_l^rel/v0 - 1 inside the contact (diverging; stick zone outlined)
    slip_transverse.png       v_perp/v0 inside the contact (diverging; stick zone outlined)
    dissipation.png           dissipated power density / v0
    adhesive_traction.png     adhesive traction (interaction.model = "adhesive"; contact outlined)
    max_principal_stress.png  sigma_I (diverging)
    von_mises.png             von Mises stress
    current_<dir>.png         |current density| for a pressure gradient along <dir>

Axes are in the length unit of the case ("x (µm)" with grid.unit = "um", "x (L)" without),
with the true aspect ratio (a view more than 20 times longer than wide, such as a line
contact on a few rows, is stretched and its title says so); the maps of one contact (Hertz,
sphere, power-law tip, flat punch, cylinder) are zoomed onto it. Every colour bar is
labelled "symbol (unit)". The contact is outlined where that does not hide the field (a
contact of a few patches: Hertz, not a measured or rough surface); the legend sits below the
map, outside the data. --only draws a subset (names as above without .png; "current" for all
current maps); --profiles also draws profiles.png from DIR/profiles.csv (plot_profiles.py);
analysis.png (spectrum, patches, gap and pressure PDFs; plot_analysis.py) is drawn when DIR has
the analysis tables (name "analysis" for --only).
Every figure is drawn to a temporary (NAME.png.tmp.<pid>) and all of them are renamed
together at the end: an interrupted command (Ctrl-C, SIGTERM) changes no figure, leaves no
temporary and exits with status 4, without a traceback.
Exit status: 0 when every map was drawn, 2 when a fields file is missing or unreadable,
4 when interrupted, 1 on other errors.
"""
import argparse
import glob
import json
import os
import re
import sys
import warnings

import figure_io  # noqa: E402 (beside this script)

if __name__ == "__main__":
    figure_io.exit_on_interrupt_while_starting()

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

try:
    import tomllib
except ImportError:  # Python < 3.11: the indenter type comes from summary.json then
    tomllib = None

STAGING = ".maps.tmp.nc"  # include/gfmd/case/outputs.hpp: kMapsStagingFile
MAX_PIXELS = 1024  # long side of the drawn data after block averaging
STRETCH_BEYOND = 20.0  # views longer than this to one are drawn stretched (not to scale)
# The contact outline is left out where it would hide the map: its edge cells more than
# OUTLINE_MAX_EDGE_FRACTION of the drawn cells and more than OUTLINE_MAX_RATIO times the edge of
# one disc of the same area (many small patches: a rough or measured surface). A Hertz disc
# has a ratio near 1, an egg-crate's four patches per period 2.
OUTLINE_MAX_EDGE_FRACTION = 0.02
OUTLINE_MAX_RATIO = 3.0
ZOOM_MARGIN = 0.3  # Hertz zoom: margin around the contact, relative to its size
ZOOM_MAX_ASPECT = 2.0  # a zoomed view's sides: at most this to one where the cell allows
# Indenter types that make one contact, whose maps are zoomed onto it (as Hertz's).
ONE_CONTACT = ("hertz", "sphere", "powerlaw", "flatpunch", "cylinder")
ZOOM_MIN_CELLS = 4  # ... and at least this many cells

# name -> (field, title, symbol, colormap, kind); kind: "positive" (0 at the bottom),
# "range" (data range), "diverging" (symmetric about 0), "slip" (diverging, contact only).
MAPS = [
    ("pressure", "pressure", "contact pressure", "$p$", "inferno", "positive"),
    ("gap", "gap", "gap", "$g$", "viridis", "positive"),
    ("slip_longitudinal", "slip_longitudinal", "longitudinal slip excess",
     r"$v_\ell^\mathrm{rel}/v_0 - 1$", "RdBu_r", "slip"),
    ("slip_transverse", "slip_transverse", "transverse slip", r"$v_\perp/v_0$", "RdBu_r", "slip"),
    ("dissipation", "dissipation", "dissipated power density", r"$\dot w/v_0$", "inferno", "positive"),
    ("adhesive_traction", "adhesive_traction", "adhesive traction (contact and cohesive zone)",
     r"$\sigma_\mathrm{a}$", "viridis", "positive"),
    ("max_principal_stress", "sigma_1", "maximum principal surface stress", r"$\sigma_\mathrm{I}$",
     "RdBu_r", "diverging"),
    ("von_mises", "von_mises", "von Mises surface stress", r"$\sigma_\mathrm{vM}$", "inferno", "positive"),
]
CURRENT = re.compile(r"current_([^_]+)")  # magnitudes; components are current_x_<dir>, current_y_<dir>


class InputProblem(Exception):
    """A fields file that is missing or unreadable (exit status 2)."""


def read_netcdf(path, keep=None):
    """Reads the 2D variables (dims y, x) of a gfmd NetCDF file: returns a dict with
    "fields" {name: (array, long_name, units)}, "x", "y", "lx", "ly", "length_unit" and
    "input_toml" (text or None). keep(name): read only the variables it accepts."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # "numpy.ndarray size changed" (Debian's build)
            import netCDF4
    except ImportError as e:
        raise InputProblem(f"{path}: cannot read NetCDF files ({e}; install python3-netcdf4)")
    if not os.path.isfile(path):
        raise InputProblem(f"{path}: no such file")
    try:
        with netCDF4.Dataset(path) as nc:
            x = np.array(nc.variables["x"][:], dtype=float)
            y = np.array(nc.variables["y"][:], dtype=float)
            unit = getattr(nc.variables["x"], "units", "")
            attrs = nc.ncattrs()
            lx = float(nc.getncattr("lx")) if "lx" in attrs else None
            ly = float(nc.getncattr("ly")) if "ly" in attrs else None
            text = nc.getncattr("input_toml") if "input_toml" in attrs else None
            fields = {}
            for name, v in nc.variables.items():
                if v.dimensions != ("y", "x") or (keep is not None and not keep(name)):
                    continue
                a = np.ma.filled(np.ma.asarray(v[:], dtype=float), np.nan)
                fields[name] = (np.asarray(a, dtype=float), getattr(v, "long_name", name),
                                getattr(v, "units", ""))
    except InputProblem:
        raise
    except Exception as e:  # netCDF4 raises OSError, KeyError, RuntimeError ...
        raise InputProblem(f"{path}: unreadable as a gfmd fields file ({type(e).__name__}: {e})")
    nx, ny = len(x), len(y)
    if lx is None:
        lx = (x[1] - x[0]) * nx if nx > 1 else 1.0
    if ly is None:
        ly = (y[1] - y[0]) * ny if ny > 1 else lx
    return {"fields": fields, "x": x, "y": y, "lx": lx, "ly": ly, "length_unit": unit, "input_toml": text}


def grid_extent(nx, ny, lx, ly):
    """Edges of the cells (cell ix centred at x = ix * dx): (x0, x1, y0, y1)."""
    dx, dy = lx / nx, ly / ny
    return (-0.5 * dx, lx - 0.5 * dx, -0.5 * dy, ly - 0.5 * dy)


def contact_bbox(pressure, lx, ly):
    """Bounding box (x0, x1, y0, y1) of the centres of the cells with pressure > 0, or None."""
    ny, nx = pressure.shape
    iy, ix = np.nonzero(pressure > 0)
    if ix.size == 0:
        return None
    dx, dy = lx / nx, ly / ny
    return (ix.min() * dx, ix.max() * dx, iy.min() * dy, iy.max() * dy)


def zoom_limits(pressure, lx, ly, margin=ZOOM_MARGIN, min_cells=ZOOM_MIN_CELLS):
    """Axis limits (x0, x1, y0, y1) of a map zoomed onto the contact: the cells with
    pressure > 0 plus a margin of `margin` times the contact's size on each side (at least
    min_cells cells), clipped to the grid. The whole grid when nothing is in contact."""
    ny, nx = pressure.shape
    full = grid_extent(nx, ny, lx, ly)
    box = contact_bbox(pressure, lx, ly)
    if box is None:
        return full
    dx, dy = lx / nx, ly / ny
    wx, wy = box[1] - box[0] + dx, box[3] - box[2] + dy
    mx, my = max(margin * wx, min_cells * dx), max(margin * wy, min_cells * dy)
    x0, x1 = max(full[0], box[0] - 0.5 * dx - mx), min(full[1], box[1] + 0.5 * dx + mx)
    y0, y1 = max(full[2], box[2] - 0.5 * dy - my), min(full[3], box[3] + 0.5 * dy + my)
    # A contact that spans the cell one way (a cylinder's line) would leave a strip: the other
    # side is widened to half the long one, where the cell allows.
    if y1 - y0 > ZOOM_MAX_ASPECT * (x1 - x0):
        x0, x1 = widened(x0, x1, (y1 - y0) / ZOOM_MAX_ASPECT, full[0], full[1])
    elif x1 - x0 > ZOOM_MAX_ASPECT * (y1 - y0):
        y0, y1 = widened(y0, y1, (x1 - x0) / ZOOM_MAX_ASPECT, full[2], full[3])
    return x0, x1, y0, y1


def widened(lo, hi, width, full_lo, full_hi):
    """The interval [lo, hi] widened about its centre to `width`, kept inside [full_lo, full_hi]."""
    c = 0.5 * (lo + hi)
    lo, hi = c - 0.5 * width, c + 0.5 * width
    if lo < full_lo:
        lo, hi = full_lo, hi + (full_lo - lo)
    if hi > full_hi:
        lo, hi = lo - (hi - full_hi), full_hi
    return max(lo, full_lo), min(hi, full_hi)


def block_average(a, k):
    """Means over k x k blocks (NaNs ignored; the last blocks padded with NaN)."""
    if k <= 1:
        return a
    ny, nx = a.shape
    py, px = -ny % k, -nx % k
    b = np.pad(a, ((0, py), (0, px)), constant_values=np.nan)
    b = b.reshape((ny + py) // k, k, (nx + px) // k, k)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN blocks
        return np.nanmean(b, axis=(1, 3))


def window(limits, nx, ny, lx, ly):
    """Index ranges (iy0, iy1, ix0, ix1) of the cells that cover the axis limits."""
    x0, _, y0, _ = grid_extent(nx, ny, lx, ly)
    dx, dy = lx / nx, ly / ny
    ix0 = max(0, int(np.floor((limits[0] - x0) / dx + 1e-9)))
    ix1 = min(nx, int(np.ceil((limits[1] - x0) / dx - 1e-9)))
    iy0 = max(0, int(np.floor((limits[2] - y0) / dy + 1e-9)))
    iy1 = min(ny, int(np.ceil((limits[3] - y0) / dy - 1e-9)))
    return iy0, max(iy1, iy0 + 1), ix0, max(ix1, ix0 + 1)


class View:
    """The part of the grid a map shows: crop window, block-averaging factor, limits."""

    def __init__(self, nx, ny, lx, ly, limits):
        self.nx, self.ny, self.lx, self.ly, self.limits = nx, ny, lx, ly, limits
        self.iy0, self.iy1, self.ix0, self.ix1 = window(limits, nx, ny, lx, ly)
        self.k = max(1, -(-max(self.iy1 - self.iy0, self.ix1 - self.ix0) // MAX_PIXELS))
        dx, dy = lx / nx, ly / ny
        x0, _, y0, _ = grid_extent(nx, ny, lx, ly)
        cols = -(-(self.ix1 - self.ix0) // self.k)
        rows = -(-(self.iy1 - self.iy0) // self.k)
        self.extent = (x0 + self.ix0 * dx, x0 + (self.ix0 + cols * self.k) * dx,
                       y0 + self.iy0 * dy, y0 + (self.iy0 + rows * self.k) * dy)
        # Centres of the averaged blocks (for outlines).
        self.xc = self.extent[0] + (np.arange(cols) + 0.5) * self.k * dx
        self.yc = self.extent[2] + (np.arange(rows) + 0.5) * self.k * dy

    def data(self, a):
        return block_average(a[self.iy0:self.iy1, self.ix0:self.ix1], self.k)


def indenter_type(input_toml, summary):
    if input_toml and tomllib is not None:
        try:
            return str(tomllib.loads(input_toml).get("indenter", {}).get("type", ""))
        except Exception:
            pass
    try:
        return str(summary["input"]["indenter"]["type"])
    except (KeyError, TypeError):
        return ""


def map_limits(data, pressure, hertz):
    """Axis limits of every map of a run: zoomed onto the contact for one-contact indenters."""
    ny, nx = pressure.shape
    if hertz:
        return zoom_limits(pressure, data["lx"], data["ly"])
    return grid_extent(nx, ny, data["lx"], data["ly"])


def colour_label(symbol, units):
    """The colour bar's label: "symbol (unit)", "(–)" for a dimensionless field."""
    return figure_io.label(symbol, units)


def rolling(summary):
    """Tractive rolling (friction.creepage != 1 or lateral_creepage != 0; sliding is creepage 1):
    friction_coefficient is not the number to read there (README), traction_coefficient is."""
    try:
        f = summary["input"]["friction"]
        return f.get("coefficient", 0) > 0 and (f.get("creepage", 1.0) != 1.0 or f.get("lateral_creepage", 0.0) != 0.0)
    except (KeyError, TypeError, AttributeError):
        return False


def subtitle(summary, unit="length"):
    """The run's key numbers under a map's title: load, mean pressure, contact area and the
    friction coefficient (the traction coefficient for rolling)."""
    if not summary:
        return ""
    u = figure_io.unit_text(unit)
    keys = [("normal_force", "F = {:.4g} E* " + u + "²"), ("mean_pressure", "p̄ = {:.4g} E*"),
            ("relative_contact_area", "A/A₀ = {:.4g}")]
    if rolling(summary):
        keys.append(("traction_coefficient", "traction coefficient F_t/F = {:.4g}"))
    else:
        keys.append(("friction_coefficient", "μ = {:.4g}"))
    parts = []
    for key, fmt in keys:
        v = summary.get(key)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            parts.append(fmt.format(v))
    return ",  ".join(parts)


def outline_hides_data(contact_view):
    """True for a contact of many small patches (a rough or measured surface), whose outlines
    would cover the map: see OUTLINE_MAX_EDGE_FRACTION and OUTLINE_MAX_RATIO."""
    c = np.nan_to_num(contact_view) > 0.5
    if c.size == 0 or not c.any():
        return False
    edge = np.zeros_like(c)
    edge[:, 1:] |= c[:, 1:] != c[:, :-1]
    edge[1:, :] |= c[1:, :] != c[:-1, :]
    disc = 2.0 * np.sqrt(np.pi * c.sum())  # edge cells of one disc of the contact's area
    return edge.sum() > OUTLINE_MAX_EDGE_FRACTION * c.size and edge.sum() > OUTLINE_MAX_RATIO * disc


def figure(aspect):
    """A figure whose map axes have the data's aspect ratio (height / width) and a colour bar
    beside them, laid out by hand (a layout engine would double the drawing time)."""
    left, bottom, top, gap, bar, right = 0.8, 0.55, 0.6, 0.15, 0.18, 0.95  # inches
    aw = 4.0
    ah = aw * aspect
    if ah > 6.0:
        ah, aw = 6.0, 6.0 / aspect
    ah = max(ah, 0.4)
    fw, fh = left + aw + gap + bar + right, bottom + ah + top
    fw = max(fw, 4.5)
    fig = plt.figure(figsize=(fw, fh), dpi=150)
    ax = fig.add_axes((left / fw, bottom / fh, aw / fw, ah / fh))
    cax = fig.add_axes(((left + aw + gap) / fw, bottom / fh, bar / fw, ah / fh))
    return fig, ax, cax


def draw(path, view, values, title, label, cmap, kind, unit, contact, stick=None, note="", batch=None):
    """One map: the field over the view, a colour bar, the contact (and stick zone) outlines.
    Drawn to batch's temporary (published with the others), else written at once."""
    v = view.data(values)
    finite = v[np.isfinite(v)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if kind in ("diverging", "slip"):
        m = max(abs(lo), abs(hi)) or 1.0
        lo, hi = -m, m
    elif kind == "positive":
        lo = min(0.0, lo)
    if hi <= lo:
        hi = lo + (abs(lo) or 1.0)
    x0, x1, y0, y1 = view.limits
    aspect = (y1 - y0) / (x1 - x0)
    # A cell far longer than wide (a line contact on a few rows) would be a line a pixel high
    # at true aspect: drawn stretched, and said so.
    stretched = not (1 / STRETCH_BEYOND <= aspect <= STRETCH_BEYOND)
    if stretched:
        note = (note + "  " if note else "") + f"(not to scale: the view is {max(aspect, 1 / aspect):.0f}:1)"
        aspect = min(max(aspect, 0.25), 4.0)
    fig, ax, cax = figure(aspect)
    cm = plt.get_cmap(cmap).copy()
    cm.set_bad("0.85")
    im = ax.imshow(v, origin="lower", extent=view.extent, cmap=cm, vmin=lo, vmax=hi,
                   interpolation="nearest" if max(v.shape) <= 256 else "antialiased")
    fig.colorbar(im, cax=cax, label=label)
    outline = "black" if kind in ("diverging", "slip") else ("white" if cmap == "viridis" else "cyan")
    handles = []
    c = view.data(contact)
    # An outline needs two rows and two columns of blocks (a cell a few points across, e.g. a
    # cylinder's line contact, averages to one row: no outline there).
    outlined = min(c.shape) >= 2
    if outlined and np.nanmin(c) < 0.5 < np.nanmax(c) and not outline_hides_data(c):
        ax.contour(view.xc, view.yc, c, levels=[0.5], colors=outline, linewidths=0.8)
        handles.append(Line2D([], [], color=outline, lw=0.8, label="contact"))
    if stick is not None:
        s = view.data(stick)
        if outlined and np.nanmax(s) > 0.5 and np.nanmin(s) < 0.5:
            ax.contour(view.xc, view.yc, s, levels=[0.5], colors="limegreen", linewidths=1.0,
                       linestyles="--")
            handles.append(Line2D([], [], color="limegreen", lw=1.0, ls="--", label="stick zone"))
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("auto" if stretched else "equal")
    ax.set_xlabel(figure_io.label("x", unit or "length"))
    ax.set_ylabel(figure_io.label("y", unit or "length"))
    ax.set_title(title + (f"\n{note}" if note else ""), fontsize=9)
    if handles:  # below the map (outside the data), under the x label
        # 0.16 axes heights below, and clear of the x label on short (stretched) axes.
        ah = ax.get_position().height * fig.get_figheight()
        leg = ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -max(0.16, 0.45 / ah)), ncol=len(handles),
                        fontsize=7, frameon=False)
        if outline in ("white", "cyan"):  # light lines: a grey key so that they show
            leg.set_frame_on(True)
            leg.get_frame().set_facecolor("0.45")
            leg.get_frame().set_edgecolor("none")
    figure_io.fit(fig)
    if batch is None:
        figure_io.save_png(fig, path)
    else:
        batch.save(fig, path, format="png")


def fields_file(d, given=None):
    if given:
        return given
    for name in ("fields.nc", STAGING):
        p = os.path.join(d, name)
        if os.path.isfile(p):
            return p
    return os.path.join(d, "fields.nc")


def wanted(name, only):
    return only is None or name in only or (name.startswith("current_") and "current" in only)


def plot_dir(d, fields=None, only=None, profiles=False, batch=None):
    """Draws the maps of run directory d into batch (a figure_io.Batch: the caller publishes
    them); without one they are published before returning. Returns the paths."""
    if batch is None:
        batch = figure_io.Batch()
        try:
            written = plot_dir(d, fields, only, profiles, batch)
            batch.publish()
        finally:
            batch.discard()
        return written
    path = fields_file(d, fields)
    need = {"pressure", "contact", "stick"}
    for name, var, *_ in MAPS:
        if wanted(name, only):
            need.add(var)
    flow_nc = os.path.join(d, "flow.nc")
    flow = wanted("current_x", only) and os.path.isfile(flow_nc)
    data = read_netcdf(path, lambda k: k in need or (not flow and CURRENT.fullmatch(k) and wanted(k, only)))
    f = data["fields"]
    if "pressure" not in f:
        raise InputProblem(f"{path}: no pressure field (not a gfmd fields file)")
    summary = None
    try:
        with open(os.path.join(d, "summary.json")) as fh:
            summary = json.load(fh)
    except (OSError, ValueError):
        pass
    pressure = f["pressure"][0]
    ny, nx = pressure.shape
    contact = f["contact"][0] if "contact" in f else (pressure > 0).astype(float)
    stick = f["stick"][0] if "stick" in f else None
    if stick is not None and not np.any(stick > 0.5):
        stick = None
    hertz = indenter_type(data["input_toml"], summary) in ONE_CONTACT
    # The zoom frames what is loaded: the contact, and with adhesion the attracted cells too.
    footprint = np.maximum(pressure, f["adhesive_traction"][0]) if "adhesive_traction" in f else pressure
    view = View(nx, ny, data["lx"], data["ly"], map_limits(data, footprint, hertz))
    unit = data["length_unit"] or "length"
    note = subtitle(summary, unit)
    written = []
    for name, var, title, symbol, cmap, kind in MAPS:
        if var not in f or not wanted(name, only):
            continue
        values, _, units = f[var]
        if kind == "slip":
            values = np.where(contact > 0.5, values, np.nan)  # shown inside the contact only
        if name == "pressure" and np.nanmin(values) < 0:
            cmap, kind = "RdBu_r", "diverging"  # adhesion: tension (blue) beside compression (red)
        out = os.path.join(d, name + ".png")
        draw(out, view, values, title, colour_label(symbol, units), cmap, kind, unit, contact,
             stick if kind == "slip" else None, note, batch)
        written.append(out)
    # Flow current magnitudes: flow.nc (written with every flow), else the fields file.
    currents = {k: v for k, v in f.items() if CURRENT.fullmatch(k)}
    if flow:
        currents = read_netcdf(flow_nc, lambda k: CURRENT.fullmatch(k) and wanted(k, only))["fields"]
    for name in sorted(currents):
        if not wanted(name, only):
            continue
        values, _, units = currents[name]
        if values.shape != pressure.shape:
            continue
        tag = CURRENT.fullmatch(name).group(1)
        out = os.path.join(d, name + ".png")
        draw(out, view, values, f"flow current density, pressure gradient along {tag}",
             colour_label("$|q|$", units), "plasma", "positive", unit, contact, None, note, batch)
        written.append(out)
    if wanted("analysis", only) and os.path.isfile(os.path.join(d, "spectrum.csv")):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import plot_analysis

        written.append(plot_analysis.main(d, batch))
    if profiles and os.path.isfile(os.path.join(d, "profiles.csv")):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import plot_profiles

        written.append(plot_profiles.main(os.path.join(d, "profiles.csv"), batch))
    return written


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+", metavar="DIR", help="run directory (written by gfmd run)")
    ap.add_argument("--fields", help="NetCDF fields file (default DIR/fields.nc); one DIR only")
    ap.add_argument("--only", help="comma-separated map names to draw (e.g. pressure,current)")
    ap.add_argument("--profiles", action="store_true", help="also draw profiles.png from DIR/profiles.csv")
    args = ap.parse_args(argv)
    if args.fields and len(args.dirs) > 1:
        ap.error("--fields takes one DIR")
    only = set(args.only.split(",")) if args.only else None
    token = os.getpid()  # the temporaries of every directory: NAME.tmp.<token>
    jobs = [(d, args.fields, only, args.profiles, token) for d in args.dirs]
    workers = min(len(jobs), os.cpu_count() or 1, 4)
    try:
        if workers > 1:  # sweeps and studies: directories in parallel (forked after the imports)
            import multiprocessing

            with multiprocessing.get_context("fork").Pool(workers, initializer=figure_io.worker_signals) as pool:
                results = pool.map(plot_job, jobs, chunksize=1)
        else:
            results = [plot_job(j) for j in jobs]
        # Every directory's figures are published together, once all are drawn.
        batch = figure_io.Batch(token)
        for pending, _, _, _ in results:
            batch.add(pending)
        batch.publish()
    except KeyboardInterrupt:
        # The pool has ended its workers (SIGTERM); their temporaries and ours go.
        remove_temporaries(args.dirs, token)
        raise
    for _, written, _, _ in results:
        for p in written:
            print(p)
    for _, _, status, message in results:
        if message:
            print(f"plot_maps.py: error: {message}", file=sys.stderr)
    return max(status for _, _, status, _ in results)


def remove_temporaries(dirs, token):
    """Removes the figures' temporaries (*.tmp.<token>) in dirs."""
    with figure_io.signals_held():
        for d in dirs:
            for p in glob.glob(os.path.join(glob.escape(d), f"*.tmp.{token}")):
                try:
                    os.remove(p)
                except FileNotFoundError:
                    pass


def plot_job(job):
    """plot_dir for one directory, drawn to temporaries: ((temporary, path) pairs to publish,
    paths, exit status, error message). A failed directory's temporaries are removed."""
    d, fields, only, profiles, token = job
    batch = figure_io.Batch(token)
    try:
        written = plot_dir(d, fields, only, profiles, batch)
        pending, batch.pending = batch.pending, []
        return pending, written, 0, ""
    except InputProblem as e:
        return [], [], 2, str(e)
    except Exception as e:  # one directory's failure does not stop the others
        return [], [], 1, f"{d}: {type(e).__name__}: {e}"
    finally:
        batch.discard()


if __name__ == "__main__":
    figure_io.run_main(main, "plot_maps.py")
