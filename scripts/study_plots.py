"""The figures of studies with kind = "sweep", "percolation" and "green" (PNG + PDF, and the
plotted data as CSV next to them); study.py loads this module only when it draws (after
choosing the Agg backend), so that `--runs-only` needs no matplotlib. The field maps and
profiles of kind = "runs" are in study_figures.py."""
import os

import numpy as np
from figure_io import log_spaced, save, subplots, write_csv
from study_file import series_dir


def plot_percolation(study, results, out, fig_base):
    import netCDF4

    n = len(results)
    fig, axes = subplots(1, n, figsize=(3.2 * n, 3.3), dpi=150, squeeze=False)
    rows = []
    for i, (s, res) in enumerate(results):
        d = series_dir(out, i)
        masks = []
        for tag in ("static_at_pstar", "sliding_at_pstar"):
            with netCDF4.Dataset(os.path.join(d, tag, "fields.nc")) as nc:
                masks.append(np.array(nc.variables["contact"][:]) > 0.5)
        img = np.ones(masks[0].shape + (3,))
        img[masks[0] & ~masks[1]] = (0.2, 0.4, 0.9)   # frictionless only: blue
        img[~masks[0] & masks[1]] = (1.0, 0.6, 0.1)   # with friction only: orange
        img[masks[0] & masks[1]] = (0.55, 0.3, 0.65)  # both: purple
        ax = axes[0][i]
        ax.imshow(img, origin="lower", extent=[0, 1, 0, 1])
        ax.set_title(s["label"], fontsize=7)
        ax.set_xlabel("x / λ  (sliding →)", fontsize=7)
        ax.tick_params(labelsize=6)
        a0 = res["frictionless"]["critical_relative_contact_area"]
        a1 = res["sliding_at_pstar"]["relative_contact_area"]
        ax.text(0.02, 0.02, f"a_c* = {a0:.3f}\nwith friction at p*: {a1:.3f}", fontsize=6, transform=ax.transAxes,
                va="bottom")
        rows.append([s["label"], a0, res["frictionless"]["critical_pressure"],
                     res["static_at_pstar"]["relative_contact_area"], a1,
                     res["friction_along"]["critical_relative_contact_area"],
                     res["friction_across"]["critical_relative_contact_area"]])
    fig.suptitle(study.get("title", ""), fontsize=8)
    fig.tight_layout()
    save(fig, fig_base)
    write_csv(fig_base + ".csv", ["series", "a_c*_frictionless", "p*", "a_c_static_at_p*", "a_c_sliding_at_p*",
                                  "a_c*_friction_along_sliding", "a_c*_friction_across_sliding"], rows)


def col(rows, key):
    return np.array([float(r[key]) if r.get(key, "") not in ("", "null") else np.nan for r in rows])


def series_points(rows, x, y, xs, ys, divide_by):
    """x and y of one sweep's rows, scaled, and divided by the column divide_by (if any)."""
    xv, yv = col(rows, x) * xs, col(rows, y) * ys
    if divide_by:
        g = col(rows, divide_by)
        xv, yv = xv / g, yv / g
    return xv, yv


def reference_points(r):
    """x and y of a [[reference]] curve: its file's columns r["x"], r["y"] on the rows that
    match every "column=value" of r["where"] (numbers compared as numbers)."""
    import csv

    with open(r["_path"], newline="") as f:
        rows = list(csv.DictReader(f))
    for cond in r.get("where", []):
        k, v = cond.split("=", 1)
        try:
            rows = [row for row in rows if float(row[k]) == float(v)]
        except ValueError:
            rows = [row for row in rows if row[k] == v]
    return col(rows, r["x"]), col(rows, r["y"])


def ensemble_stats(per_seed):
    """Per load (the i-th point of every seed's sweep): mean x, and the mean, standard
    deviation (n - 1) and range of y over the seeds that reached it."""
    n = max(len(xv) for xv, _ in per_seed.values())
    out = []
    for i in range(n):
        xs = np.array([xv[i] for xv, _ in per_seed.values() if i < len(xv)])
        ys = np.array([yv[i] for _, yv in per_seed.values() if i < len(yv)])
        sd = float(np.std(ys, ddof=1)) if len(ys) > 1 else 0.0
        out.append((float(np.mean(xs)), float(np.mean(ys)), sd, float(ys.min()), float(ys.max()), len(ys)))
    return out


def plot_sweeps(study, results, fig_base):
    """One panel of y against x per series. With a [published] table (divide_by = a summary
    column, e.g. the realised rms gradient) a first panel draws x and y divided by that
    column, the way a published panel was drawn; then either the plain axes or, with a
    [second] table, its quantity (second.y, divided alike). A series with `seeds` is drawn as
    the mean over its seeds with a band of one standard deviation (darker) and the range
    (lighter); the table holds every seed and the mean, std, min and max per load."""
    x, y = study["x"], study["y"]
    xs = float(study.get("x_scale", 1.0))
    ys = float(study.get("y_scale", 1.0))
    pub = study.get("published")
    sec = study.get("second")
    panels = ([("published", pub, y)] if pub else [])
    panels += [("second", sec, sec["y"])] if sec else [("plain", None, y)]
    if sec and not pub:
        panels = [("plain", None, y)] + panels
    fig, axes = subplots(1, len(panels), figsize=(4.6 * len(panels), 3.4 + (0.4 if pub else 0)), dpi=150,
                         squeeze=False)
    table = []
    extra_cols = list(study.get("table_columns", []))
    import figure_io
    for (kind, spec, yname), ax in zip(panels, axes[0]):
        divide = pub["divide_by"] if pub and kind != "plain" else None
        # The series' y_scale (e.g. 1/mu_c) applies to the study's y, not to a [second] quantity.
        for s, res in results:
            sx = xs * float(s.get("x_scale", 1.0))
            sy = ys * (float(s.get("y_scale", 1.0)) if yname == y else 1.0)
            style, color = s.get("style", "o-"), s.get("color")
            if isinstance(res, dict) and "seeds" in res:
                per_seed = {seed: series_points(rows, x, yname, sx, sy, divide) for seed, rows in res["seeds"].items()}
                st = ensemble_stats(per_seed)
                mx, my = np.array([r[0] for r in st]), np.array([r[1] for r in st])
                sd = np.array([r[2] for r in st])
                lo, hi = np.array([r[3] for r in st]), np.array([r[4] for r in st])
                # The line first: its colour (the series' own, or the cycle's next) is the bands'.
                line, = ax.plot(mx, my, style, label=f"{s['label']} ({len(per_seed)} seeds)", color=color, ms=3)
                ax.fill_between(mx, lo, hi, color=line.get_color(), alpha=0.12, lw=0)
                ax.fill_between(mx, my - sd, my + sd, color=line.get_color(), alpha=0.3, lw=0)
                for seed, rows in res["seeds"].items():
                    xv, yv = per_seed[seed]
                    extra = [col(rows, c) for c in extra_cols]
                    table += [[kind, s["label"], repr(float(a)), repr(float(b))]
                              + [repr(float(e[k])) for e in extra] + [str(seed), yname]
                              for k, (a, b) in enumerate(zip(xv, yv))]
                for r in st:
                    for tag, v in (("mean", r[1]), ("std", r[2]), ("min", r[3]), ("max", r[4])):
                        table.append([kind, s["label"], repr(r[0]), repr(v)] + [""] * len(extra_cols) + [tag, yname])
            else:
                xv, yv = series_points(res, x, yname, sx, sy, divide)
                ax.plot(xv, yv, style, label=s["label"], color=color)
                extra = [col(res, c) for c in extra_cols]
                table += [[kind, s["label"], repr(float(a)), repr(float(b))]
                          + [repr(float(e[k])) for e in extra] + ["", yname] for k, (a, b) in enumerate(zip(xv, yv))]
        # Reference curves (e.g. the published data) on their panel, from their CSV file.
        for r in study.get("reference", []):
            if r.get("panel", "published") == kind and yname == y:
                rx, ry = reference_points(r)
                # A reference's colour, where it has one, replaces the default style's black
                # (matplotlib warns about a colour in both, even color=None).
                colour = {"color": r["color"]} if r.get("color") else {}
                ax.plot(rx, ry, r.get("style", ":" if colour else "k:"), label=r["label"], lw=1.2, **colour)
        # Without a label in the study file: the quantity's name and unit (figure_io), and a log
        # axis where the swept values are log-spaced (as gfmd sweep draws them).
        own = spec if kind != "plain" else None
        xlabel = (pub or {}).get("xlabel") if divide else study.get("xlabel")
        ax.set_xlabel(xlabel or figure_io.quantity_label(x))
        ylabel = (own or {}).get("ylabel") if own else study.get("ylabel")
        ax.set_ylabel(ylabel or figure_io.quantity_label(yname))
        if study.get("xscale"):
            ax.set_xscale(study["xscale"])
        elif not divide:
            all_rows = [rows for _, res in results
                        for rows in (res["seeds"].values() if isinstance(res, dict) and "seeds" in res else [res])]
            spaced = [log_spaced(list(col(rows, x))) for rows in all_rows if len(rows) > 2]
            if spaced and all(spaced):
                ax.set_xscale("log")
        if study.get("yscale"):
            ax.set_yscale(study["yscale"])
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6)
        ax.set_title((own or {}).get("title", study.get("title", "")), fontsize=8)
    if pub and pub.get("caption"):
        fig.text(0.5, 0.01, pub["caption"], ha="center", va="bottom", fontsize=6.5, wrap=True)
        fig.tight_layout(rect=(0, 0.09, 1, 1))
    else:
        fig.tight_layout()
    save(fig, fig_base)
    # Extra summary columns (e.g. stick_fraction) per point, as listed in table_columns; then,
    # where the study has them, the seed (or mean/std/min/max over the seeds) and the quantity
    # drawn (y or second.y): the columns of studies without seeds and [second] stay as they were.
    seeded = any(isinstance(res, dict) and "seeds" in res for _, res in results)
    n = 4 + len(extra_cols)
    keep = list(range(n)) + ([n] if seeded else []) + ([n + 1] if sec else [])
    head = [(["panel", "series", "x", "y"] + extra_cols + ["seed", "quantity"])[c] for c in keep]
    table = [[r[c] for c in keep] for r in table]
    write_csv(fig_base + ".csv", head, table)


def plot_green(study, results, fig_base):
    fig, ax = subplots(figsize=(4.6, 3.4), dpi=150)
    rows_out = []
    for _, rows in results:
        nus = sorted({r["poisson"] for r in rows}, key=float)
        for nu in nus:
            sel = [r for r in rows if r["poisson"] == nu]
            qh = np.array([float(r["qh"]) for r in sel])
            im = np.array([float(r["im_phi13"]) for r in sel])
            ax.plot(qh, im, label=f"ν = {float(nu):g}")
            rows_out += [[nu, a, b] for a, b in zip(qh, im)]
    ax.set_xscale("log")
    ax.set_xlabel("q h")
    ax.set_ylabel("Im Φ_13")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(study.get("title", ""), fontsize=8)
    fig.tight_layout()
    save(fig, fig_base)
    write_csv(fig_base + ".csv", ["poisson", "qh", "im_phi13"], rows_out)
