#!/usr/bin/python3
"""Distributed runs (mpirun) against threads: strong scaling, time per iteration, memory per rank.

    /usr/bin/python3 scripts/bench_mpi.py --sizes 2048 [--case rough] [--ranks 1 2 4] [--set KEY=VALUE]
                                          [--json FILE]

For each size: the case with 1 and 2 OpenMP threads in one process, then under
`mpirun -np N --oversubscribe` with one thread per rank for each N. Prints one row per run:
solve seconds, iterations (CG / friction steps), seconds per CG iteration, the share of the
solve spent in the transforms (fft_time_s, which under MPI includes FFTW-MPI's transposes), the
share spent in the reductions' collectives (summary "mpi.reduction_time_s", rank 0), the peak
memory of each rank at the end of the solves and rank 0's at the end of the run.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench import CASES, GFMD, ROOT  # noqa: E402

ENV = dict(os.environ, OMP_WAIT_POLICY="PASSIVE", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")


def run(case, n, threads, ranks, sets=()):
    path, extra = CASES[case]
    with tempfile.TemporaryDirectory() as d:
        cmd = [GFMD, "run", os.path.join(ROOT, path), "-o", d, "-q",
               "--set", f"grid.nx={n}", "--set", f"solver.threads={threads}",
               "--set", "output.fields=false", "--set", "output.png=false", "--set", "output.analysis=false"]
        for e in list(extra(n)) + list(sets):
            cmd += ["--set", e]
        if ranks:
            cmd = ["mpirun", "-np", str(ranks), "--oversubscribe", "--bind-to", "none"] + cmd
        p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
        if p.returncode != 0:
            return {"error": (p.stdout + p.stderr)[-2000:]}
        with open(os.path.join(d, "summary.json")) as f:
            return json.load(f)


def row(label, s):
    if "error" in s:
        return f"| {label} | failed: {s['error'][-200:]!r} |"
    it = s["iterations"]
    outer = s.get("outer_iterations", 0)
    wall = s["wall_time_s"]
    fft = s.get("fft_time_s", 0.0)
    m = s.get("mpi")
    red = m["reduction_time_s"][0] if m else 0.0
    mem = " / ".join(f"{v:.0f}" for v in m["solve_peak_memory_mib"]) if m else "-"
    root = f"{m['rank0_peak_memory_mib']:.0f}" if m else "-"
    return (f"| {label} | {wall:.2f} | {it} / {outer} | {1e3 * wall / max(it, 1):.1f} | {100 * fft / wall:.0f} % | "
            f"{100 * red / wall:.1f} % | {mem} | {root} | {s['friction_coefficient']:.15g} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", nargs="+", type=int, default=[2048])
    ap.add_argument("--case", default="rough", choices=sorted(CASES))
    ap.add_argument("--ranks", nargs="+", type=int, default=[1, 2, 4])
    ap.add_argument("--no-threads", action="store_true", help="skip the one-process thread runs")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a further case setting (e.g. solver.tolerance=1e-4 for a memory table at large sizes)")
    ap.add_argument("--json", help="write every summary to this file")
    a = ap.parse_args()
    results = {}
    print("| run | solve s | CG / friction steps | ms per CG iteration | transforms | reductions | "
          "solve peak MiB per rank | rank 0 peak MiB | friction coefficient |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n in a.sizes:
        runs = [] if a.no_threads else [(f"{n}² 1 process × 1 thread", 1, 0), (f"{n}² 1 process × 2 threads", 2, 0)]
        runs += [(f"{n}² mpirun -np {r} × 1 thread", 1, r) for r in a.ranks]
        for label, threads, ranks in runs:
            s = run(a.case, n, threads, ranks, a.set)
            results[label] = s
            print(row(label, s), flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
