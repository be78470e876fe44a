"""The figures of studies with kind = "sweep", "percolation" and "green" (PNG + PDF, and the
plotted data as CSV next to them); study.py loads this module only when it draws (after
choosing the Agg backend), so that `--runs-only` needs no matplotlib. The field maps and
profiles of kind = "runs" are in study_figures.py."""
import os

import matplotlib.pyplot as plt
import numpy as np
from figure_io import save, write_csv
from study_file import series_dir


def plot_percolation(study, results, out, fig_base):
    import netCDF4

    n = len(results)
    fig, axes = plt.subplots(1, n, figsize=(3.2 * n, 3.3), dpi=150, squeeze=False)
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


def plot_sweeps(study, results, fig_base):
    """One panel of y against x per series. With a [published] table (divide_by = a summary
    column, e.g. the realised rms gradient) a first panel draws x and y divided by that
    column, the way a published panel was drawn, and the plain axes follow as a second panel."""
    x, y = study["x"], study["y"]
    xs = float(study.get("x_scale", 1.0))
    ys = float(study.get("y_scale", 1.0))
    pub = study.get("published")
    panels = ([("published", pub)] if pub else []) + [("plain", None)]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels), 3.4 + (0.4 if pub else 0)), dpi=150,
                             squeeze=False)
    data = {}
    for (kind, spec), ax in zip(panels, axes[0]):
        for s, rows in results:
            xv = col(rows, x) * xs * float(s.get("x_scale", 1.0))
            yv = col(rows, y) * ys
            if spec:
                g = col(rows, spec["divide_by"])
                xv, yv = xv / g, yv / g
            ax.plot(xv, yv, s.get("style", "o-"), label=s["label"], color=s.get("color"))
            extra = [col(rows, c) for c in study.get("table_columns", [])]
            data[(kind, s["label"])] = (xv, yv, extra)
        # Without a label in the study file: the quantity's name and unit (figure_io), and a log
        # axis where the swept values are log-spaced (as gfmd sweep draws them).
        import figure_io
        from plot_sweep import log_spaced
        ax.set_xlabel(spec.get("xlabel", x) if spec else study.get("xlabel", figure_io.quantity_label(x)))
        ax.set_ylabel(spec.get("ylabel", y) if spec else study.get("ylabel", figure_io.quantity_label(y)))
        if study.get("xscale"):
            ax.set_xscale(study["xscale"])
        elif not spec:
            spaced = [log_spaced(list(col(rows, x))) for _, rows in results if len(rows) > 2]
            if spaced and all(spaced):
                ax.set_xscale("log")
        if study.get("yscale"):
            ax.set_yscale(study["yscale"])
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title((spec or {}).get("title", study.get("title", "")), fontsize=8)
    if pub and pub.get("caption"):
        fig.text(0.5, 0.01, pub["caption"], ha="center", va="bottom", fontsize=6.5)
        fig.tight_layout(rect=(0, 0.07, 1, 1))
    else:
        fig.tight_layout()
    save(fig, fig_base)
    # Extra summary columns (e.g. stick_fraction) per point, as listed in table_columns.
    write_csv(fig_base + ".csv", ["panel", "series", "x", "y"] + list(study.get("table_columns", [])),
              [[kind, label, repr(float(a)), repr(float(b))] + [repr(float(e[k])) for e in extra]
               for (kind, label), (xv, yv, extra) in data.items() for k, (a, b) in enumerate(zip(xv, yv))])


def plot_green(study, results, fig_base):
    fig, ax = plt.subplots(figsize=(4.6, 3.4), dpi=150)
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
