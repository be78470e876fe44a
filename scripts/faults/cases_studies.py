"""Faults with `gfmd study`: interrupted, missing or malformed studies.

Each function adds its faults in the order of the table (ids are positions); fault_table.py
calls them in that order."""
import os
import signal
import time

from faults.harness import SMALL_STUDY, STUDY_SMALL, SWEEP_CASE


def issue_studies(F):
    """Gfmd study: Ctrl-C, missing and malformed studies (from the issue)."""
    base, add = F.base, F.add

    def f12(d):
        if not os.path.exists(STUDY_SMALL):
            return "not tried", "-", STUDY_SMALL + " not found"
        t0 = time.monotonic()
        r, sent = F.interrupt(["study", STUDY_SMALL, "--quick", "-o", d, "--set", "grid.nx=128",
                               "--set", "sweep.from=5e-3"], signal.SIGINT,
                              lambda: time.monotonic() - t0 > 5.0 or
                              (os.path.isdir(d) and time.monotonic() - t0 > 3.0))
        return F.interrupted_verdict(r, sent, d, "the study")
    add("Ctrl-C in `gfmd study studies/fig2b.toml --quick`", f12)

    add("`gfmd study` on a missing file",
        lambda d: F.expect_refusal(["study", F.path("nothere.toml"), "--quick", "-o", d],
                                   ["nothere.toml"], new_dir=d))

    def f13b(d):
        p = F.write("bad_study.toml", 'title = "broken\nkind = "runs"\n[[series]\ncase = 3\n')
        return F.expect_refusal(["study", p, "--quick", "-o", d], ["bad_study.toml"], new_dir=d)
    add("`gfmd study` on a malformed study (broken TOML)", f13b)

    add("`gfmd study` on a case file (base.toml)",
        lambda d: F.expect_refusal(["study", base, "--quick", "-o", d], ["base.toml"], new_dir=d))

    def f13d(d):
        p = F.write("studies/missing_case.toml", SMALL_STUDY.replace("sweep_case.toml", "none_such.toml"))
        return F.expect_refusal(["study", p, "--quick", "-o", d], [("none_such.toml", "missing_case.toml")],
                                new_dir=d)
    add("`gfmd study` whose series names a missing case", f13d)

    def f13e(d):
        p = F.write("studies/bad_kind.toml", SMALL_STUDY.replace('kind = "sweep"', 'kind = "sweeps"'))
        return F.expect_refusal(["study", p, "--quick", "-o", d], ["kind"], new_dir=d)
    add("`gfmd study` with kind = \"sweeps\" (valid TOML, wrong value)", f13e)

    def f12b(d):
        p = F.write("studies/small.toml", SMALL_STUDY)
        F.write("sweep_case.toml", SWEEP_CASE)
        done = lambda: os.path.exists(os.path.join(d, "small", "quick", "series_00", "sweep.json"))
        r, sent = F.interrupt(["study", p, "--quick", "-o", d], signal.SIGINT, done, max_wait=60)
        figs = [f for f in os.listdir(os.path.join(d, "small", "quick")) if f.startswith("small.")] \
            if os.path.isdir(os.path.join(d, "small", "quick")) else []
        cls, code, note = F.interrupted_verdict(r, sent, d, "the figure")
        if sent and r.rc == 4 and figs:
            note = "figure files present: %s. %s" % (", ".join(sorted(figs)), note)
        return cls, code, note
    add("Ctrl-C while `gfmd study` draws its figure (own 3-point study)", f12b)


def study_bad_set(F):
    """A typo in a study's --set."""
    add = F.add

    def study_bad_set(d):
        if not os.path.exists(STUDY_SMALL):
            return "not tried", "-", STUDY_SMALL + " not found"
        return F.expect_refusal(["study", STUDY_SMALL, "--quick", "-o", d, "--set", "grid.nxx=64"], ["nxx"],
                                timeout=60)
    add("`gfmd study --set grid.nxx=64` (typo for every run)", study_bad_set)
