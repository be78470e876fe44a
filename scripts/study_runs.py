"""The runs of a figure study (scripts/study.py): each case into its directory, in this process
through the gfmd package of the calling program or by starting that program; the input checks
before each run, the signals (SIGINT, SIGTERM: Interrupted) and the exit statuses they share."""
import hashlib
import json
import os
import signal
import subprocess
import sys

from study_file import BadInput

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# `gfmd study` names itself in GFMD; run from the source tree, the build's binary.
GFMD = os.environ.get("GFMD", os.path.join(ROOT, "build", "gfmd"))
FORCE = False  # --force (set by study.py): the runs may write into non-empty directories gfmd did not make


LAST_LOG = []  # the last line logged (gfmd.study, which runs a study in its own process, reports it)


def log(msg):
    LAST_LOG[:] = [str(msg)]
    print(msg, file=sys.stderr, flush=True)


NOT_CONVERGED = 3  # gfmd's exit status when a solve does not converge
BAD_INPUT = 2      # ... for bad input (the study's exit status too)
INTERRUPTED = 4    # ... when stopped by SIGINT/SIGTERM (the study's exit status too)
INTERRUPTED_MESSAGE = "gfmd: study interrupted; run the same command again to continue"  # as gfmd study's


def fail(msg, status):
    """Ends the study with msg on standard error and an exit status (3: a run did not
    converge, 1: anything else)."""
    log(msg)
    sys.exit(status)


class Interrupted(Exception):
    """SIGINT/SIGTERM (or a run that was stopped by one): exit 4."""


# Signals. SIGINT and SIGTERM set STOP. While a gfmd run is being waited for, the signal is
# passed on to it (a Ctrl-C reaches it anyway; a SIGTERM sent to this process alone does
# not) and the run is waited for: gfmd stops at its next check, writes nothing half-done and
# exits 4. While this script computes or draws itself, the signal raises KeyboardInterrupt
# at once. Either way main() ends with one line and exit status 4.
STOP = []
_child = {"waiting": False, "proc": None, "exiting": False}


def _on_signal(signum, _frame):
    STOP.append(signum)
    if _child["exiting"]:
        return
    if _child["waiting"]:
        if _child["proc"] is not None:
            try:
                _child["proc"].send_signal(signum)  # nothing if it has ended
            except OSError:
                pass
        return
    _child["exiting"] = True  # once: the clean-up that follows is not interrupted again
    raise KeyboardInterrupt


def install_signal_handlers():
    signal.signal(signal.SIGINT, _on_signal)
    signal.signal(signal.SIGTERM, _on_signal)


def check_stop():
    if STOP:
        raise Interrupted()


# Each run reads its case file once (gfmd sweep, curve and run make every point from that
# text, and the surface of a height file once); a study runs gfmd once per series, so a case
# file, a height file or a master curve edited between two of its runs would mix two cases in
# one figure. The content each had at its first run, by path.
_CASE_DIGESTS = {}


def check_case_unchanged(path, what="case file"):
    """Records the file's content at its first run in this study; at a later run a changed
    content ends the study (exit status 1) instead of drawing series of two different cases."""
    with open(path, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    if _CASE_DIGESTS.setdefault(os.path.realpath(path), digest) != digest:
        fail(f"study: {path}: the {what} changed while the study ran (its earlier runs were solved "
             "from the previous content); run the study again (runs of the new content are solved again, "
             "finished ones of the old content are not reused for it)", 1)


def input_files(case, settings):
    """The files a gfmd run of `case` reads besides it, as (path, what): the height file of a file
    indenter (indenter.path) and the master curves of a viscoelastic body (elastic.master_curve,
    and that of each elastic.viscoelastic_parts table), relative to the case file's folder as gfmd
    reads them; a setting of the run (KEY=VALUE in settings) replaces the case's value."""
    import tomllib

    try:
        with open(case, "rb") as f:
            data = tomllib.load(f)
    except (OSError, ValueError):
        return []  # gfmd names the problem
    sets = {}
    for kv in settings:
        if "=" in kv:
            k, v = kv.split("=", 1)
            sets[k.strip()] = v.strip()

    def value(section, key):
        if f"{section}.{key}" in sets:
            try:
                return tomllib.loads("x = " + sets[f"{section}.{key}"])["x"]
            except ValueError:
                return None
        table = data.get(section)
        return table.get(key) if isinstance(table, dict) else None

    found = [(value("indenter", "path"), "height file"), (value("elastic", "master_curve"), "master curve file")]
    parts = value("elastic", "viscoelastic_parts")
    for part in parts if isinstance(parts, list) else []:
        if isinstance(part, dict):
            found.append((part.get("master_curve"), "master curve file"))
    base = os.path.dirname(os.path.abspath(case))
    return [(os.path.join(base, p), what) for p, what in found
            if isinstance(p, str) and p and os.path.isfile(os.path.join(base, p))]


def check_inputs(case, settings):
    """Before each run of a case: a case file, height file or master curve that changed since
    its first run in this study ends it (check_case_unchanged)."""
    check_stop()
    if os.path.isfile(case):
        check_case_unchanged(case)
        for path, kind in input_files(case, settings):
            check_case_unchanged(path, kind)


def set_args(settings):
    args = []
    for kv in settings:
        args += ["--set", kv]
    return args


def run(cmd, tolerate_not_converged=False, what=""):
    """Runs a gfmd command (argument vector; GFMD_STUDY_RUNS=process or no package) and waits
    for it; on SIGINT/SIGTERM it is stopped and waited for, then Interrupted is raised. Exit
    status 2 of the run is bad input (a setting of the study or of --set): BadInput naming
    `what` and the run's reason."""
    check_stop()
    _child["waiting"] = True
    try:
        try:
            p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, encoding="utf-8",
                                 errors="replace")
        except OSError as e:
            fail(f"study: cannot start {cmd[0]}: {e.strerror} (GFMD names the gfmd program)", 1)
        _child["proc"] = p
        if STOP:  # a signal came between Popen and the line above: pass it on now
            p.send_signal(STOP[-1])
        out, err = p.communicate()
    finally:
        _child["waiting"] = False
        _child["proc"] = None
    p = subprocess.CompletedProcess(cmd, p.returncode, out, err)
    if STOP or p.returncode == INTERRUPTED:
        raise Interrupted()
    if p.returncode == BAD_INPUT:
        why = " ".join(ln.strip() for ln in p.stderr.splitlines() if ln.strip())
        raise BadInput(f"{what}: {why or 'gfmd ' + cmd[1] + ' refused its input'}")
    if p.returncode != 0 and not (tolerate_not_converged and p.returncode == NOT_CONVERGED):
        fail(f"study: command failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}{p.stderr}",
             NOT_CONVERGED if p.returncode == NOT_CONVERGED else 1)
    return p


def stopped_reason(p):
    """Why a gfmd command that exited 3 stopped: the last line it printed."""
    return (p.stderr.strip().splitlines() or ["not converged"])[-1]


# ---------------------------------------------------------------------------------------
# The runs in this process: the gfmd package of the calling program (find_package), loaded by
# main(); None where the runs start the program instead.
LIB = None


def find_package(program):
    """The folder of the gfmd package that belongs to `program` (<build>/python/gfmd beside
    <build>/gfmd; <site>/gfmd for <site>/gfmd/bin/gfmd), or None."""
    where = os.path.dirname(os.path.realpath(program))
    for pkg in (os.path.join(where, "python", "gfmd"), os.path.dirname(where)):
        try:
            names = os.listdir(pkg)
        except OSError:
            continue
        if "__init__.py" in names and any(n.startswith("_core") and n.endswith(".so") for n in names):
            return pkg
    return None


def reset(library=None, program=None):
    """The state of one study: no stop requested, no run waited for, no case read, nothing
    logged; the runs in `library` (the calling gfmd package, gfmd.study) or, where None, as
    load_library finds them. `program`: the gfmd program for what starts it."""
    global LIB, GFMD, FORCE
    STOP.clear()
    _child.update(waiting=False, proc=None, exiting=False)
    _CASE_DIGESTS.clear()
    LAST_LOG.clear()
    FORCE = False
    LIB = library
    if program:
        GFMD = program


def load_library():
    """Imports the package of the calling program for the runs (or leaves LIB None: the
    program is started per run); GFMD_STUDY_RUNS=process asks for the latter. A package given
    to reset() (the calling one, in its own process) is kept unless process is asked for."""
    global LIB
    mode = os.environ.get("GFMD_STUDY_RUNS") or "library"  # unset or empty: the default
    if mode not in ("library", "process"):
        raise BadInput(f"GFMD_STUDY_RUNS: must be library or process (got {mode!r})")
    if mode == "process":
        LIB = None
        return
    if LIB is not None:
        return
    pkg = find_package(GFMD)
    if pkg is None:
        return
    sys.path.insert(0, os.path.dirname(pkg))
    import gfmd  # noqa: E402

    if os.path.realpath(os.path.dirname(gfmd.__file__)) != os.path.realpath(pkg):
        log(f"study: warning: another gfmd package ({gfmd.__file__}) is loaded; the runs start {GFMD}")
        return
    LIB = gfmd


def call(what, f, *args, tolerate_not_converged=False, **kwargs):
    """A study of the gfmd package in this process: (its result, None), or where a solve did not
    converge and tolerate_not_converged (None, the reason). Bad input is BadInput naming `what`;
    Ctrl-C or SIGTERM (KeyboardInterrupt: the package stops the solve within an iteration and
    keeps what is finished, as gfmd does) is Interrupted."""
    check_stop()
    try:
        return f(*args, **kwargs), None
    except KeyboardInterrupt:
        raise Interrupted() from None
    except LIB.InputError as e:
        raise BadInput(f"{what}: {e}") from None
    except LIB.SolveError as e:
        if tolerate_not_converged:
            return None, str(e)
        fail(f"study: {what}: {e}", NOT_CONVERGED)
    except OSError as e:
        fail(f"study: {what}: {e}", 1)


# The runs a study makes, each into its directory d, with the settings of the study and its
# series (KEY=VALUE); in this process (LIB) or by starting gfmd.

def case_command(command, case, d, settings, *options):
    """The argument vector of `gfmd COMMAND CASE OPTIONS -o d -q --set ... [--force]`."""
    return [GFMD, command, case, *options, "-o", d, "-q"] + set_args(settings) + (["--force"] if FORCE else [])


def run_case(case, d, settings, what):
    """One case (gfmd run --resume: a finished result is reused); returns its summary."""
    check_inputs(case, settings)
    if LIB is not None:
        call(what, LIB.run, case, set=settings, output=d, force=FORCE, resume=True)
    else:
        run(case_command("run", case, d, settings, "--resume"), what=what)
    with open(os.path.join(d, "summary.json")) as f:
        return json.load(f)


def sweep_case(case, d, settings, y, what):
    """The case's own [sweep] drawn against y (gfmd sweep --plot y): None, or where a point did
    not converge the reason (the finished points are kept in d)."""
    check_inputs(case, settings)
    if LIB is not None:
        return call(what, LIB.sweep, case, output=d, set=settings, plot=y, force=FORCE,
                    tolerate_not_converged=True)[1]
    p = run(case_command("sweep", case, d, settings, "--plot", y), tolerate_not_converged=True, what=what)
    return stopped_reason(p) if p.returncode != 0 else None


def curve_case(case, d, settings, approaches, what):
    """An approach path (gfmd curve --approaches; finished points of the same path are reused):
    None, or the reason it stopped."""
    check_inputs(case, settings)
    if LIB is not None:
        return call(what, LIB.curve, case, approaches=approaches, output=d, set=settings, force=FORCE,
                    tolerate_not_converged=True)[1]
    p = run(case_command("curve", case, d, settings, "--approaches", approaches), tolerate_not_converged=True,
            what=what)
    return stopped_reason(p) if p.returncode != 0 else None


def percolation_case(case, d, settings, direction, what):
    """The percolation threshold along direction (gfmd percolation) into d."""
    check_inputs(case, settings)
    if LIB is not None:
        call(what, LIB.percolation, case, direction, set=settings, output=d, force=FORCE)
    else:
        run(case_command("percolation", case, d, settings, "--direction", direction), what=what)


def green_table(poisson, csv_path, what):
    """The Green's tensor table for these Poisson ratios (gfmd green) into csv_path."""
    if LIB is not None:
        call(what, LIB.green, poisson=[float(v) for v in poisson], output=csv_path)
    else:
        run([GFMD, "green", "--poisson", ",".join(str(v) for v in poisson), "-o", csv_path], what=what)
