#!/usr/bin/env python3
"""Python API against the command line on the same case: wall time and peak memory.

Each side runs in its own process (so that peak RSS is its own): the CLI as
`gfmd run CASE -o DIR` (fields.nc written, so that it too keeps every field; no maps), Python as
gfmd.Topography.self_affine(...) + gfmd.solve(...) with the same parameters. Reported: the
solve's own wall time (summary wall_time_s, same C++ code on both sides), the end-to-end time
of the process, the Python call's time around the solve, and peak RSS; each side runs twice,
alternating, and the faster run counts.

    /usr/bin/python3 scripts/bench_python.py --nx 2048 [--build build] [--threads 2]
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CASE = """[grid]
nx = {nx}
lx = 1.0
[elastic]
poisson = 0.3
[indenter]
type = "selfaffine"
hurst = 0.8
lambda_long = 0.5
lambda_short = {ls!r}
rms_height = 0.01
seed = 0
[load]
pressure = 0.01
[friction]
coefficient = 0.5
[solver]
threads = {threads}
tolerance = 1e-6
[stress]
profiles = false
[output]
fields = true
png = false
"""

PY = """
import json, resource, sys, time
sys.path.insert(0, {pydir!r})
import gfmd
t0 = time.perf_counter()
top = gfmd.Topography.self_affine(nx={nx}, lx=1.0, hurst=0.8, lambda_long=0.5, lambda_short={ls!r},
                                  rms_height=0.01, seed=0)
t1 = time.perf_counter()
r = gfmd.solve(top, gfmd.ElasticBody(poisson=0.3), pressure=0.01, friction=0.5,
               threads={threads}, tolerance=1e-6)
t2 = time.perf_counter()
s = r.summary
print(json.dumps({{"solve_s": s["wall_time_s"], "call_s": t2 - t1, "topography_s": t1 - t0,
                  "iterations": s["iterations"], "mu": s["friction_coefficient"],
                  "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}}))
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nx", type=int, default=2048)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    a = ap.parse_args()
    ls = 4.0 / a.nx  # lambda_short = 4 dx
    env = dict(os.environ, OMP_WAIT_POLICY="PASSIVE")
    with tempfile.TemporaryDirectory() as tmp:
        case = os.path.join(tmp, "case.toml")
        with open(case, "w") as f:
            f.write(CASE.format(nx=a.nx, ls=ls, threads=a.threads))
        runs = {"cli": [], "py": []}
        for rep in range(2):
            out = os.path.join(tmp, f"cli{rep}")
            t0 = time.perf_counter()
            before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
            subprocess.run([os.path.join(a.build, "gfmd"), "run", case, "-o", out, "-q"], check=True, env=env)
            total = time.perf_counter() - t0
            peak = max(before, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss) / 1024
            with open(os.path.join(out, "summary.json")) as f:
                runs["cli"].append((total, peak, json.load(f)))
            t0 = time.perf_counter()
            p = subprocess.run([sys.executable, "-c", PY.format(pydir=os.path.join(a.build, "python"), nx=a.nx,
                                                                ls=ls, threads=a.threads)],
                               check=True, env=env, capture_output=True, text=True)
            runs["py"].append((time.perf_counter() - t0, json.loads(p.stdout.strip().splitlines()[-1])))
        cli_total, cli_peak, cli = min(runs["cli"], key=lambda r: r[2]["wall_time_s"])
        py_total, py = min(runs["py"], key=lambda r: r[1]["solve_s"])
        # RUSAGE_CHILDREN is the largest child so far: the CLI's peak is that of its first run
        # unless a Python child was larger; the Python side reports its own.
        cli_peak = runs["cli"][0][1]
    same = py["mu"] == cli["friction_coefficient"] and py["iterations"] == cli["iterations"]
    print(f"nx = {a.nx}, threads = {a.threads}, rough sliding (mu_c = 0.5) on a nu = 0.3 half-space, p = 0.01 E*")
    print("| side | solve s (in C++) | around the solve s | process s | peak MiB |")
    print("|---|---|---|---|---|")
    print(f"| CLI | {cli['wall_time_s']:.2f} | – | {cli_total:.2f} | {cli_peak:.0f} |")
    print(f"| Python | {py['solve_s']:.2f} | {py['call_s']:.2f} | {py_total:.2f} | {py['peak_mib']:.0f} |")
    print(f"Python solve() call / CLI solve: {py['call_s'] / cli['wall_time_s']:.3f}; "
          f"process: {py_total / cli_total:.3f}; peak memory: {py['peak_mib'] / cli_peak:.3f}; "
          f"same numbers: {same}")


if __name__ == "__main__":
    main()
