#!/usr/bin/python3
"""Tries the faults a careless user makes against a gfmd binary and prints a Markdown table:
one row per fault (id, what was tried, exit code, outcome class, note) and a totals row.

    /usr/bin/python3 scripts/fault_table.py --gfmd build/gfmd [--python-pkg build/python] [--keep DIR]

Everything happens in a fresh temporary directory (removed at the end; --keep DIR copies it to
a new DIR first). Children are started from argument lists (no shell), each with a timeout,
in a session of their own (a "Ctrl-C" is SIGINT to that process group, as a terminal sends
it; a "SIGTERM" goes to the gfmd process alone, as `kill PID` does), with
OMP_WAIT_POLICY=PASSIVE. Grids are tiny (64^2, 128^2 for the runs that must last); PNGs are
drawn only where drawing is the point. About 2-4 minutes on 2 cores.

Outcome classes (the worst one is reported):
  refused            exit 2 and stderr names the key, option, file or directory at fault
  handled            the documented behaviour (exit 0 with the right result, 3 for a solve that
                     cannot converge, 4 for an interruption), no traceback
  wrong              the expected exit code, but the message or result is not the documented
                     one (e.g. exit 2 without naming the key, -q printing, no warning)
  crashed            killed by a signal, a Python Traceback, a hang (timeout) or an unexpected
                     exit code
  data lost or mixed a user file changed/deleted, a previous complete result changed by a failed
                     or interrupted run, *.tmp* / .maps.tmp.nc left, .gfmd-staging left after a
                     successful or failed run, outputs written into a directory that was to be
                     refused, or figures/tables of two runs in one directory
"Not interrupted in time" (the process ended before the signal could be sent while it did the
thing to interrupt) is reported as handled with a note starting INCONCLUSIVE; "not tried" rows
(a fault this machine cannot set up) are not counted. After every child the script checks that
no process of its group outlived it (else: wrong, and they are killed).

Safety: -o / is tried with a run that cannot converge (solver.max_iterations=2), only when / holds
none of gfmd's output names, and whatever a binary that does not refuse it writes there (entries
new in / with gfmd's names) is removed again; -o $HOME is tried with HOME set to a scratch
directory. --only 3,17 tries only those ids (ids are positions in the list, stable per version).

Exit status: 0 when the table was made (whatever it says), 2 for bad arguments.
"""
import argparse
import hashlib
import json
import math
import os
import random
import resource
import shutil
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import time

SEVERITY = {"not tried": -1, "handled": 0, "refused": 0, "wrong": 1, "crashed": 2, "data lost or mixed": 3}
CLASSES = ["refused", "handled", "wrong", "crashed", "data lost or mixed"]
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

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


# ---------------------------------------------------------------------------- file checks

def snapshot(path):
    """{relative path: (kind, sha1 or '', mtime_ns)} of everything under path (hidden too)."""
    snap = {}
    if not os.path.lexists(path):
        return snap
    if not os.path.isdir(path):
        return {".": ("file", _sha1(path), os.stat(path).st_mtime_ns)}
    for dirpath, dirnames, filenames in os.walk(path):
        for d in dirnames:
            full = os.path.join(dirpath, d)
            snap[os.path.relpath(full, path)] = ("dir", "", 0)
        for f in filenames:
            full = os.path.join(dirpath, f)
            try:
                st = os.lstat(full)
                digest = _sha1(full) if stat.S_ISREG(st.st_mode) else ""
                snap[os.path.relpath(full, path)] = ("file", digest, st.st_mtime_ns)
            except OSError:
                pass
    return snap


def _sha1(path):
    h = hashlib.sha1()
    try:
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
    except OSError as e:
        return "unreadable:%s" % e
    return h.hexdigest()


def _top(rel):
    return rel.split(os.sep, 1)[0]


def changed(before, after, ignore=()):
    """Files of `before` deleted or changed in `after`; names (or first path parts) in ignore
    are not compared."""
    out = []
    for rel, (kind, digest, _) in sorted(before.items()):
        if _top(rel) in ignore or os.path.basename(rel) in ignore:
            continue
        if rel not in after:
            out.append("deleted " + rel)
        elif kind == "file" and after[rel][1] != digest:
            out.append("changed " + rel)
    return out


def added(before, after, ignore=()):
    return sorted(rel for rel in after if rel not in before and _top(rel) not in ignore
                  and os.path.basename(rel) not in ignore)


def leftovers(path, staging_ok=False):
    """Temporary files (*.tmp*, .maps.tmp.nc) and, unless staging_ok, .gfmd-staging left under path."""
    bad = []
    if not os.path.isdir(path):
        return bad
    for dirpath, dirnames, filenames in os.walk(path):
        rel_dir = os.path.relpath(dirpath, path)
        for d in list(dirnames):
            if d == ".gfmd-staging":
                if not staging_ok:
                    bad.append(os.path.normpath(os.path.join(rel_dir, d)) + "/")
                dirnames.remove(d)
        for f in filenames:
            if ".tmp" in f:
                bad.append(os.path.normpath(os.path.join(rel_dir, f)))
    return bad


def has_fragment(text, frag):
    low = text.lower()
    if isinstance(frag, (tuple, list)):
        return any(f.lower() in low for f in frag)
    return frag.lower() in low


def frag_text(frag):
    return " or ".join(repr(f) for f in frag) if isinstance(frag, (tuple, list)) else repr(frag)


def short(text, n=140):
    lines = [l.strip() for l in text.strip().splitlines() if l.strip()]
    s = " / ".join(lines)
    return (s[: n - 1] + "…") if len(s) > n else s


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


# ---------------------------------------------------------------------------- the runner

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


# ---------------------------------------------------------------------------- the faults

def npy_bytes(descr, shape, raw, fortran=False):
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (descr, fortran, tuple(shape))
    pad = 64 - (10 + len(header) + 1) % 64
    header = header + " " * pad + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode("latin1") + raw


def file_case(name, path, extra_indenter="", grid="lx = 10.0\nunit = \"um\"", load="pressure = 0.01"):
    return ("[grid]\n%s\n\n[indenter]\ntype = \"file\"\npath = \"%s\"\n%s\n\n[load]\n%s\n\n"
            "[output]\npng = false\n" % (grid, path, extra_indenter, load))


def define(F):
    base = F.base
    add = F.add

    # ---------------------------------------------------------------- from the issue
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

    def f5(d):
        r = F.run(["run", base, "-o", d, "-q", "--set", "load.approach=1e6"], timeout=min(F.timeout, 20))
        lost = []
        if os.path.exists(os.path.join(d, "summary.json")):
            lost.append("summary.json written for a failed solve")
        lost += leftovers(d)
        return F.verdict(r, {3: "handled"}, ["load.approach"], lost)
    add("--set load.approach=1e6 (mean pressure > 1000 E*)", f5)

    def f6(d):
        os.makedirs(d)
        n, L = 64, 10.0
        rows = []
        for j in range(n):
            y = j * L / n
            rows.append(",".join("%.4f" % (80.0 * math.sin(2 * math.pi * i / n) * math.cos(2 * math.pi * 2 * y / L)
                                           + 40.0 * math.sin(2 * math.pi * 3 * (i / n + y / L)))
                                 for i in range(n)))
        F.write(os.path.join(d, "map_nm.csv"), "\n".join(rows) + "\n")
        F.write(os.path.join(d, "case.toml"), file_case("nm", "map_nm.csv", 'unit = "um"'))
        r = F.run(["run", os.path.join(d, "case.toml"), "-o", os.path.join(d, "out"), "-q"])
        wrong = []
        if not (has_fragment(r.err, "gradient") and has_fragment(r.err, ("unit",))):
            wrong.append("no rms-gradient warning naming the unit keys")
        s = read_json(os.path.join(d, "out", "summary.json"))
        if r.rc == 0 and s is not None and not s.get("warnings"):
            wrong.append("summary.json has no warnings")
        return F.verdict(r, {0: "handled", 3: "handled"}, [], leftovers(os.path.join(d, "out")), wrong)
    add("nm height map declared as µm (rms gradient ~100)", f6)

    def xyz_case(d, scattered):
        os.makedirs(d)
        n, h = 32, 0.25
        lines = ["x,y,z"]
        rnd = random.Random(1)
        for j in range(n):
            for i in range(n):
                x, y = i * h, j * h
                if scattered:
                    x, y = rnd.uniform(0, n * h), rnd.uniform(0, n * h)
                z = 0.05 * math.sin(2 * math.pi * i / n) * math.sin(2 * math.pi * j / n)
                lines.append("%.6f,%.6f,%.6f" % (x, y, z))
        F.write(os.path.join(d, "points.csv"), "\n".join(lines) + "\n")
        F.write(os.path.join(d, "case.toml"),
                file_case("xyz", "points.csv", 'unit = "um"', grid='unit = "um"', load="pressure = 0.02"))
        out = os.path.join(d, "out")
        r = F.run(["run", os.path.join(d, "case.toml"), "-o", out, "-q"])
        if scattered:
            return F.verdict(r, {2: "refused"}, ["points.csv"], leftovers(out))
        s = read_json(os.path.join(out, "summary.json")) or {}
        grid = (s.get("input") or {}).get("grid", {})
        wrong = []
        if r.rc == 0 and (grid.get("nx"), grid.get("ny")) != (n, n):
            wrong.append("read as a %sx%s grid, not 32x32 points" % (grid.get("nx"), grid.get("ny")))
        if r.rc == 0 and abs(grid.get("lx", 0) - n * h) > 1e-9:
            wrong.append("lx = %s, not %g" % (grid.get("lx"), n * h))
        return F.verdict(r, {0: "handled", 2: "refused"}, ["points.csv"] if r.rc == 2 else [],
                         leftovers(out), wrong)
    add("x,y,z CSV, points on a regular 32x32 grid", lambda d: xyz_case(d, False))
    add("x,y,z CSV, scattered points", lambda d: xyz_case(d, True))

    approach_list = ",".join("%g" % (i * 1e-9) for i in range(300))
    sweep0 = ["--set", "friction.coefficient=0"] + NO_FILES + ["--set", "load.approach=" + approach_list]

    def interrupted_verdict(r, sent, d, what, staging_ok=True, before=None, ignore=()):
        lost = leftovers(d, staging_ok=staging_ok)
        if before is not None:
            lost += changed(before, snapshot(d), ignore=set(ignore) | {"status.json", ".gfmd.lock",
                                                                        ".gfmd-staging", "checkpoint.bin"})
        if not sent:
            if lost:
                return F.verdict(r, {}, [], lost)
            cls, code, note = F.verdict(r, {0: "handled", 3: "handled", 4: "handled"}, [])
            return cls, code, "INCONCLUSIVE: ended before %s could be interrupted (%.1f s). %s" % (what, r.secs, note)
        wrong = []
        if r.rc == 4 and not has_fragment(r.err, "interrupt"):
            wrong.append("no 'interrupted' on stderr")
        if r.rc == 0:
            # The signal came while it was still running: ignoring it is a bug.
            return F.verdict(r, {4: "handled"}, [], lost, [], "the signal was ignored (ran to the end in %.1f s)" % r.secs)
        return F.verdict(r, {4: "handled"}, [], lost, wrong)

    def f8(d):
        t0 = time.monotonic()
        r, sent = F.interrupt(["sweep", base, "-o", d, "-q"] + sweep0, signal.SIGINT,
                              lambda: time.monotonic() - t0 > 2.0)
        cls, code, note = interrupted_verdict(r, sent, d, "the sweep")
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

    def f9(d):
        vals = ",".join("%.7g" % (0.01 + i * 1e-6) for i in range(10001))
        return F.expect_refusal(["sweep", base, "-o", d, "-q", "--set", "load.force=" + vals],
                                [("10000", "10 000", "10,000")], new_dir=d, timeout=min(F.timeout, 20))
    add("10 001 values in a --set list (sweep)", f9)

    # A run with PNGs, redrawn by gfmd plot (Ctrl-C), then re-run with another load (Ctrl-C).
    png_dir = F.path("drawn")

    def pngs_newer(d, t_ns):
        for dirpath, _, files in os.walk(d):
            for f in files:
                if f.endswith(".png") or ".png" in f:
                    try:
                        if os.stat(os.path.join(dirpath, f)).st_mtime_ns > t_ns:
                            return True
                    except OSError:
                        pass
        return False

    def f10(d):
        F.base_run(png_dir, "--set", "output.png=true")
        before = snapshot(png_dir)
        t_ns = time.time_ns()
        r, sent = F.interrupt(["plot", png_dir], signal.SIGINT, lambda: pngs_newer(png_dir, t_ns))
        # PNGs may be partly redrawn from the same data; the data must not change.
        return interrupted_verdict(r, sent, png_dir, "the drawing", staging_ok=False, before=before,
                                   ignore={n for n in before if n.endswith(".png")})
    add("Ctrl-C while `gfmd plot` draws", f10)

    def f11(d):
        if not os.path.exists(os.path.join(png_dir, "summary.json")):
            F.base_run(png_dir, "--set", "output.png=true")
        before = snapshot(png_dir)
        t_ns = time.time_ns()
        r, sent = F.interrupt(["run", base, "-o", png_dir, "-q", "--set", "output.png=true",
                               "--set", "load.force=0.02"], signal.SIGINT, lambda: pngs_newer(png_dir, t_ns))
        cls, code, note = interrupted_verdict(r, sent, png_dir, "the drawing", staging_ok=True, before=before)
        if sent and r.rc == 4 and cls == "handled" and not has_fragment(r.err, "kept unchanged"):
            cls, note = "wrong", "no 'kept unchanged' on stderr. " + note
        return cls, code, note
    add("Ctrl-C while `gfmd run` draws (re-run over a result with PNGs)", f11)

    study_small = os.path.join(REPO, "studies", "fig2b.toml")

    def f12(d):
        if not os.path.exists(study_small):
            return "not tried", "-", study_small + " not found"
        t0 = time.monotonic()
        r, sent = F.interrupt(["study", study_small, "--quick", "-o", d, "--set", "grid.nx=128",
                               "--set", "sweep.from=5e-3"], signal.SIGINT,
                              lambda: time.monotonic() - t0 > 5.0 or
                              (os.path.isdir(d) and time.monotonic() - t0 > 3.0))
        return interrupted_verdict(r, sent, d, "the study")
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
        cls, code, note = interrupted_verdict(r, sent, d, "the figure")
        if sent and r.rc == 4 and figs:
            note = "figure files present: %s. %s" % (", ".join(sorted(figs)), note)
        return cls, code, note
    add("Ctrl-C while `gfmd study` draws its figure (own 3-point study)", f12b)

    def f14(d):
        r = F.run(["run", base, "-o", d, "-q"])
        wrong = ["-q printed: " + short(r.out + r.err, 80)] if (r.out.strip() or r.err.strip()) else []
        return F.verdict(r, {0: "handled"}, [], leftovers(d), wrong)
    add("`gfmd run -q` on success prints nothing", f14)

    def f14b(d):
        r = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01"])
        wrong = ["-q printed: " + short(r.out + r.err, 80)] if (r.out.strip() or r.err.strip()) else []
        return F.verdict(r, {0: "handled"}, [], leftovers(d), wrong)
    add("`gfmd sweep -q` on success prints nothing", f14b)

    add("unknown subcommand `gfmd rnu base.toml`",
        lambda d: F.expect_refusal(["rnu", base], ["rnu"]))

    # ---------------------------------------------------------------- our own
    add("typo in a --set key (solver.max_iteration)",
        lambda d: F.expect_refusal(["run", base, "-o", d, "--set", "solver.max_iteration=5"],
                                   ["max_iteration"], new_dir=d))

    def typo_file(d):
        p = F.write("typo.toml", BASE_TOML.replace("nx = 64", "nxx = 64"))
        return F.expect_refusal(["run", p, "-o", d], ["nxx"], new_dir=d)
    add("typo in a case-file key ([grid] nxx)", typo_file)

    for what, setting, frag in [
            ("wrong type (grid.nx=\"sixty\")", 'grid.nx="sixty"', "grid.nx"),
            ("float for an integer (grid.nx=64.5)", "grid.nx=64.5", "grid.nx"),
            ("negative size (grid.lx=-4)", "grid.lx=-4", "grid.lx"),
            ("zero grid (grid.nx=0)", "grid.nx=0", "grid.nx"),
            ("NaN (load.force=nan)", "load.force=nan", "load.force"),
            ("inf (elastic.contact_modulus=inf)", "elastic.contact_modulus=inf", "contact_modulus"),
            ("out of range (elastic.poisson=0.6)", "elastic.poisson=0.6", "poisson"),
            ("zero radius (indenter.radius=0)", "indenter.radius=0", "radius"),
            ("unknown section (foo.bar=1)", "foo.bar=1", "foo"),
            ("without '=' (load.force)", "load.force", "load.force"),
            ("with an empty value (load.force=)", "load.force=", "load.force")]:
        add("--set " + what,
            lambda d, s=setting, fr=frag: F.expect_refusal(["run", base, "-o", d, "--set", s], [fr], new_dir=d))

    def huge(d):
        limit = 8 << 30

        def cap():
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        r = F.run(["run", base, "-o", d, "--set", "grid.nx=65536"], preexec=cap)
        return F.verdict(r, {2: "refused"}, [("memory", "grid.nx")], leftovers(d),
                         note="(ulimit -v 8 GiB as a safety net)")
    add("grid beyond memory (grid.nx=65536: 32 GiB a field)", huge)

    def dup_set(d):
        r = F.run(["run", base, "-o", d, "-q", "--set", "load.force=0.01", "--set", "load.force=0.02"])
        s = read_json(os.path.join(d, "summary.json")) or {}
        wrong = []
        if r.rc == 0 and abs(float(s.get("normal_force", 0)) - 0.02) > 1e-6:
            wrong.append("normal_force %s: the last --set did not win" % s.get("normal_force"))
        return F.verdict(r, {0: "handled", 2: "refused"}, ["load.force"] if r.rc == 2 else [], leftovers(d), wrong,
                         "last one wins" if r.rc == 0 and not wrong else "")
    add("duplicate --set keys (load.force twice)", dup_set)

    def dup_file(d):
        p = F.write("dupkey.toml", BASE_TOML.replace("nx = 64", "nx = 64\nnx = 32"))
        return F.expect_refusal(["run", p, "-o", d], [("nx", "dupkey.toml")], new_dir=d)
    add("duplicate key in the case file (nx twice)", dup_file)

    def two_loads(d):
        p = F.write("twoloads.toml", BASE_TOML.replace("force = 0.01", "force = 0.01\npressure = 0.001"))
        return F.expect_refusal(["run", p, "-o", d], ["load"], new_dir=d)
    add("two loads in the case file (force and pressure)", two_loads)

    add("comma list given to `run` (load.force=0.01,0.02)",
        lambda d: F.expect_refusal(["run", base, "-o", d, "--set", "load.force=0.01,0.02"], ["sweep"], new_dir=d))

    def empty_case(d):
        p = F.write("empty.toml", "")
        return F.expect_refusal(["run", p, "-o", d], [("empty.toml", "indenter", "load")], new_dir=d)
    add("empty case file", empty_case)

    def garbage(d):
        p = F.path("garbage.toml")
        with open(p, "wb") as f:
            f.write(bytes(random.Random(7).randrange(256) for _ in range(4096)))
        return F.expect_refusal(["run", p, "-o", d], ["garbage.toml"], new_dir=d)
    add("binary garbage as the case file", garbage)

    def big_case(d):
        p = F.write("big.toml", BASE_TOML + ("# padding " + "x" * 100 + "\n") * 11000)
        return F.expect_refusal(["run", p, "-o", d], [("big.toml", "MB")], new_dir=d)
    add("case file of 1.2 MB (comment padding)", big_case)

    def dir_case(d):
        os.makedirs(os.path.join(d, "casedir"))
        return F.expect_refusal(["run", os.path.join(d, "casedir"), "-o", os.path.join(d, "o")], ["casedir"],
                                new_dir=os.path.join(d, "o"))
    add("a directory given as the case", dir_case)

    add("missing case file",
        lambda d: F.expect_refusal(["run", F.path("no_such_case.toml"), "-o", d], ["no_such_case.toml"], new_dir=d))

    def unreadable(d):
        os.makedirs(d)
        p = os.path.join(d, "locked.toml")
        shutil.copy(base, p)
        os.chmod(p, 0)
        out = os.path.join(d, "o")
        r = F.run(["run", p, "-o", out, "-q"])
        os.chmod(p, 0o644)
        if F.is_root:
            return F.verdict(r, {0: "handled"}, [], leftovers(out),
                             note="run as root: chmod 000 does not stop root reading it, so this does not apply")
        return F.verdict(r, {2: "refused"}, ["locked.toml"], leftovers(out))
    add("unreadable case file (chmod 000)", unreadable)

    def fifo(d):
        os.makedirs(d)
        p = os.path.join(d, "pipe.toml")
        os.mkfifo(p)
        return F.expect_refusal(["run", p, "-o", os.path.join(d, "o")], ["pipe.toml"], timeout=20,
                                new_dir=os.path.join(d, "o"))
    add("a FIFO as the case file (must not hang)", fifo)

    add("/dev/zero as the case file (must not hang)",
        lambda d: F.expect_refusal(["run", "/dev/zero", "-o", d], ["/dev/zero"], timeout=20, new_dir=d))

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

    add("unknown option (--fast)", lambda d: F.expect_refusal(["run", base, "-o", d, "--fast"], ["--fast"], new_dir=d))
    add("no case argument (`gfmd run -o DIR`)",
        lambda d: F.expect_refusal(["run", "-o", d], ["case"], new_dir=d))

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

    def ckpt(d, value, expect):
        r = F.run(["run", base, "-o", d, "-q", "--checkpoint-interval", value])
        return F.verdict(r, expect, ["checkpoint-interval"] if r.rc == 2 else [], leftovers(d))
    add("--checkpoint-interval 0", lambda d: ckpt(d, "0", {0: "handled", 2: "refused"}))
    add("--checkpoint-interval -5", lambda d: ckpt(d, "-5", {2: "refused"}))
    add("--checkpoint-interval nan", lambda d: ckpt(d, "nan", {2: "refused"}))

    def sweep_string(d):
        r = F.run(["sweep", base, "-o", d, "-q", "--set", "indenter.type=hertz,eggcrate"])
        return F.verdict(r, {0: "handled", 2: "refused"}, ["indenter.type"] if r.rc == 2 else [], leftovers(d))
    add("sweep over a non-numeric key (indenter.type=hertz,eggcrate)", sweep_string)

    def sweep_two_lists(d):
        r = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01", "--set", "elastic.poisson=0.2,0.3"])
        return F.verdict(r, {2: "refused"}, [("load.force", "elastic.poisson", "one key")], leftovers(d))
    add("sweep with lists on two keys", sweep_two_lists)

    add("sweep with an empty list item (load.force=0.01,,0.02)",
        lambda d: F.expect_refusal(["sweep", base, "-o", d, "--set", "load.force=0.01,,0.02"], ["load.force"],
                                   new_dir=d))

    def sweep_term(d):
        r0 = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01,0.02"])
        if r0.rc != 0:
            raise RuntimeError("baseline sweep failed: " + short(r0.err))
        before = snapshot(d)
        t0 = time.monotonic()
        r, sent = F.interrupt(["sweep", base, "-o", d, "-q"] + sweep0, signal.SIGTERM,
                              lambda: time.monotonic() - t0 > 2.0, group=False)
        cls, code, note = interrupted_verdict(r, sent, d, "the sweep", before=before)
        new_points = [p for p in added(before, snapshot(d), ignore={".gfmd-staging", "status.json"})
                      if os.sep not in p]
        if new_points and cls != "crashed":
            cls, note = "data lost or mixed", "new entries beside the previous sweep: %s. %s" % (
                ", ".join(new_points[:4]), note)
        if sent and r.rc == 4 and cls == "handled" and not has_fragment(r.err, "kept unchanged"):
            cls, note = "wrong", "no 'kept unchanged' on stderr. " + note
        return cls, code, note
    add("SIGTERM (kill PID) a 300-point sweep over a previous sweep", sweep_term)

    # flow / plot on the wrong directories
    def flow_foreign(d):
        os.makedirs(d)
        F.write(os.path.join(d, "notes.txt"), "mine\n")
        return F.expect_refusal(["flow", d], [os.path.basename(d)], watch=[d])
    add("`gfmd flow` on a directory that is not a run", flow_foreign)

    def flow_bad_direction(d):
        F.base_run(d)
        return F.expect_refusal(["flow", d, "--direction", "diagonal"], ["direction"], watch=[d])
    add("`gfmd flow --direction diagonal` on a run", flow_bad_direction)

    def plot_empty(d):
        os.makedirs(d)
        return F.expect_refusal(["plot", d], [os.path.basename(d)], watch=[d])
    add("`gfmd plot` on an empty directory", plot_empty)
    add("`gfmd plot` on a missing directory",
        lambda d: F.expect_refusal(["plot", d], [os.path.basename(d)], new_dir=d))

    add("`gfmd green --from 10 --to 1`",
        lambda d: F.expect_refusal(["green", "--poisson", "0.25", "--from", "10", "--to", "1", "-o",
                                    os.path.join(F.tmp, "phi.csv")], [("--from", "--to", "from")]))

    # height maps
    def map_case(d, name, data, frags, extra='unit = "um"', mode="w"):
        os.makedirs(d, exist_ok=True)
        p = os.path.join(d, name)
        with open(p, mode) as f:
            f.write(data)
        F.write(os.path.join(d, "case.toml"), file_case(name, name, extra))
        out = os.path.join(d, "out")
        return F.expect_refusal(["run", os.path.join(d, "case.toml"), "-o", out], frags, new_dir=out)

    def nan_map(d):
        rows = []
        for j in range(32):
            rows.append(",".join("nan" if (i, j) in ((3, 4), (10, 20)) else "%.3f" % (0.01 * math.sin(i + j))
                                 for i in range(32)))
        return map_case(d, "holes.csv", "\n".join(rows) + "\n", ["holes.csv", "missing"])
    add("height map with NaNs (missing = \"error\")", nan_map)

    def npy_complex(d):
        raw = struct.pack("<%dd" % (2 * 32 * 32), *([0.1] * (2 * 32 * 32)))
        return map_case(d, "complex.npy", npy_bytes("<c16", (32, 32), raw), ["complex.npy"], mode="wb")
    add(".npy of complex128", npy_complex)

    def npy_str(d):
        raw = ("abc" * (32 * 32)).encode("utf-32-le")
        return map_case(d, "strings.npy", npy_bytes("<U3", (32, 32), raw), ["strings.npy"], mode="wb")
    add(".npy of strings (<U3)", npy_str)

    def npy_3d(d):
        raw = struct.pack("<%dd" % (2 * 16 * 16), *([0.1] * (2 * 16 * 16)))
        return map_case(d, "cube.npy", npy_bytes("<f8", (2, 16, 16), raw), ["cube.npy"], mode="wb")
    add(".npy with 3 dimensions", npy_3d)

    def npy_truncated(d):
        raw = struct.pack("<%dd" % 100, *([0.1] * 100))
        return map_case(d, "short.npy", npy_bytes("<f8", (32, 32), raw), ["short.npy"], mode="wb")
    add(".npy shorter than its header says", npy_truncated)

    add("x3p that is not a zip",
        lambda d: map_case(d, "fake.x3p", "this is not a zip archive\n", ["fake.x3p"], extra=""))
    add("empty height-map file (0 bytes .csv)", lambda d: map_case(d, "empty.csv", "", ["empty.csv"]))

    def map_missing(d):
        os.makedirs(d)
        F.write(os.path.join(d, "case.toml"), file_case("x", "nowhere.csv", 'unit = "um"'))
        out = os.path.join(d, "out")
        return F.expect_refusal(["run", os.path.join(d, "case.toml"), "-o", out], ["nowhere.csv"], new_dir=out)
    add("height-map path that does not exist", map_missing)

    def study_bad_set(d):
        if not os.path.exists(study_small):
            return "not tried", "-", study_small + " not found"
        return F.expect_refusal(["study", study_small, "--quick", "-o", d, "--set", "grid.nxx=64"], ["nxx"],
                                timeout=60)
    add("`gfmd study --set grid.nxx=64` (typo for every run)", study_bad_set)


    # ---------------------------------------------------------------- more interruptions and re-runs
    def midsolve(d):
        F.base_run(d)
        before = snapshot(d)
        t0 = time.monotonic()
        r, sent = F.interrupt(["run", base, "-o", d, "-q", "--set", "load.force=0.02"] + LONG, signal.SIGINT,
                              lambda: time.monotonic() - t0 > 2.0)
        cls, code, note = interrupted_verdict(r, sent, d, "the solve", staging_ok=True, before=before)
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
        return interrupted_verdict(r, sent, d, "the drawing", staging_ok=True, before=before)
    add("Ctrl-C twice (0.3 s apart) while `gfmd run` draws", double_ctrl_c)

    def study_term(d):
        if not os.path.exists(study_small):
            return "not tried", "-", study_small + " not found"
        t0 = time.monotonic()
        r, sent = F.interrupt(["study", study_small, "--quick", "-o", d, "--set", "grid.nx=128",
                               "--set", "sweep.from=5e-3"], signal.SIGTERM,
                              lambda: time.monotonic() - t0 > 4.0, group=False)
        return interrupted_verdict(r, sent, d, "the study")
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

    def resume_done(d):
        F.base_run(d)
        before = snapshot(d)
        r = F.run(["run", base, "-o", d, "-q", "--resume"])
        lost = changed(before, snapshot(d), ignore={"status.json", ".gfmd.lock"}) + leftovers(d)
        return F.verdict(r, {0: "handled"}, [], lost)
    add("--resume on a directory that holds the converged result", resume_done)

    def sweep_fail_over(d):
        r0 = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01"])
        if r0.rc != 0:
            raise RuntimeError("baseline sweep failed: " + short(r0.err))
        before = snapshot(d)
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
        r0 = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01,0.015,0.02"])
        if r0.rc != 0:
            raise RuntimeError("baseline sweep failed: " + short(r0.err))
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
        r0 = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01"])
        if r0.rc != 0:
            raise RuntimeError("baseline sweep failed: " + short(r0.err))
        before = snapshot(d)
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

    def bom_crlf(d):
        p = F.path("windows.toml")
        with open(p, "wb") as f:
            f.write(b"\xef\xbb\xbf" + BASE_TOML.replace("\n", "\r\n").encode())
        r = F.run(["run", p, "-o", d, "-q"])
        return F.verdict(r, {0: "handled", 2: "refused"}, ["windows.toml"] if r.rc == 2 else [], leftovers(d))
    add("case file with a UTF-8 BOM and CRLF line ends", bom_crlf)

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

    # ---------------------------------------------------------------- the Python package
    if F.pkg:
        def py(d, code, frags, watch=(), home=None, timeout=None):
            os.makedirs(d, exist_ok=True)
            # exit 2: the exception expected was raised (printed as EXC type message); 0: none was
            prog = ("import sys, warnings\nsys.path.insert(0, %r)\ntry:\n    import gfmd\n"
                    "    assert hasattr(gfmd, 'run'), 'no gfmd.run in ' + str(gfmd.__path__)\n"
                    "except (ImportError, AssertionError) as e:\n    print('IMPORT', e, file=sys.stderr)\n    sys.exit(7)\n"
                    "try:\n%s\nexcept Exception as e:\n    print('EXC', type(e).__name__, e, file=sys.stderr)\n"
                    "    sys.exit(2)\nsys.exit(0)\n" % (F.pkg, "\n".join("    " + l for l in code.splitlines())))
            before = {w: snapshot(w) for w in watch}
            r = F.run([[sys.executable, "-c", prog]], cwd=d, env=dict(F.env, HOME=home) if home else None,
                      timeout=timeout)
            if r.rc == 7 and r.err.startswith("IMPORT"):
                return "not tried", "-", "cannot import gfmd from %s: %s" % (F.pkg, short(r.err[7:], 80))
            lost = []
            for w in watch:
                after = snapshot(w)
                lost += changed(before[w], after) + ["wrote " + x for x in added(before[w], after)]
            return F.verdict(r, {2: "refused"}, frags, lost)

        def py_foreign(d):
            out = os.path.join(d, "mine")
            os.makedirs(out)
            F.write(os.path.join(out, "spectrum.csv"), "mine\n")
            return py(d, "gfmd.run(%r, output=%r)" % (base, out), ["mine"], watch=[out])
        add("Python gfmd.run(output=foreign dir with spectrum.csv)", py_foreign)
        def py_home(d):
            home = os.path.join(d, "emptyhome")
            os.makedirs(home)
            return py(d, "gfmd.run(%r, output=%r)" % (base, home), ["home directory"], watch=[home], home=home)
        add("Python gfmd.run(output=$HOME), HOME an empty dir", py_home)
        add("Python gfmd.run(set=['solver.max_iteration=3'])",
            lambda d: py(d, "gfmd.run(%r, set=['solver.max_iteration=3'], output=%r)" % (base, os.path.join(d, "o")),
                         ["max_iteration"]))
        add("Python gfmd.sweep with 10 001 values",
            lambda d: py(d, "gfmd.sweep(%r, 'load.force', [0.01 + i * 1e-6 for i in range(10001)], %r)"
                         % (base, os.path.join(d, "o")), [("10000", "10 000", "10,000")], timeout=min(F.timeout, 20)))

        def py_save(d):
            out = os.path.join(d, "mine")
            os.makedirs(out)
            F.write(os.path.join(out, "notes.txt"), "mine\n")
            code = ("t = gfmd.Topography.hertz(64, 4.0, radius=1.0)\n"
                    "r = gfmd.solve(t, force=0.01)\nr.save(%r)" % out)
            return py(d, code, ["mine"], watch=[out])
        add("Python Result.save(foreign dir)", py_save)

        add("Python gfmd.solve(pressure=nan)",
            lambda d: py(d, "t = gfmd.Topography.hertz(64, 4.0, radius=1.0)\ngfmd.solve(t, pressure=float('nan'))",
                         ["pressure"]))


# ---------------------------------------------------------------------------- output

def table(rows, gfmd, secs):
    lines = ["Faults tried against `%s` (%.0f s)" % (gfmd, secs), "",
             "| id | what was tried | exit | outcome | note |", "|---|---|---|---|---|"]
    for fid, what, code, cls, note in rows:
        lines.append("| %s | %s | %s | %s | %s |" % (fid, what.replace("|", "\\|"), code, cls,
                                                       note.replace("|", "\\|").replace("\n", " ")))
    tried = [r for r in rows if r[3] != "not tried"]
    counts = {c: sum(1 for r in tried if r[3] == c) for c in CLASSES}
    lines.append("| **totals** | tried %d / refused %d / handled %d / wrong %d / crashed %d / data lost or mixed %d"
                 "%s | | | |" % (len(tried), counts["refused"], counts["handled"], counts["wrong"], counts["crashed"],
                                 counts["data lost or mixed"],
                                 " (not tried %d)" % (len(rows) - len(tried)) if len(rows) != len(tried) else ""))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--gfmd", required=True, help="the gfmd binary to try")
    ap.add_argument("--python-pkg", help="BUILD/python: also try the Python package's faults")
    ap.add_argument("--keep", help="copy the scratch directory to this new directory at the end")
    ap.add_argument("--timeout", type=float, default=120.0, help="seconds one child may take (default 120)")
    ap.add_argument("--only", help="comma-separated fault ids to try (all by default)")
    a = ap.parse_args()
    if not (os.path.isfile(a.gfmd) and os.access(a.gfmd, os.X_OK)):
        ap.error("--gfmd %s: not an executable file" % a.gfmd)
    if a.python_pkg and not os.path.isdir(os.path.join(a.python_pkg, "gfmd")):
        ap.error("--python-pkg %s: no gfmd package in it" % a.python_pkg)
    if a.keep and os.path.exists(a.keep) and (not os.path.isdir(a.keep) or os.listdir(a.keep)):
        ap.error("--keep %s: exists and is not an empty directory" % a.keep)
    F = Faults(a.gfmd, a.python_pkg, a.timeout)
    only = set(a.only.split(",")) if a.only else None
    if only:
        real_add = F.add

        def add(what, fn):
            if str(F.n + 1) in only:
                real_add(what, fn)
            else:
                F.n += 1
        F.add = add
    t0 = time.monotonic()
    try:
        define(F)
    except KeyboardInterrupt:
        F.stop_all()
        sys.stderr.write("fault_table: interrupted; the table so far:\n")
    finally:
        F.stop_all()
        print(table(F.rows, a.gfmd, time.monotonic() - t0))
        sys.stdout.flush()
        if a.keep:
            shutil.copytree(F.tmp, a.keep, symlinks=True, dirs_exist_ok=True)
            sys.stderr.write("scratch directory copied to %s\n" % a.keep)
        shutil.rmtree(F.tmp, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
