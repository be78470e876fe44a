#!/usr/bin/python3
"""End-to-end benchmark: iterations, time per iteration, total time and peak memory of
gfmd solves, next to the bare-FFT time of one iteration (3 forward + 3 inverse real 2D
transforms, plain FFTW executes) measured by bench_kernels right before and right after each
solve, so that the ratio compares the two at the same moment. Prints a Markdown table.

    /usr/bin/python3 scripts/bench.py --sizes 256 512 [--cases hertz rough] [--threads 2] [--planner measure]
                                      [--repeat 3]

With --planner measure the solver's FFTW plans are measured (solver.fft_planner) and kept
as wisdom (see include/gfmd/core/fft.hpp); a first, untimed solve per size makes the wisdom so
that the timed solve does not include planning.

With --backend cuda the solves run on the GPU (solver.backend = "cuda") and the bare time is
that of cuFFT's 3 + 3 double-precision transforms (build/bench_cufft, CUDA events); the
memory columns are then the device memory the solve held (summary.json's
device_memory_bytes), not the host's.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GFMD = os.path.join(ROOT, "build", "gfmd")
KERNELS = os.path.join(ROOT, "build", "bench_kernels")
CUFFT = os.path.join(ROOT, "build", "bench_cufft")

CASES = {
    # Hertz sliding, paper Fig. 2: L = 4R, F = 0.01 E* R^2, nu = 0.25, mu_c = 1.
    "hertz": ("examples/hertz_sliding.toml", lambda n: []),
    # Self-affine sliding against a confined layer: dx = lambda_s/8 at every size.
    "rough": ("examples/selfaffine.toml",
              lambda n: [f"indenter.lambda_short={16.0 / n:.10g}",
                         "friction.coefficient=1", "load.pressure=0.01"]),
    # Stick-slip: the paper's Fig. 2(e) thin layer (nu = 0.49, h = 0.05 lambda_l, mu_c = 1),
    # lambda_s = 8 dx, at a load without stick (0.01 E*) and one with stick (0.1 E*).
    "thin_p0.01": ("examples/fig2e_rough_layer_sweep.toml",
                   lambda n: [f"indenter.lambda_short={16.0 / n:.10g}", "elastic.thickness=0.05",
                              "load.pressure=0.01"]),
    "thin_p0.1": ("examples/fig2e_rough_layer_sweep.toml",
                  lambda n: [f"indenter.lambda_short={16.0 / n:.10g}", "elastic.thickness=0.05",
                             "load.pressure=0.1"]),
    # The same two loads with the second-order upwind slip derivative (docs/solver.md).
    "thin_p0.01_upwind2": ("examples/fig2e_rough_layer_sweep.toml",
                           lambda n: [f"indenter.lambda_short={16.0 / n:.10g}", "elastic.thickness=0.05",
                                      "load.pressure=0.01", 'friction.slip_derivative="upwind2"']),
    "thin_p0.1_upwind2": ("examples/fig2e_rough_layer_sweep.toml",
                          lambda n: [f"indenter.lambda_short={16.0 / n:.10g}", "elastic.thickness=0.05",
                                     "load.pressure=0.1", 'friction.slip_derivative="upwind2"']),
    # p = 0.1 E* with Anderson mixing of the stick-slip splitting (friction.stick_acceleration,
    # opt-in; docs/solver.md).
    "thin_p0.1_upwind2_accel": ("examples/fig2e_rough_layer_sweep.toml",
                                lambda n: [f"indenter.lambda_short={16.0 / n:.10g}", "elastic.thickness=0.05",
                                           "load.pressure=0.1", 'friction.slip_derivative="upwind2"',
                                           "friction.stick_acceleration=5"]),
    # The rough case with the second-order upwind slip derivative: where the large grids meet a
    # few points near stick, the stick-slip splitting settles in fewer steps (docs/solver.md).
    "rough_upwind2": ("examples/selfaffine.toml",
                      lambda n: [f"indenter.lambda_short={16.0 / n:.10g}", "friction.coefficient=1",
                                 "load.pressure=0.01", 'friction.slip_derivative="upwind2"']),
    "hertz_frictionless": ("examples/hertz_nu025.toml", lambda n: []),
    "rough_frictionless": ("examples/selfaffine.toml",
                           lambda n: [f"indenter.lambda_short={16.0 / n:.10g}", "load.pressure=0.01"]),
}


def fft_time(n, threads, planner, backend="threads"):
    """Seconds of one bare-FFT iteration (3 + 3 real 2D transforms) of an n x n grid."""
    if backend == "cuda":
        out = subprocess.run([CUFFT, str(n)], capture_output=True, text=True, check=True).stdout
        return json.loads(out)["seconds"]
    name = f"BM_FFTIteration/{n}/{threads}/{1 if planner == 'measure' else 0}"
    out = subprocess.run([KERNELS, f"--benchmark_filter=^{name}/", "--benchmark_format=json"],
                         capture_output=True, text=True, check=True).stdout
    for b in json.loads(out)["benchmarks"]:
        if b["name"].startswith(name):
            return b["real_time"] / 1e3  # ms -> s
    return float("nan")


def run_case(case, n, threads, tol, planner="estimate", backend="threads"):
    path, extra = CASES[case]
    with tempfile.TemporaryDirectory() as d:
        cmd = [GFMD, "run", os.path.join(ROOT, path), "-o", d, "-q",
               "--set", f"grid.nx={n}", "--set", f"solver.threads={threads}", "--set", f"solver.tolerance={tol}",
               "--set", "output.fields=false", "--set", "output.png=false",
               "--set", f"solver.fft_planner={planner}", "--set", f'solver.backend="{backend}"']
        for e in extra(n):
            cmd += ["--set", e]
        # The child's peak resident memory from its own resource usage (wait4).
        with tempfile.TemporaryFile("w+") as log:
            p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
            _, status, usage = os.wait4(p.pid, 0)
            p.returncode = os.waitstatus_to_exitcode(status)
            log.seek(0)
            text = log.read()
        if p.returncode != 0:
            return {"error": text}
        rss_kb = usage.ru_maxrss
        s = json.load(open(os.path.join(d, "summary.json")))
        s["peak_rss_bytes"] = rss_kb * 1024
        return s


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
    ap.add_argument("--cases", nargs="+", default=["hertz", "rough"], choices=sorted(CASES))
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--tolerance", type=float, default=1e-6)
    ap.add_argument("--planner", choices=["estimate", "measure"], default="estimate")
    ap.add_argument("--backend", choices=["threads", "cuda"], default="threads",
                    help="cuda: the solves on the GPU, the bare transforms timed with cuFFT (build/bench_cufft)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="timed solves per case and size; the row shows the one with the median ratio")
    args = ap.parse_args()
    print(f"backend = {args.backend}, threads = {args.threads}, tolerance = {args.tolerance}, "
          f"FFTW planner = {args.planner}, repeat = {args.repeat}")
    print("bare 3+3 FFT: measured right before and right after each solve, the mean is used; "
          "in-solve: the solve's wall time over the time its own transforms took\n")
    print("| case | N | CG iterations | friction steps | FFTs | solve s | ms / CG iteration "
          "| bare 3+3 FFT ms (before/after) | solve time / bare time of its FFTs (range) "
          "| solve time / in-solve FFT time (range) | peak MiB | bytes / point |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for case in args.cases:
        for n in args.sizes:
            if args.planner == "measure":
                run_case(case, n, args.threads, 0.5, args.planner)  # makes the wisdom
            rows = []
            for _ in range(max(1, args.repeat)):
                f0 = fft_time(n, args.threads, args.planner, args.backend)
                s = run_case(case, n, args.threads, args.tolerance, args.planner, args.backend)
                f1 = fft_time(n, args.threads, args.planner, args.backend)
                if "error" in s:
                    break
                nfft = s.get("fft_count", 0)
                t = s["wall_time_s"]
                ratio = t / (nfft / 6.0 * 0.5 * (f0 + f1)) if nfft else float("nan")
                tin = s.get("fft_time_s", 0.0)
                ratio_in = t / tin if tin > 0 else float("nan")
                rows.append((ratio, ratio_in, f0, f1, s))
            if not rows or "error" in s:
                print(f"| {case} | {n} | failed: {s['error'].strip().splitlines()[-1]} |")
                continue
            rows.sort(key=lambda r: r[0])
            ratio, ratio_in, f0, f1, s = rows[len(rows) // 2]
            lo, hi = rows[0][0], rows[-1][0]
            ins = sorted(r[1] for r in rows)
            it = s["iterations"]
            t = s["wall_time_s"]
            rng = f" ({lo:.2f}–{hi:.2f})" if len(rows) > 1 else ""
            rng_in = f" ({ins[0]:.2f}–{ins[-1]:.2f})" if len(rows) > 1 else ""
            steps = f"{s.get('outer_iterations', 0)}"
            if s.get("tangential_iterations"):
                steps += f" (+{s['tangential_iterations']} splitting, stick {100 * s.get('stick_fraction', 0):.2f} %)"
            dev = s.get("device_memory_bytes", 0)
            mem = (f"| {dev / 2**20:.0f} (device) | {dev / n / n:.0f} (device) |" if dev else
                   f"| {s['peak_rss_bytes'] / 2**20:.0f} | {s['peak_rss_bytes'] / n / n:.0f} |")
            print(f"| {case} | {n} | {it} | {steps} | {s.get('fft_count', 0)} | {t:.3f} "
                  f"| {t / max(it, 1) * 1e3:.2f} | {f0 * 1e3:.2f}/{f1 * 1e3:.2f} | {ratio:.2f}{rng} "
                  f"| {ratio_in:.2f}{rng_in} " + mem)
            # The stresses after the solve (surface stresses and their summary; on the device
            # with the cuda backend where summary.json says stress_backend = "cuda").
            if "stress_time_s" in s:
                print(f"|   stresses: {s['stress_time_s']:.3f} s on {s.get('stress_backend', 'the host')} |")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
