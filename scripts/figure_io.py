"""What gfmd's drawing scripts share: one notation for units in labels, figures written to
temporaries and published together, the handling of Ctrl-C and SIGTERM (exit status 4, no
traceback, no temporary left, no figure changed), and atomic CSV tables.

Labels: "quantity (unit)" everywhere (axes and colour bars, CLI and Python): lengths in the
case's grid.unit ("x (µm)") or "L" where the case names none ("x (L)"), pressures and
stresses in "E*", dimensionless quantities marked "(–)".

Publishing: a Batch collects the figures of one command, each drawn to "<path>.tmp.<token>";
publish() renames them all at the end (with SIGINT/SIGTERM held back, so a Ctrl-C never
leaves a mix of old and new figures); discard() removes the temporaries. run_main() runs a
script's main(): on Ctrl-C or SIGTERM it discards every unpublished batch, prints one line and
exits with status 4 (gfmd's "interrupted", which the C++ front end passes on)."""
import contextlib
import csv
import json
import math
import os
import re
import signal
import sys

INTERRUPTED = 4  # gfmd's exit status for an interrupted command
DIMENSIONLESS = "–"
_SUPERSCRIPT = {"1": "¹", "2": "²", "3": "³", "4": "⁴", "-": "⁻"}
_batches = []  # unpublished batches of this process (run_main discards them on an interrupt)
_published = []  # the paths this process has published (for run_main's last line)


# ---------------------------------------------------------------------------------------
# Units and labels


def length_unit(unit):
    """The display form of a length unit of gfmd's files: 'length' or '' (no grid.unit) -> 'L',
    'um' -> 'µm'; other names as they are."""
    if unit in (None, "", "length", "L"):
        return "L"
    return {"um": "µm", "micron": "µm", "microns": "µm", "Angstrom": "Å", "angstrom": "Å"}.get(unit, unit)


def unit_text(units):
    """The display form of a units attribute: '1' or '' -> '' (dimensionless); the lengths as
    length_unit; powers as superscripts ('length^3' -> 'L³', 'um^2' -> 'µm²')."""
    if units in (None, "", "1", "-", DIMENSIONLESS):
        return ""
    out = []
    for token in str(units).split():
        m = re.fullmatch(r"(.+?)(?:\^(-?\d+))?", token)
        base, power = length_unit(m.group(1)), m.group(2)
        out.append(base + "".join(_SUPERSCRIPT.get(c, c) for c in power or ""))
    return " ".join(out)


def label(quantity, units):
    """'quantity (unit)', or 'quantity (–)' for a dimensionless one: the one notation of every
    axis and colour-bar label."""
    u = unit_text(units)
    return f"{quantity} ({u or DIMENSIONLESS})"


def grid_unit(summary):
    """The case's length unit from a summary.json (or the "input" of sweep.json/curve.json)."""
    if not isinstance(summary, dict):
        return "length"
    inp = summary.get("input", summary.get("input_first_point", summary))
    try:
        return inp.get("grid", {}).get("unit") or "length"
    except AttributeError:
        return "length"


def grid_unit_beside(path, json_name):
    """grid.unit recorded in the JSON file json_name (summary.json, sweep.json) in the folder of
    path, 'length' where there is none."""
    try:
        with open(os.path.join(os.path.dirname(path) or ".", json_name)) as fh:
            return grid_unit(json.load(fh))
    except (OSError, ValueError):
        return "length"


def save_png_or_stage(fig, out, batch=None):
    """Writes fig to out at once or, with batch (a Batch its caller publishes), stages it there.
    Returns out."""
    if batch is None:
        save_png(fig, out)
    else:
        batch.save(fig, out, format="png")
    return out


# ---------------------------------------------------------------------------------------
# Signals


@contextlib.contextmanager
def signals_held():
    """SIGINT and SIGTERM held back (delivered when the block ends)."""
    sigs = {signal.SIGINT, signal.SIGTERM}
    old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _raise_interrupt(signum, frame):
    raise KeyboardInterrupt


def _exit_interrupted_at_start(signum, frame):
    os.write(2, f"{os.path.basename(sys.argv[0])}: interrupted; no figure was changed\n".encode())
    os._exit(INTERRUPTED)


def exit_on_interrupt_while_starting():
    """Until run_main takes over: Ctrl-C or SIGTERM ends the script at once with status 4 (it
    has written nothing yet; this covers the second or so of importing matplotlib). Only in
    a script's __main__ (never on import: it would change the importing program's signals)."""
    for s in (signal.SIGINT, signal.SIGTERM):
        if signal.getsignal(s) is not signal.SIG_IGN:
            signal.signal(s, _exit_interrupted_at_start)


def worker_signals():
    """For a worker process of a pool: the parent alone handles Ctrl-C (it ends the workers
    with SIGTERM, then removes their temporaries)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def run_main(main, name=None):
    """Runs a script's main() and exits with its status (None = 0). Ctrl-C and SIGTERM raise
    KeyboardInterrupt; then every unpublished batch's temporaries are removed, one line goes
    to stderr (no traceback) and the status is 4."""
    name = name or os.path.basename(sys.argv[0])
    for s in (signal.SIGINT, signal.SIGTERM):
        if signal.getsignal(s) is not signal.SIG_IGN:
            signal.signal(s, _raise_interrupt)
    try:
        try:
            status = main()
        finally:
            with signals_held():
                for b in list(_batches):
                    b.discard()
    except KeyboardInterrupt:
        for s in (signal.SIGINT, signal.SIGTERM):
            signal.signal(s, signal.SIG_IGN)
        done = "no figure was changed" if not _published else f"after writing {len(_published)} figures"
        print(f"{name}: interrupted; {done}", file=sys.stderr)
        sys.exit(INTERRUPTED)
    sys.exit(status or 0)


# ---------------------------------------------------------------------------------------
# Figures and tables


def temporary_name(path, token=None):
    return f"{path}.tmp.{os.getpid() if token is None else token}"


class Batch:
    """Figures drawn to temporaries (<path>.tmp.<token>, token = this process's id unless
    given) and renamed together by publish(). pending: the (temporary, path) pairs."""

    def __init__(self, token=None):
        self.token = os.getpid() if token is None else token
        self.pending = []
        _batches.append(self)

    def save(self, fig, path, **savefig):
        """Draws fig to path's temporary (format from the extension, PNG by default) and closes it."""
        ext = os.path.splitext(path)[1].lstrip(".").lower()
        savefig.setdefault("format", ext if ext in ("png", "pdf", "svg") else "png")
        tmp = temporary_name(path, self.token)
        self.pending.append((tmp, path))  # before drawing: a half-written temporary is known too
        try:
            fig.savefig(tmp, **savefig)
        finally:
            _close(fig)
        return path

    def add(self, pairs):
        """Takes over (temporary, path) pairs drawn elsewhere (a worker process)."""
        self.pending.extend(pairs)

    def publish(self):
        """Renames every temporary to its path, with Ctrl-C held back until all are renamed.
        Returns the paths."""
        done = []
        with signals_held():
            try:
                for tmp, path in self.pending:
                    os.replace(tmp, path)
                    done.append(path)
            finally:
                _published.extend(done)
                self.pending = self.pending[len(done):]
                self.discard()
        return done

    def discard(self):
        """Removes the temporaries not published."""
        with signals_held():
            for tmp, _ in self.pending:
                with contextlib.suppress(FileNotFoundError):
                    os.remove(tmp)
            self.pending = []
            if self in _batches:
                _batches.remove(self)


def subplots(nrows=1, ncols=1, figsize=None, dpi=None, **kwargs):
    """plt.subplots without pyplot: a Figure of its own (drawn by savefig with Agg), so that a
    study drawn inside a user's Python process (gfmd.study) neither needs nor changes the
    process's matplotlib backend, and keeps no figure open in it."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, dpi=dpi)
    FigureCanvasAgg(fig)  # its renderer measures text (tight_layout, wrapped titles)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def _close(fig):
    """Closes a pyplot figure (the plotting scripts'); a Figure of subplots() is not pyplot's."""
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close(fig)


def save(fig, base, **savefig):
    """Writes base.png and base.pdf (to temporaries, renamed together) and closes fig."""
    b = Batch()
    try:
        for ext in ("png", "pdf"):
            tmp = temporary_name(f"{base}.{ext}")
            b.pending.append((tmp, f"{base}.{ext}"))
            fig.savefig(tmp, format=ext, **savefig)
        b.publish()
    finally:
        _close(fig)
        b.discard()


def save_png(fig, path, **savefig):
    """Writes path as PNG (to a temporary, then renamed; the temporary removed if drawing
    fails) and closes fig."""
    b = Batch()
    try:
        b.save(fig, path, format="png", **savefig)
        b.publish()
    finally:
        b.discard()
    return path


def write_csv(path, head, rows):
    tmp = temporary_name(path)
    try:
        with open(tmp, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(head)
            w.writerows(rows)
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.remove(tmp)


def fit(fig, pad=0.06):
    """Grows fig where its labels, titles, colour bars or legends reach past its edge (or
    shrinks a wasted margin), keeping every axes' size in inches: nothing is cut off. Text
    layout only (no image is drawn: cheaper than savefig's bbox_inches="tight")."""
    from matplotlib.transforms import Bbox

    r = fig.canvas.get_renderer()
    boxes = [a.get_tightbbox(r) for a in fig.axes if a.get_visible()]
    boxes += [t.get_window_extent(r) for t in fig.texts if t.get_visible() and t.get_text()]
    boxes += [leg.get_window_extent(r) for leg in fig.legends]
    boxes = [b for b in boxes if b is not None and b.width > 0 and b.height > 0]
    if not boxes:
        return fig
    bb = Bbox.union(boxes)
    dpi = fig.dpi
    w, h = fig.get_size_inches()
    x0, y0 = bb.x0 / dpi - pad, bb.y0 / dpi - pad  # inches from the figure's lower left corner
    x1, y1 = bb.x1 / dpi + pad, bb.y1 / dpi + pad
    # Only grow (a hand-made layout's margins are kept where they suffice).
    left, bottom = max(0.0, -x0), max(0.0, -y0)
    nw, nh = left + max(w, x1), bottom + max(h, y1)
    if left == 0 and bottom == 0 and nw == w and nh == h:
        return fig
    boxes_in = [(a, a.get_position()) for a in fig.axes]
    fig.set_size_inches(nw, nh)
    for a, p in boxes_in:
        a.set_position(((p.x0 * w + left) / nw, (p.y0 * h + bottom) / nh, p.width * w / nw, p.height * h / nh))
    for t in fig.texts:
        x, y = t.get_position()
        if t.get_transform() == fig.transFigure:
            t.set_position(((x * w + left) / nw, (y * h + bottom) / nh))
    return fig


# ---------------------------------------------------------------------------------------
# Names of the numbers in summary.json / sweep.csv / curve.csv and of the swept keys, for the
# axes of sweep and curve plots: key -> (name, units). "length" is the case's grid.unit.
QUANTITIES = {
    # swept input keys
    "load.pressure": ("mean pressure p̄", "E*"),
    "load.force": ("normal force F", "E* length^2"),
    "load.approach": ("approach d", "length"),
    "friction.coefficient": ("local friction coefficient μ_c", "1"),
    "friction.direction": ("sliding direction", "deg"),
    "friction.creepage": ("creepage ξ", "1"),
    "friction.lateral_creepage": ("lateral creepage η", "1"),
    "friction.regularization": ("regularisation slip speed ε/v₀", "1"),
    "elastic.poisson": ("Poisson's ratio ν", "1"),
    "elastic.thickness": ("layer thickness h", "length"),
    "indenter.radius": ("indenter radius R", "length"),
    "indenter.radius_x": ("indenter radius R_x", "length"),
    "indenter.radius_y": ("indenter radius R_y", "length"),
    "indenter.amplitude": ("egg-crate amplitude", "length"),
    "indenter.wavelength": ("egg-crate wavelength", "length"),
    "indenter.hurst": ("Hurst exponent H", "1"),
    "indenter.rms_height": ("rms height", "length"),
    "indenter.rms_gradient": ("rms gradient", "1"),
    "indenter.lambda_long": ("long-wavelength cut-off λ_l", "length"),
    "indenter.lambda_short": ("short-wavelength cut-off λ_s", "length"),
    "indenter.seed": ("random seed", "1"),
    "grid.nx": ("grid points nx", "1"),
    "grid.ny": ("grid points ny", "1"),
    "grid.lx": ("cell length lx", "length"),
    "grid.ly": ("cell length ly", "length"),
    "solver.tolerance": ("solver tolerance", "1"),
    # results (summary.json, sweep.csv, curve.csv)
    "pressure": ("mean pressure p̄", "E*"),
    "relative_contact_area": ("relative contact area A/A₀", "1"),
    "normal_force": ("normal force F", "E* length^2"),
    "mean_pressure": ("mean pressure p̄", "E*"),
    "max_pressure": ("maximum pressure", "E*"),
    "mean_gap": ("mean gap over the cell ⟨g⟩", "length"),  # contact points count 0
    "approach": ("approach d", "length"),
    "iterations": ("iterations", "1"),
    "residual": ("residual", "1"),
    "wall_time_s": ("wall time", "s"),
    "fft_count": ("FFTs", "1"),
    "fft_time_s": ("time in FFTs", "s"),
    "friction_coefficient": ("μ from the dissipation", "1"),
    "friction_coefficient_downhill": ("μ from μ_c F + downhill force", "1"),
    "traction_coefficient": ("traction coefficient F_t/F", "1"),
    "energy_balance_error": ("energy balance error", "1"),
    "min_slip_velocity": ("minimum slip speed / v₀", "1"),
    "near_stick_fraction": ("near-stick fraction", "1"),
    "stick_fraction": ("stick fraction of the contact", "1"),
    "friction_force": ("friction force", "E* length^2"),
    "friction_force_slip": ("friction force of the slipping points", "E* length^2"),
    "numerical_dissipation_fraction": ("numerical dissipation fraction", "1"),
    "tangential_force": ("tangential force F_t", "E* length^2"),
    "tangential_force_x": ("tangential force F_x", "E* length^2"),
    "tangential_force_y": ("tangential force F_y", "E* length^2"),
    "tangential_iterations": ("stick-slip steps", "1"),
    "max_tensile_stress": ("max. tensile stress σ_I", "E*"),
    "max_von_mises": ("max. von Mises stress", "E*"),
    "high_tension_area_fraction": ("high-tension area fraction", "1"),
    "area_fraction_above_half_max": ("area fraction above half the max. σ_I", "1"),
    "rms_height": ("rms height", "length"),
    "rms_gradient": ("rms gradient", "1"),
    "rms_curvature": ("rms curvature", "length^-1"),
    "topography.rms_height": ("rms height", "length"),
    "topography.rms_gradient": ("rms gradient", "1"),
    "topography.rms_curvature": ("rms curvature", "length^-1"),
    "analysis.gap.mean": ("mean gap out of contact", "length"),
    "analysis.pressure.mean": ("mean pressure in contact", "E*"),
}


def quantity(key):
    """(name, units) of a summary/sweep/curve column or a swept key; units None if unknown."""
    if key in QUANTITIES:
        return QUANTITIES[key]
    for prefix, units, name in (("conductivity_", "length^3", "conductivity K_eff along "),
                                ("flow_factor_", "1", "flow factor K_eff/⟨g⟩³ along "),
                                ("percolates_", "1", "percolates along ")):
        if key.startswith(prefix):
            return name + key[len(prefix):], units
    return key, None


def quantity_label(key, length="length"):
    """The axis label of a column or swept key: "name (unit)", lengths in `length` (grid.unit);
    an unknown key as it is, with no unit claimed."""
    name, units = quantity(key)
    if units is None:
        return key
    return label(name, _with_length(units, length))


def _with_length(units, length):
    out = []
    for t in units.split():
        base, _, power = t.partition("^")
        out.append((length if base == "length" else base) + (f"^{power}" if power else ""))
    return " ".join(out)


def wrap_to_width(text_artist, width_px, renderer, min_chars=8):
    """Rewraps a Text (at blanks) into the fewest lines no wider than width_px; returns it."""
    import textwrap

    words = " ".join(text_artist.get_text().split("\n"))
    for chars in range(len(words), min_chars - 1, -1):
        text_artist.set_text(textwrap.fill(words, chars))
        if text_artist.get_window_extent(renderer).width <= width_px:
            break
    return text_artist


def log_spaced(values):
    """True for positive values that are closer to a geometric than to an arithmetic
    progression (two values: a ratio of 10 or more)."""
    x = sorted(set(v for v in values if math.isfinite(v)))
    if len(x) < 2 or x[0] <= 0:
        return False
    if len(x) == 2:
        return x[1] / x[0] >= 10
    lin = [b - a for a, b in zip(x, x[1:])]
    log = [math.log(b / a) for a, b in zip(x, x[1:])]

    def spread(d):
        m = sum(d) / len(d)
        return math.sqrt(sum((v - m) ** 2 for v in d) / len(d)) / m

    return spread(log) < spread(lin)
