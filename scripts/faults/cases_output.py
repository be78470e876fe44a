"""Faults about output directories: where -o points, what a failed, concurrent or re-run leaves there.

Each function adds its faults in the order of the table (ids are positions); fault_table.py
calls them in that order."""
import os
import resource
import shutil
import signal
import time

from faults.checks import added, changed, has_fragment, leftovers, read_json, snapshot
from faults.harness import GFMD_NAMES, LONG


def issue_outputs(F):
    """-o at a user's directory, /, ., $HOME; a failing re-run (from the issue)."""
    base, add = F.base, F.add

    def f1(d):
        os.makedirs(d)
        out = os.path.join(d, "mydata")
        os.makedirs(out)
        with open(os.path.join(out, "spectrum.csv"), "w") as f:
            f.write("mine\n")
        return F.expect_refusal(["run", base, "-o", out, "--set", "solver.max_iterations=2"],
                                ["mydata", "--force"], watch=[out])
    add("-o DIR holding the user's spectrum.csv (max_iterations=2)", f1)

    def root_test(d, extra, target="/"):
        """-o / with a run that cannot converge (the least a binary that does not refuse / writes)."""
        present = GFMD_NAMES & set(os.listdir("/"))
        if present:
            return "not tried", "-", "/ already holds %s: not safe to try" % ", ".join(sorted(present))
        before = set(os.listdir("/"))
        r = F.run(["run", base, "-o", target, "--set", "solver.max_iterations=2"] + extra)
        new = sorted(set(os.listdir("/")) - before)
        for name in new:  # remove only what this run created, and only gfmd's names
            if name in GFMD_NAMES or ".tmp" in name:
                p = os.path.join("/", name)
                shutil.rmtree(p) if os.path.isdir(p) and not os.path.islink(p) else os.remove(p)
        lost = ["wrote " + ", ".join(new) + " into / (removed again)"] if new else []
        return F.verdict(r, {2: "refused"}, ["root directory"], lost)
    add("-o / (max_iterations=2)", lambda d: root_test(d, []))
    add("-o / --force", lambda d: root_test(d, ["--force"]))

    def root_link(d):
        os.makedirs(d)
        os.symlink("/", os.path.join(d, "rootlink"))
        return root_test(d, ["--force"], os.path.join(d, "rootlink"))
    add("-o a symlink to / (--force)", root_link)

    def cwd_test(d, extra, target="."):
        os.makedirs(os.path.join(d, "sub"))
        shutil.copy(base, os.path.join(d, "case.toml"))
        F.write(os.path.join(d, "notes.txt"), "my notes\n")
        return F.expect_refusal(["run", "case.toml", "-o", target, "-q"] + extra,
                                [("working directory", "current directory")], cwd=d, watch=[d])
    add("-o . (the working directory, holding the case)", lambda d: cwd_test(d, []))
    add("-o . --force", lambda d: cwd_test(d, ["--force"]))
    add("-o sub/.. --force (the working directory, spelled otherwise)", lambda d: cwd_test(d, ["--force"], "sub/.."))

    def home_test(d, extra):
        return F.expect_refusal(["run", base, "-o", F.home, "-q"] + extra, ["home directory"], watch=[F.home])
    add("-o $HOME (HOME set to a scratch dir with a user file)", lambda d: home_test(d, []))
    add("-o $HOME --force", lambda d: home_test(d, ["--force"]))

    def f4(d):
        F.base_run(d)
        before = snapshot(d)
        r = F.run(["run", base, "-o", d, "-q", "--set", "solver.max_iterations=2"])
        after = snapshot(d)
        lost = changed(before, after, ignore={"status.json", ".gfmd.lock"}) + leftovers(d)
        wrong = [] if has_fragment(r.err, "kept unchanged") else ["no 'kept unchanged' on stderr"]
        st = read_json(os.path.join(d, "status.json")) or {}
        if r.rc == 3 and (st.get("status") != "failed" or "kept unchanged" not in str(st.get("result", ""))):
            wrong.append("status.json: status %r, result %r" % (st.get("status"), st.get("result")))
        return F.verdict(r, {3: "handled"}, [], lost, wrong)
    add("re-run that fails (max_iterations=2) over a converged result", f4)


def output_targets(F):
    """-o at a file, /dev/null, /proc, "", the case's directory; --force; odd names."""
    base, add = F.base, F.add

    def o_file(d):
        os.makedirs(d)
        p = os.path.join(d, "results.txt")
        F.write(p, "my results\n")
        return F.expect_refusal(["run", base, "-o", p], ["results.txt"], watch=[d])
    add("-o pointing at an existing file", o_file)

    add("-o /dev/null", lambda d: F.expect_refusal(["run", base, "-o", "/dev/null", "-q"], ["/dev/null"]))

    def o_readonly(d):
        target = "/proc/gfmd-fault-out"
        r = F.run(["run", base, "-o", target, "-q"])
        note = "as root no chmod makes a path read-only; /proc refuses new entries instead"
        return F.verdict(r, {1: "refused", 2: "refused"}, ["gfmd-fault-out"], [], note=note)
    add("-o inside a path that cannot be written (/proc/…)", o_readonly)

    add("-o \"\" (empty)", lambda d: F.expect_refusal(["run", base, "-o", ""], [("output", "-o", "empty")]))

    def o_casedir(d):
        os.makedirs(d)
        p = os.path.join(d, "case.toml")
        shutil.copy(base, p)
        F.write(os.path.join(d, "notes.txt"), "mine\n")
        return F.expect_refusal(["run", p, "-o", d], ["--force"], watch=[d])
    add("-o the directory that holds the case file", o_casedir)

    def force_foreign(d):
        os.makedirs(d)
        F.write(os.path.join(d, "notes.txt"), "mine\n")
        before = snapshot(d)
        r = F.run(["run", base, "-o", d, "-q", "--force"])
        lost = changed(before, snapshot(d)) + leftovers(d)
        wrong = [] if r.rc != 0 or os.path.exists(os.path.join(d, "summary.json")) else ["no summary.json"]
        return F.verdict(r, {0: "handled"}, [], lost, wrong)
    add("--force into a foreign dir with notes.txt (must survive)", force_foreign)

    def odd_name(d):
        out = os.path.join(d, "my results ü (1)")
        r = F.run(["run", base, "-o", out, "-q"])
        wrong = [] if r.rc != 0 or os.path.exists(os.path.join(out, "summary.json")) else ["no summary.json"]
        return F.verdict(r, {0: "handled"}, [], leftovers(out), wrong)
    add("-o a name with spaces, parentheses and ü", odd_name)


def shared_dirs(F):
    """Two runs into one directory; --resume."""
    base, add = F.base, F.add

    def concurrent(d, wait):
        p = F.start(["run", base, "-o", d, "-q"] + LONG)
        t0 = time.monotonic()
        while p.poll() is None and time.monotonic() - t0 < 10 and not os.path.exists(os.path.join(d, ".gfmd.lock")):
            time.sleep(0.05)
        time.sleep(0.5)
        if p.poll() is not None:
            ra = F.finish(p)
            return "handled", ra.code(), "INCONCLUSIVE: the first run ended in %.1f s" % ra.secs
        if not wait:
            rb = F.run(["run", base, "-o", d, "-q"], timeout=30)
            F.signal_group(p, signal.SIGINT)
            ra = F.finish(p, timeout=60)
            lost = leftovers(d, staging_ok=True)
            note = "first run: exit %s" % ra.code()
            if ra.rc not in (4,):
                note += " (expected 4 after Ctrl-C)"
            return F.verdict(rb, {2: "refused"}, [("another", "lock", "busy", "in use")], lost, note=note)
        b = F.start(["run", base, "-o", d, "-q", "--wait"])
        time.sleep(1.5)
        b_waited = b.poll() is None
        F.signal_group(p, signal.SIGINT)
        ra = F.finish(p, timeout=60)
        rb = F.finish(b, timeout=60)
        wrong = [] if b_waited else ["the --wait run did not wait (ended while the first ran)"]
        if rb.rc == 0 and not os.path.exists(os.path.join(d, "summary.json")):
            wrong.append("no summary.json after the waiting run")
        return F.verdict(rb, {0: "handled"}, [], leftovers(d), wrong,
                         "first run: exit %s; the second waited and then ran" % ra.code() if not wrong else "")
    add("two runs into one directory at once (second refused)", lambda d: concurrent(d, False))
    add("two runs into one directory, second with --wait", lambda d: concurrent(d, True))

    def resume_none(d):
        r = F.run(["run", base, "-o", d, "-q", "--resume"])
        wrong = []
        if r.rc == 0 and not os.path.exists(os.path.join(d, "summary.json")):
            wrong.append("exit 0 but no summary.json")
        return F.verdict(r, {0: "handled", 2: "refused"}, ["checkpoint"] if r.rc == 2 else [], leftovers(d), wrong)
    add("--resume with no checkpoint (new directory)", resume_none)

    def resume_changed(d):
        t0 = time.monotonic()
        r1, sent = F.interrupt(["run", base, "-o", d, "-q", "--checkpoint-interval", "0.5"] + LONG, signal.SIGINT,
                               lambda: time.monotonic() - t0 > 2.5)
        if not sent:
            return "handled", r1.code(), "INCONCLUSIVE: the first run ended before Ctrl-C (%.1f s)" % r1.secs
        r = F.run(["run", base, "-o", d, "-q", "--resume", "--set", "grid.nx=128",
                   "--set", "load.force=0.02"])
        s = read_json(os.path.join(d, "summary.json")) or {}
        lost = leftovers(d, staging_ok=(r.rc != 0))
        if r.rc == 0 and abs(float(s.get("normal_force", 0)) - 0.02) > 1e-6:
            lost.append("resumed the old case: normal_force %s, asked 0.02" % s.get("normal_force"))
        note = "first run (Ctrl-C): exit %s" % r1.code()
        return F.verdict(r, {0: "handled", 2: "refused"}, [("checkpoint", "changed", "differ")] if r.rc == 2 else [],
                         lost, note=note + ("; solved the new case afresh" if r.rc == 0 and not lost else ""))
    add("--resume after a changed input (load.force, tolerance)", resume_changed)


def reruns(F):
    """Re-runs over finished results and sweeps."""
    base, add = F.base, F.add

    def resume_done(d):
        F.base_run(d)
        before = snapshot(d)
        r = F.run(["run", base, "-o", d, "-q", "--resume"])
        lost = changed(before, snapshot(d), ignore={"status.json", ".gfmd.lock"}) + leftovers(d)
        return F.verdict(r, {0: "handled"}, [], lost)
    add("--resume on a directory that holds the converged result", resume_done)

    def sweep_fail_over(d):
        before = F.base_sweep(d)
        r = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01", "--set", "solver.max_iterations=2"])
        after = snapshot(d)
        lost = changed(before, after, ignore={"status.json", ".gfmd.lock", ".gfmd-staging"}) + leftovers(d, staging_ok=True)
        lost += ["new " + x for x in added(before, after, ignore={"status.json", ".gfmd-staging"}) if os.sep not in x]
        wrong = [] if has_fragment(r.err, "kept unchanged") else ["no 'kept unchanged' on stderr"]
        staging = os.path.join(d, ".gfmd-staging")
        note = ""
        if os.path.isdir(staging):
            if os.listdir(staging):
                note = ".gfmd-staging kept with %s (README: a failed sweep keeps its finished points)" % \
                    ", ".join(sorted(os.listdir(staging))[:3])
            else:
                wrong.append("an empty .gfmd-staging/ left (no point had finished)")
        st = (read_json(os.path.join(d, "status.json")) or {}).get("status")
        if r.rc == 3 and st != "failed":
            wrong.append("status.json says %r, not 'failed'" % st)
        return F.verdict(r, {3: "handled"}, [], lost, wrong, note)
    add("sweep that fails (max_iterations=2) over a finished sweep", sweep_fail_over)

    def sweep_shrink(d):
        F.base_sweep(d, "0.005,0.01,0.015,0.02")
        r = F.run(["sweep", base, "-o", d, "-q", "--set", "elastic.poisson=0.2,0.3"])
        points = sorted(x for x in os.listdir(d) if x.startswith("point_")) if os.path.isdir(d) else []
        stale = []
        try:
            with open(os.path.join(d, "sweep.csv")) as f:
                if not f.readline().startswith("elastic.poisson"):
                    stale.append("sweep.csv")
        except OSError:
            pass
        lost = leftovers(d)
        if r.rc == 0 and len(points) != 2:
            lost.append("%d point dirs after a 2-point sweep: %s" % (len(points), ", ".join(points)))
        if r.rc == 0 and stale:
            lost.append("the previous sweep's " + ", ".join(stale) + " left")
        return F.verdict(r, {0: "handled"}, [], lost)
    add("2-point sweep of another key over a 4-point sweep", sweep_shrink)

    def run_over_sweep(d):
        before = F.base_sweep(d)
        r = F.run(["run", base, "-o", d, "-q"])
        names = set(os.listdir(d))
        lost = leftovers(d)
        if r.rc == 0 and "summary.json" in names and ("sweep.json" in names or "sweep.csv" in names):
            lost.append("a run's summary.json beside the earlier sweep's sweep.json/csv and point_*")
        if r.rc == 2:
            lost += changed(before, snapshot(d), ignore={".gfmd.lock"})
        return F.verdict(r, {0: "handled", 2: "refused"}, [os.path.basename(d)] if r.rc == 2 else [], lost)
    add("`gfmd run -o DIR` where DIR holds a sweep", run_over_sweep)

    def png_stale(d):
        F.base_run(d, "--set", "output.png=true")
        r = F.run(["run", base, "-o", d, "-q", "--set", "load.force=0.015"])
        pngs = sorted(x for x in os.listdir(d) if x.endswith(".png"))
        lost = leftovers(d)
        if r.rc == 0 and pngs:
            lost.append("the previous run's %s left beside the new summary.json" % ", ".join(pngs[:3]) +
                        (" (+%d)" % (len(pngs) - 3) if len(pngs) > 3 else ""))
        return F.verdict(r, {0: "handled"}, [], lost)
    add("re-run with output.png=false over a result with PNGs", png_stale)

    def plot_nofields(d):
        F.base_run(d, "--set", "output.fields=false")
        before = snapshot(d)
        r = F.run(["plot", d])
        lost = changed(before, snapshot(d), ignore={".gfmd.lock", "status.json"}) + leftovers(d)
        return F.verdict(r, {0: "handled", 2: "refused"}, [("fields",)] if r.rc == 2 else [], lost)
    add("`gfmd plot` on a run made with output.fields=false", plot_nofields)


def environment(F):
    """No Python for the figures; a write that fails."""
    base, add = F.base, F.add

    def no_python(d):
        env = dict(F.env, GFMD_PYTHON=F.path("no_such_python"))
        r = F.run(["run", base, "-o", d, "-q", "--set", "output.png=true"], env=env)
        wrong = []
        if r.rc == 0 and not os.path.exists(os.path.join(d, "summary.json")):
            wrong.append("no summary.json")
        if r.rc == 0 and not has_fragment(r.err, "warning"):
            wrong.append("no warning that the figures were not drawn")
        return F.verdict(r, {0: "handled"}, [], leftovers(d), wrong)
    add("PNGs asked for with GFMD_PYTHON naming no interpreter", no_python)

    def disk_full(d):
        F.base_run(d)
        before = snapshot(d)
        limit = 100 * 1024

        def cap():
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
        r = F.run(["run", base, "-o", d, "-q", "--set", "load.force=0.02"], preexec=cap)
        after = snapshot(d)
        lost = changed(before, after, ignore={"status.json", ".gfmd.lock"}) + leftovers(d)
        return F.verdict(r, {1: "handled"}, [(".nc", ".csv", ".json", "File too large", "write")], lost,
                         note="files limited to 100 kB (ulimit -f) as a full disk")
    add("a write fails (ulimit -f 100 kB) in a re-run over a result", disk_full)
