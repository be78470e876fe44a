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
import os
import shutil
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from faults import cases_input, cases_interrupt, cases_maps, cases_output, cases_python, cases_studies  # noqa: E402
from faults.harness import CLASSES, Faults  # noqa: E402

# The faults in the order of the table (a fault's id is its position): the themes interleave as
# the list grew (first the faults from the issue, then our own, then more interruptions).
SECTIONS = [
    cases_output.issue_outputs,
    cases_input.issue_approach,
    cases_maps.issue_maps,
    cases_interrupt.issue_sweep,
    cases_input.issue_long_list,
    cases_interrupt.issue_drawing,
    cases_studies.issue_studies,
    cases_input.issue_quiet,
    cases_input.case_inputs,
    cases_output.output_targets,
    cases_input.bad_arguments,
    cases_output.shared_dirs,
    cases_input.checkpoint_sweep_args,
    cases_interrupt.sweep_term,
    cases_input.flow_plot_args,
    cases_maps.bad_maps,
    cases_studies.study_bad_set,
    cases_interrupt.more_interrupts,
    cases_output.reruns,
    cases_input.encoding,
    cases_output.environment,
    cases_python.python_package,
]


def define(F):
    for section in SECTIONS:
        section(F)


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
