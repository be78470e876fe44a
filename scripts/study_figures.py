"""Figures drawn from the fields of single runs (studies with kind = "runs"): a grid of
maps (rows = fields, columns = series) or of line profiles along and across the sliding
direction through the pressure maximum. Axes labelled "quantity (unit)" (lengths in the
case's grid.unit, else L), every colour bar labelled with its [[maps]] label, the series'
titles wrapped to their map's width (clear of the colour bars)."""
import json
import os
import textwrap

import netCDF4
import numpy as np
from figure_io import label, save, subplots, wrap_to_width, write_csv


def load_fields(d):
    with netCDF4.Dataset(os.path.join(d, "fields.nc")) as nc:
        f = {k: np.array(v[:], dtype=float) for k, v in nc.variables.items() if v.ndim == 2}
        f["_lx"] = float(nc.getncattr("lx"))
        f["_ly"] = float(nc.getncattr("ly"))
        f["_unit"] = getattr(nc.variables["x"], "units", "") if "x" in nc.variables else ""
    return f


def window(f, crop):
    """Index window of half-width crop (length units) around the indenter's highest point."""
    h = f["topography"]
    ny, nx = h.shape
    iy, ix = np.unravel_index(np.argmax(h), h.shape)
    dx = f["_lx"] / nx
    w = int(round(crop / dx)) if crop else nx // 2
    ys = (np.arange(iy - w, iy + w + 1)) % ny
    xs = (np.arange(ix - w, ix + w + 1)) % nx
    ext = [-w * dx, w * dx, -w * dx, w * dx]
    return np.ix_(ys, xs), ext


def field(f, spec):
    name = spec["var"]
    if name not in f:  # e.g. slip fields of a static run
        return np.full_like(f["pressure"], np.nan)
    v = f[name].copy()
    if spec.get("contact_only"):
        v[f["pressure"] <= 0] = np.nan
    return v * float(spec.get("scale", 1.0))


def draw(study, results, out, fig_base):
    series = [(s, os.path.join(out, f"series_{i:02d}")) for i, (s, _) in enumerate(results)]
    if study.get("figure", "maps") == "maps":
        draw_maps(study, series, fig_base)
    elif study["figure"] == "cross_section":
        draw_cross_section(study, series, fig_base)
    else:
        draw_profiles(study, series, fig_base)


def draw_maps(study, series, fig_base):
    """One row per [[maps]] entry, one column per series. A map with scale_to = "<field>" is
    multiplied by max(<field>) / max(own) over the whole cell (the paper's scaling of its
    post-analysis panels), drawn with the colour limits of <field> and labelled with the
    factor. Post-analysis summaries go to <fig_base>_ratios.csv."""
    rows = study["maps"]
    fig, axes = subplots(len(rows), len(series), figsize=(2.5 * len(series), 2.2 * len(rows) + 0.4), dpi=150,
                         squeeze=False)
    table = []
    unit = "length"
    for c, (s, d) in enumerate(series):
        f = load_fields(d)
        unit = f["_unit"] or "length"
        idx, ext = window(f, study.get("crop"))
        for r, spec in enumerate(rows):
            v = field(f, spec)
            factor = None
            if spec.get("scale_to"):
                ref = field(f, {"var": spec["scale_to"]})
                if np.nanmax(v) > 0:
                    factor = float(np.nanmax(ref) / np.nanmax(v))
                    v = v * factor
                lim = float(np.nanmax(np.abs(ref[idx])))
            else:
                lim = np.nanmax(np.abs(v[idx])) if spec.get("symmetric") else None
            v = v[idx]
            ax = axes[r][c]
            im = ax.imshow(v, origin="lower", extent=ext, cmap=spec.get("cmap", "viridis"),
                           vmin=-lim if lim else spec.get("vmin"), vmax=lim if lim else spec.get("vmax"))
            if factor is not None:
                ax.text(0.03, 0.95, f"× {factor:.3g}", transform=ax.transAxes, fontsize=7, va="top",
                        bbox={"facecolor": "white", "alpha": 0.7, "lw": 0})
            cb = fig.colorbar(im, ax=ax, shrink=0.8)
            cb.set_label(spec.get("label", spec["var"]), fontsize=7)
            cb.ax.tick_params(labelsize=6)
            # Coordinates from the indenter's highest point, on the outer panels only.
            ax.tick_params(labelsize=6, labelbottom=r == len(rows) - 1, labelleft=c == 0)
            if r == len(rows) - 1:
                ax.set_xlabel(label("x − x₀", unit), fontsize=7)
            if c == 0:
                ax.set_ylabel(label("y − y₀", unit), fontsize=7)
            if r == 0:
                ax.set_title(s["label"], fontsize=7)
            table.append([s["label"], spec["var"], float(np.nanmin(v)), float(np.nanmax(v))])
    fig.suptitle(textwrap.fill(study.get("title", ""), 30 * len(series)), fontsize=8)
    if study.get("caption"):
        fig.text(0.5, 0.005, study["caption"], ha="center", va="bottom", fontsize=6, wrap=True)
    rect = (0, 0.04 if study.get("caption") else 0, 1, 1)
    fig.tight_layout(rect=rect)
    # The series' titles no wider than their maps (centred over them: wider ones ran into the
    # colour bars beside them), then the layout again for their height.
    renderer = fig.canvas.get_renderer()
    for ax in axes[0]:
        wrap_to_width(ax.title, ax.get_window_extent(renderer).width, renderer)
    fig.tight_layout(rect=rect)
    save(fig, fig_base)
    write_csv(fig_base + ".csv", ["series", "field", "min", "max"], table)
    ratios = []
    for s, d in series:
        with open(os.path.join(d, "summary.json")) as fh:
            j = json.load(fh)
        for key, pa in j.items():
            if key.startswith("post_analysis_") and isinstance(pa, dict):
                ratios.append([s["label"], pa["kind"], j["max_tensile_stress"], pa["max_tensile_stress"],
                               pa["ratio_max_tensile_stress"], pa["ratio_max_von_mises"],
                               j.get("area_fraction_above_half_max"), pa["area_fraction_above_half_max"],
                               pa["ratio_area_above_half_max"]])
    if ratios:
        write_csv(fig_base + "_ratios.csv",
                  ["series", "post_analysis", "full_sigma_I_max", "post_sigma_I_max", "full_over_post_sigma_I_max",
                   "full_over_post_von_mises_max", "full_area_above_half_max", "post_area_above_half_max",
                   "full_over_post_area"], ratios)


def draw_cross_section(study, series, fig_base):
    """Indenter surface (uz + gap) and deformed elastic surface uz along the middle row."""
    fig, axes = subplots(len(series), 1, figsize=(6.0, 2.0 * len(series)), dpi=150, squeeze=False)
    table = []
    for k, (s, d) in enumerate(series):
        f = load_fields(d)
        ny, nx = f["uz"].shape
        row = ny // 2
        x = np.arange(nx) * f["_lx"] / nx
        body = f["uz"][row]
        indenter = body + f["gap"][row]
        ax = axes[k][0]
        ax.fill_between(x, indenter, indenter.max() + 0.2 * np.ptp(indenter), color="0.55", lw=0)
        ax.fill_between(x, body, body.min() - 0.2 * np.ptp(indenter), color="C0", alpha=0.5, lw=0)
        ax.plot(x, body, color="C0", lw=0.8)
        ax.plot(x, indenter, color="0.2", lw=0.8)
        ax.set_title(s["label"], fontsize=7)
        unit = f["_unit"] or "length"
        ax.set_xlabel(label("x", unit), fontsize=7)
        ax.set_ylabel(label("z", unit), fontsize=7)
        ax.tick_params(labelsize=6)
        table += [[s["label"], float(a), float(b), float(c)] for a, b, c in zip(x, indenter, body)]
    fig.suptitle(study.get("title", ""), fontsize=8)
    fig.tight_layout()
    save(fig, fig_base)
    write_csv(fig_base + ".csv", ["series", "x", "indenter_surface", "elastic_surface"], table)


def draw_profiles(study, series, fig_base):
    rows = study["profiles"]
    fig, axes = subplots(len(rows), len(series), figsize=(2.3 * len(series), 1.8 * len(rows)), dpi=150,
                         squeeze=False, sharex=True)
    table = []
    unit = "length"
    for c, (s, d) in enumerate(series):
        f = load_fields(d)
        unit = f["_unit"] or "length"
        p = f["pressure"]
        ny, nx = p.shape
        iy, ix = np.unravel_index(np.argmax(p), p.shape)
        dx = f["_lx"] / nx
        crop = study.get("crop", f["_lx"] / 2)
        w = int(round(crop / dx))
        off = np.arange(-w, w + 1)
        xs = off * dx
        for r, spec in enumerate(rows):
            v = field(f, spec)
            lon = v[iy, (ix + off) % nx]
            tra = v[(iy + off) % ny, ix]
            ax = axes[r][c]
            ax.plot(xs, lon, "-", color="C0", lw=1, label="longitudinal")
            ax.plot(xs, tra, "--", color="C1", lw=1, label="transverse")
            ax.axhline(0, color="0.7", lw=0.5)
            if r == 0:
                ax.set_title(s["label"], fontsize=7)
            if c == 0:
                ax.set_ylabel(spec.get("label", spec["var"]), fontsize=7)
            ax.tick_params(labelsize=6)
            for k, x in enumerate(xs):
                table.append([s["label"], spec["var"], float(x), float(lon[k]), float(tra[k])])
    for ax in axes[-1]:
        ax.set_xlabel(study.get("xlabel", label("distance from the pressure maximum", unit)), fontsize=7)
    h = fig.get_size_inches()[1]
    fig.suptitle(study.get("title", ""), fontsize=8, y=1 - 0.06 / h, va="top")
    rect = (0, 0, 1, 1 - 0.3 / h)
    fig.tight_layout(rect=rect)
    renderer = fig.canvas.get_renderer()
    for ax in axes[0]:
        wrap_to_width(ax.title, ax.get_window_extent(renderer).width, renderer)
    fig.tight_layout(rect=rect)
    # One key for all panels, under the title (outside the data).
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 1 - 0.24 / h), ncol=2, fontsize=6,
               frameon=False)
    save(fig, fig_base)
    write_csv(fig_base + ".csv", ["series", "field", "s", "longitudinal", "transverse"], table)

