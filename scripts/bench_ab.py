#!/usr/bin/python3
"""Before/after: two gfmd programs on the BENCHMARKS cases (Hertz sliding, rough sliding), run
alternately --repeat times each at one size; prints the iterations, friction steps and the
median solve time (summary.json wall_time_s) with its spread, the ratio, and whether the
friction coefficients agree bit for bit.

    /usr/bin/python3 scripts/bench_ab.py --before OLD/gfmd [--after build/gfmd] [--size 512] [--repeat 3]
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def cases(n):
    return {
        "hertz": ("examples/hertz_sliding.toml", []),
        "rough": ("examples/selfaffine.toml",
                  [f"indenter.lambda_short={16.0 / n:.10g}", "friction.coefficient=1", "load.pressure=0.01"]),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", required=True)
    ap.add_argument("--after", default=os.path.join(ROOT, "build", "gfmd"))
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    programs = {"before": a.before, "after": a.after}
    env = dict(os.environ, OMP_WAIT_POLICY="PASSIVE")
    print(f"| case ({a.size}^2) | build | iterations | friction steps | solve s (median of {a.repeat}) |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, (case, sets) in cases(a.size).items():
            times = {"before": [], "after": []}
            last = {}
            for _ in range(a.repeat):
                for side, program in programs.items():
                    out = os.path.join(tmp, f"{name}_{side}")
                    args = [program, "run", os.path.join(ROOT, case), "-o", out, "--force", "-q"]
                    for s in [f"grid.nx={a.size}", "output.fields=false", "output.png=false", "output.analysis=false",
                              f"solver.threads={a.threads}"] + sets:
                        args += ["--set", s]
                    subprocess.run(args, check=True, env=env)
                    with open(os.path.join(out, "summary.json")) as f:
                        s = json.load(f)
                    times[side].append(s["wall_time_s"])
                    last[side] = s
            for side in programs:
                t = times[side]
                print(f"| {name} | {side} | {last[side]['iterations']} | {last[side]['outer_iterations']} | "
                      f"{statistics.median(t):.3f} ({min(t):.3f}-{max(t):.3f}) |")
            ratio = statistics.median(times["after"]) / statistics.median(times["before"])
            same = last["before"].get("friction_coefficient") == last["after"].get("friction_coefficient")
            print(f"| {name} | after / before | | | {ratio:.3f} (same friction coefficient: {same}) |")


if __name__ == "__main__":
    main()
