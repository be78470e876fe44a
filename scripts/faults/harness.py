"""The fault-table harness: constants, the Result of one child, and Faults, which starts gfmd
(or a Python child) in a session of its own, interrupts it, waits with a timeout, checks that
nothing outlived it, and turns what it did into an outcome class."""
import os
import signal
import subprocess
import sys
import tempfile
import time

from faults.checks import added, changed, frag_text, has_fragment, leftovers, short, snapshot


SEVERITY = {"not tried": -1, "handled": 0, "refused": 0, "wrong": 1, "crashed": 2, "data lost or mixed": 3}
CLASSES = ["refused", "handled", "wrong", "crashed", "data lost or mixed"]
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

BASE_TOML = """# a tiny sliding Hertz contact (0.1 s)
[grid]
nx = 64
lx = 4.0

[indenter]
type = "hertz"
radius = 1.0

[load]
force = 0.01

[friction]
coefficient = 0.5

[output]
png = false
"""

# A study of our own (cases relative to the folder above studies/: the scratch directory).
SMALL_STUDY = """title = "small"
kind = "sweep"
x = "load.force"
y = "friction_coefficient"
xlabel = "F"
ylabel = "mu"

[[series]]
label = "base"
case = "sweep_case.toml"

[quick]
set = ["output.png=false"]

[full]
set = ["output.png=false"]
"""
SWEEP_CASE = BASE_TOML + """
[sweep]
parameter = "load.force"
values = [0.005, 0.01, 0.02]
"""

# A solve that lasts (20000 iterations at 128^2, ~10-25 s) so that it can be interrupted.
LONG = ["--set", "grid.nx=128", "--set", "solver.tolerance=1e-16"]
NO_FILES = ["--set", "output.fields=false", "--set", "output.analysis=false"]
# Names gfmd writes into a run directory (used to clean up after a binary that wrote into /).
GFMD_NAMES = {".gfmd.lock", ".gfmd-staging", "summary.json", "status.json", "fields.nc", "flow.json",
              "flow.nc", "profiles.csv", "patches.csv", "distributions.csv", "spectrum.csv", "bands.csv",
              "analysis.png", "profiles.png", "pressure.png", "gap.png", "slip_longitudinal.png",
              "slip_transverse.png", "dissipation.png", "max_principal_stress.png", "von_mises.png",
              "checkpoint.bin", ".maps.tmp.nc"}

# A sweep of 300 zero-iteration points (lasts long enough to be interrupted).
APPROACH_LIST = ",".join("%g" % (i * 1e-9) for i in range(300))
SWEEP0 = ["--set", "friction.coefficient=0"] + NO_FILES + ["--set", "load.approach=" + APPROACH_LIST]
# The shortest shipped study (interrupted, and refused with a typo).
STUDY_SMALL = os.path.join(REPO, "studies", "fig2b.toml")


class Result:
    def __init__(self, rc, out, err, timed_out, secs):
        self.rc, self.out, self.err, self.timed_out, self.secs = rc, out, err, timed_out, secs
        self.orphans = ""

    @property
    def text(self):
        return self.out + self.err

    def code(self):
        if self.timed_out:
            return "timeout"
        if self.rc is None:
            return "-"
        if self.rc < 0:
            try:
                return "sig " + signal.Signals(-self.rc).name
            except ValueError:
                return "sig %d" % -self.rc
        return str(self.rc)



class Faults:
    def __init__(self, gfmd, pkg, timeout):
        self.gfmd = os.path.abspath(gfmd)
        self.pkg = os.path.abspath(pkg) if pkg else None
        self.timeout = timeout
        self.tmp = tempfile.mkdtemp(prefix="gfmd-faults-")
        self.env = dict(os.environ, OMP_WAIT_POLICY="PASSIVE")
        self.env.pop("GFMD_PYTHON", None)
        self.home = self.path("home")
        os.makedirs(self.home)
        with open(os.path.join(self.home, "thesis.tex"), "w") as f:
            f.write("my thesis\n")
        self.env["HOME"] = self.home  # -o $HOME is tried against this one, never the real one
        self.rows = []
        self.base = self.write("base.toml", BASE_TOML)
        self.n = 0
        self.is_root = hasattr(os, "geteuid") and os.geteuid() == 0
        self.active = set()  # process groups started and not yet waited for

    def stop_all(self):
        """Kills what is still running (this script was interrupted)."""
        for pgid in list(self.active):
            try:
                os.killpg(pgid, signal.SIGKILL)
            except OSError:
                pass
        self.active.clear()

    @staticmethod
    def signal_group(p, sig):
        try:
            os.killpg(p.pid, sig)
        except OSError:
            pass

    def path(self, *parts):
        return os.path.join(self.tmp, *parts)

    def write(self, rel, text, mode="w"):
        p = self.path(rel)
        os.makedirs(os.path.dirname(p), exist_ok=True)
        with open(p, mode) as f:
            f.write(text)
        return p

    # -- children
    def run(self, args, cwd=None, timeout=None, env=None, preexec=None):
        """Runs gfmd (args without the program) or, if args[0] is a list, that command."""
        return self.finish(self.start(args, cwd=cwd, env=env, preexec=preexec), timeout=timeout)

    @staticmethod
    def reap(pgid, grace=5.0):
        """'' if no process of the child's group outlived it (after grace seconds), else a note
        (and they are killed)."""
        t0 = time.monotonic()
        while True:
            try:
                os.killpg(pgid, 0)
            except OSError:
                return ""
            if time.monotonic() - t0 > grace:
                break
            time.sleep(0.1)
        try:
            os.killpg(pgid, signal.SIGKILL)
        except OSError:
            pass
        return "processes it started still ran %.0f s after it ended (killed)" % grace

    def _kill_group(self, p):
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except OSError:
            pass
        p.wait()

    def _result(self, p, out_f, err_f, timed_out, t0):
        out_f.seek(0)
        err_f.seek(0)
        out = out_f.read().decode("utf-8", "replace")
        err = err_f.read().decode("utf-8", "replace")
        out_f.close()
        err_f.close()
        return Result(p.returncode, out, err, timed_out, time.monotonic() - t0)

    def start(self, args, cwd=None, env=None, preexec=None):
        """Starts gfmd (args without the program) or, if args[0] is a list, that command, in a
        session of its own; finish() waits for it."""
        cmd = args[0] if args and isinstance(args[0], list) else [self.gfmd] + list(args)
        out_f = tempfile.TemporaryFile(dir=self.tmp)
        err_f = tempfile.TemporaryFile(dir=self.tmp)
        p = subprocess.Popen(cmd, cwd=cwd or self.tmp, env=env or self.env, stdin=subprocess.DEVNULL,
                             stdout=out_f, stderr=err_f, start_new_session=True, preexec_fn=preexec)
        p._fault_files = (out_f, err_f, time.monotonic())
        self.active.add(p.pid)
        return p

    def finish(self, p, timeout=None):
        out_f, err_f, t0 = p._fault_files
        timed_out = False
        try:
            p.wait(timeout=timeout or self.timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            self._kill_group(p)
        orphans = self.reap(p.pid)
        self.active.discard(p.pid)
        r = self._result(p, out_f, err_f, timed_out, t0)
        r.orphans = orphans
        return r

    def interrupt(self, args, sig, ready, group=True, cwd=None, max_wait=30.0, delay=0.0, again=None,
                  stop_within=20.0):
        """Starts gfmd, waits until ready() (polled) or max_wait seconds, waits delay more, sends
        sig (to the process group for a Ctrl-C, else to the process) and waits for the end.
        Returns (Result, sent): sent is False when the process had ended first. A process that
        has not ended stop_within seconds after the signal is killed (Result.timed_out)."""
        p = self.start(args, cwd=cwd)
        t0 = time.monotonic()
        while p.poll() is None and time.monotonic() - t0 < max_wait:
            if ready():
                break
            time.sleep(0.05)
        if delay and p.poll() is None:
            time.sleep(delay)
        sent = False
        for attempt in range(2 if again is not None else 1):
            if attempt:
                if not sent:
                    break
                time.sleep(again)
            if p.poll() is None and (attempt or ready()):
                try:
                    if group:
                        os.killpg(p.pid, sig)
                    else:
                        os.kill(p.pid, sig)
                    sent = True
                except OSError:
                    pass
        r = self.finish(p, timeout=stop_within if sent else None)
        if sent and r.timed_out:
            r.orphans = ("did not stop within %.0f s of the signal. " % stop_within) + r.orphans
        return r, sent

    # -- verdicts
    def verdict(self, r, expect, frags=(), lost=(), wrong=(), note=""):
        """expect: {exit code: 'refused'|'handled'}; frags must all be in stderr (for a refusal,
        or for any expected code when listed); lost: data problems; wrong: failed checks."""
        notes = []
        if lost:
            cls = "data lost or mixed"
            notes.append("; ".join(lost[:4]) + (" (+%d more)" % (len(lost) - 4) if len(lost) > 4 else ""))
        elif r.timed_out:
            cls = "crashed"
            notes.append("hung: killed after %.0f s" % r.secs)
        elif r.rc is not None and r.rc < 0:
            cls = "crashed"
            notes.append("killed by " + r.code())
        elif "Traceback (most recent call last)" in r.text:
            cls = "crashed"
            notes.append("Python traceback: " + short(r.text.split("Traceback (most recent call last)")[1][-200:], 100))
        elif r.rc not in expect:
            cls = "crashed"
            notes.append("unexpected exit %s (expected %s)" % (r.rc, "/".join(str(k) for k in sorted(expect))))
        else:
            cls = expect[r.rc]
            missing = [f for f in frags if not has_fragment(r.err, f)]
            if missing:
                cls = "wrong"
                notes.append("stderr does not name " + ", ".join(frag_text(f) for f in missing))
            if wrong:
                cls = "wrong"
                notes.extend(wrong)
        if getattr(r, "orphans", ""):
            if cls in ("handled", "refused"):
                cls = "wrong"
            notes.append(r.orphans)
        if note:
            notes.append(note)
        msg = self.excerpt(r.err or r.out, frags)
        if msg and (cls != "handled" or not notes or r.rc != 0):
            notes.append("says: " + msg)
        return cls, r.code(), " — ".join(n for n in notes if n)

    def excerpt(self, text, frags=(), n=150):
        """The message line that names the first fragment (else the first lines), the scratch
        directory written $T."""
        text = text.replace(self.tmp, "$T")
        lines = [l.strip() for l in text.splitlines() if l.strip()]
        for f in frags:
            hit = [l for l in lines if has_fragment(l, f)]
            if hit:
                return short(hit[0], n)
        return short(text, n)

    def add(self, what, fn):
        self.n += 1
        fid = str(self.n)
        t0 = time.monotonic()
        try:
            cls, code, note = fn(self.path("f%02d" % self.n))
        except Exception as e:  # a fault in this script, not in gfmd: shown, not hidden
            cls, code, note = "not tried", "-", "fault_table error: %s: %s" % (type(e).__name__, e)
        self.rows.append((fid, what, code, cls, note))
        sys.stderr.write("[%s] %-60s %-8s %-18s %5.1fs\n" % (fid, what[:60], code, cls, time.monotonic() - t0))
        sys.stderr.flush()

    # -- helpers for faults
    def base_run(self, out, *extra):
        r = self.run(["run", self.base, "-o", out, "-q"] + list(extra))
        if r.rc != 0 or not os.path.exists(os.path.join(out, "summary.json")):
            raise RuntimeError("the baseline run into %s failed (exit %s): %s" % (out, r.rc, short(r.err, 200)))
        return r

    def expect_refusal(self, args, frags, cwd=None, watch=(), timeout=None, expect=None, new_dir=None):
        """A command that must be refused (exit 2 naming frags): the paths in watch must not change,
        new_dir must not be created."""
        before = {w: snapshot(w) for w in watch}
        r = self.run(args, cwd=cwd, timeout=timeout)
        lost = []
        for w in watch:
            after = snapshot(w)
            lost += [x + " in " + os.path.basename(w) for x in changed(before[w], after)]
            lost += ["wrote " + x + " into " + os.path.basename(w) for x in added(before[w], after)]
        if new_dir and os.path.exists(new_dir) and r.rc != 0:
            left = snapshot(new_dir)
            if left:
                lost.append("left %s/ with %s" % (os.path.basename(new_dir), ", ".join(sorted(left)[:3])))
        return self.verdict(r, expect or {2: "refused"}, frags, lost)

    def base_sweep(self, out, forces="0.005,0.01"):
        """A finished sweep over load.force into out (the result a later fault must keep); its snapshot."""
        r0 = self.run(["sweep", self.base, "-o", out, "-q", "--set", "load.force=" + forces])
        if r0.rc != 0:
            raise RuntimeError("baseline sweep failed: " + short(r0.err))
        return snapshot(out)

    def interrupted_verdict(self, r, sent, d, what, staging_ok=True, before=None, ignore=()):
        """The verdict on an interrupt() (sent: whether the signal went out): exit 4 naming the
        interruption, no leftovers, and before (a snapshot of d) kept, but for ignore."""
        lost = leftovers(d, staging_ok=staging_ok)
        if before is not None:
            lost += changed(before, snapshot(d), ignore=set(ignore) | {"status.json", ".gfmd.lock",
                                                                        ".gfmd-staging", "checkpoint.bin"})
        if not sent:
            if lost:
                return self.verdict(r, {}, [], lost)
            cls, code, note = self.verdict(r, {0: "handled", 3: "handled", 4: "handled"}, [])
            return cls, code, "INCONCLUSIVE: ended before %s could be interrupted (%.1f s). %s" % (what, r.secs, note)
        wrong = []
        if r.rc == 4 and not has_fragment(r.err, "interrupt"):
            wrong.append("no 'interrupted' on stderr")
        if r.rc == 0:
            # The signal came while it was still running: ignoring it is a bug.
            return self.verdict(r, {4: "handled"}, [], lost, [], "the signal was ignored (ran to the end in %.1f s)" % r.secs)
        return self.verdict(r, {4: "handled"}, [], lost, wrong)
