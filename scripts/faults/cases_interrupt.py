"""Interruptions: Ctrl-C and SIGTERM while gfmd solves, sweeps or draws, and what is left.

Each function adds its faults in the order of the table (ids are positions); fault_table.py
calls them in that order."""
import os
import signal
import time

from faults.checks import added, has_fragment, pngs_newer, read_json, snapshot
from faults.harness import LONG, STUDY_SMALL, SWEEP0


def issue_sweep(F):
    """Ctrl-C in a long sweep (from the issue)."""
    base, add = F.base, F.add

    def f8(d):
        t0 = time.monotonic()
        r, sent = F.interrupt(["sweep", base, "-o", d, "-q"] + SWEEP0, signal.SIGINT,
                              lambda: time.monotonic() - t0 > 2.0)
        cls, code, note = F.interrupted_verdict(r, sent, d, "the sweep")
        if sent and r.rc == 4 and os.path.isdir(d):
            points = [x for x in os.listdir(d) if x.startswith("point_")]
            try:
                with open(os.path.join(d, "sweep.csv")) as f:
                    rows = sum(1 for _ in f) - 1
            except OSError:
                rows = None
            st = (read_json(os.path.join(d, "status.json")) or {}).get("status")
            bad = []
            if rows is not None and rows != len(points):
                bad.append("sweep.csv has %d rows for %d point dirs" % (rows, len(points)))
            if st != "interrupted":
                bad.append("status.json says %r" % st)
            if bad and cls == "handled":
                cls = "wrong"
            note = "; ".join(bad + ["%d points published" % len(points)]) + ". " + note
        return cls, code, note
    add("Ctrl-C in a sweep of 300 zero-iteration points", f8)


def issue_drawing(F):
    """Ctrl-C while PNGs are drawn (from the issue)."""
    base, add = F.base, F.add

    # A run with PNGs, redrawn by gfmd plot (Ctrl-C), then re-run with another load (Ctrl-C).
    png_dir = F.path("drawn")


    def f10(d):
        F.base_run(png_dir, "--set", "output.png=true")
        before = snapshot(png_dir)
        t_ns = time.time_ns()
        r, sent = F.interrupt(["plot", png_dir], signal.SIGINT, lambda: pngs_newer(png_dir, t_ns))
        # PNGs may be partly redrawn from the same data; the data must not change.
        return F.interrupted_verdict(r, sent, png_dir, "the drawing", staging_ok=False, before=before,
                                   ignore={n for n in before if n.endswith(".png")})
    add("Ctrl-C while `gfmd plot` draws", f10)

    def f11(d):
        if not os.path.exists(os.path.join(png_dir, "summary.json")):
            F.base_run(png_dir, "--set", "output.png=true")
        before = snapshot(png_dir)
        t_ns = time.time_ns()
        r, sent = F.interrupt(["run", base, "-o", png_dir, "-q", "--set", "output.png=true",
                               "--set", "load.force=0.02"], signal.SIGINT, lambda: pngs_newer(png_dir, t_ns))
        cls, code, note = F.interrupted_verdict(r, sent, png_dir, "the drawing", staging_ok=True, before=before)
        if sent and r.rc == 4 and cls == "handled" and not has_fragment(r.err, "kept unchanged"):
            cls, note = "wrong", "no 'kept unchanged' on stderr. " + note
        return cls, code, note
    add("Ctrl-C while `gfmd run` draws (re-run over a result with PNGs)", f11)


def sweep_term(F):
    """SIGTERM in a sweep over a previous sweep."""
    base, add = F.base, F.add

    def sweep_term(d):
        before = F.base_sweep(d, "0.005,0.01,0.02")
        t0 = time.monotonic()
        r, sent = F.interrupt(["sweep", base, "-o", d, "-q"] + SWEEP0, signal.SIGTERM,
                              lambda: time.monotonic() - t0 > 2.0, group=False)
        cls, code, note = F.interrupted_verdict(r, sent, d, "the sweep", before=before)
        new_points = [p for p in added(before, snapshot(d), ignore={".gfmd-staging", "status.json"})
                      if os.sep not in p]
        if new_points and cls != "crashed":
            cls, note = "data lost or mixed", "new entries beside the previous sweep: %s. %s" % (
                ", ".join(new_points[:4]), note)
        if sent and r.rc == 4 and cls == "handled" and not has_fragment(r.err, "kept unchanged"):
            cls, note = "wrong", "no 'kept unchanged' on stderr. " + note
        return cls, code, note
    add("SIGTERM (kill PID) a 300-point sweep over a previous sweep", sweep_term)


def more_interrupts(F):
    """More interruptions (mid-solve, twice, SIGTERM to a study) and what they leave."""
    base, add = F.base, F.add

    def midsolve(d):
        F.base_run(d)
        before = snapshot(d)
        t0 = time.monotonic()
        r, sent = F.interrupt(["run", base, "-o", d, "-q", "--set", "load.force=0.02"] + LONG, signal.SIGINT,
                              lambda: time.monotonic() - t0 > 2.0)
        cls, code, note = F.interrupted_verdict(r, sent, d, "the solve", staging_ok=True, before=before)
        if sent and r.rc == 4 and cls == "handled" and not has_fragment(r.err, "kept unchanged"):
            cls, note = "wrong", "no 'kept unchanged' on stderr. " + note
        return cls, code, note
    add("Ctrl-C mid-solve of a re-run over a converged result", midsolve)

    def double_ctrl_c(d):
        F.base_run(d, "--set", "output.png=true")
        before = snapshot(d)
        t_ns = time.time_ns()
        r, sent = F.interrupt(["run", base, "-o", d, "-q", "--set", "output.png=true", "--set", "load.force=0.03"],
                              signal.SIGINT, lambda: pngs_newer(d, t_ns), again=0.3)
        return F.interrupted_verdict(r, sent, d, "the drawing", staging_ok=True, before=before)
    add("Ctrl-C twice (0.3 s apart) while `gfmd run` draws", double_ctrl_c)

    def study_term(d):
        if not os.path.exists(STUDY_SMALL):
            return "not tried", "-", STUDY_SMALL + " not found"
        t0 = time.monotonic()
        r, sent = F.interrupt(["study", STUDY_SMALL, "--quick", "-o", d, "--set", "grid.nx=128",
                               "--set", "sweep.from=5e-3"], signal.SIGTERM,
                              lambda: time.monotonic() - t0 > 4.0, group=False)
        return F.interrupted_verdict(r, sent, d, "the study")
    add("SIGTERM (kill PID) to `gfmd study` mid-run", study_term)

    interrupted_dir = F.path("interrupted_only")

    def make_interrupted():
        if not os.path.isdir(interrupted_dir):
            t0 = time.monotonic()
            F.interrupt(["run", base, "-o", interrupted_dir, "-q"] + LONG, signal.SIGINT,
                        lambda: time.monotonic() - t0 > 1.5)

    def plot_interrupted(d):
        make_interrupted()
        return F.expect_refusal(["plot", interrupted_dir], ["interrupted_only"], watch=[interrupted_dir])
    add("`gfmd plot` on a dir whose only run was interrupted", plot_interrupted)

    def flow_interrupted(d):
        make_interrupted()
        return F.expect_refusal(["flow", interrupted_dir], ["interrupted_only"], watch=[interrupted_dir])
    add("`gfmd flow` on a dir whose only run was interrupted", flow_interrupted)
