#!/usr/bin/env bash
# The CUDA backend's checks on a lent GPU machine (docs/gpu.md): the Device tests (device vs
# host on the example cases), then the benchmarks (bare cuFFT, rough sliding on the device
# and on 2 host cores). Needs build/gfmd, build/gfmd_tests, build/bench_cufft and
# .devcarry/devlibs.tar.xz (scripts/gpu_pack.sh). Writes its logs to $OUT (or /tmp/gpu_out).
#   bash scripts/gpu_check.sh [tests] [stress] [fig2e] [fig2e_seeds] [bench] [large] [cpu] [adhesion] [laws]
#   (default: tests bench cpu). stress: the stresses' time on the device and on the cores;
#   fig2e: the paper's Fig. 2(e) study at 2048^2 on the device, its runs only (the figure is
#   drawn where matplotlib is: gfmd study studies/fig2e.toml -o DIR --set 'solver.backend="cuda"'
#   reuses every finished run); fig2e_seeds: at 2048^2 the authors' surface over the study's ten
#   loads (studies/fig2e_authors.toml), then the eight-seed study at four loads (sweep.points=4),
#   each under its own timeout, the runs back as one tarball; large: 8192^2 and 16384^2 rough sliding with upwind2;
#   adhesion: the rough adhesive contact at 2048^2 on the device (adhesive and hard wall) and
#   on the machine's cores (BENCHMARKS.md, "Adhesion on the CUDA backend"); laws: tractive
#   rolling with a sharp static peak (the velocity law with stick) where the host did not settle
#   in 300 s (docs/solver.md, "Velocity weakening with stick").
set -uo pipefail
cd "$(dirname "$0")/.."
out=${OUT:-/tmp/gpu_out}
mkdir -p "$out"
steps=("$@")
failed=0
[ ${#steps[@]} -eq 0 ] && steps=(tests bench cpu)
has() { [[ " ${steps[*]} " == *" $1 "* ]]; }
tar -C /tmp -xJf .devcarry/devlibs.tar.xz
export LD_LIBRARY_PATH=/tmp/devlibs/lib:/usr/local/cuda/lib64:${LD_LIBRARY_PATH:-}
# The tests read the examples and run the program where they were built (the source path
# gpu_pack.sh recorded; /work/main by default).
for src in /work/main $(cat .devcarry/source_dir 2>/dev/null); do
  if [ ! -e "$src" ]; then mkdir -p "$(dirname "$src")" && ln -s "$PWD" "$src"; fi
done
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader | tee "$out/gpu.txt"
./build/gfmd --version || { echo "gfmd does not start here"; ldd ./build/gfmd | grep -i "not found"; exit 1; }
export OMP_WAIT_POLICY=PASSIVE PYTHONUNBUFFERED=1
if has tests; then
  timeout 300 ./build/gfmd_tests --gtest_filter='Device.*' 2>&1 | tee "$out/tests.txt"
  # A failure is reported and the other steps still run (their figures are needed either way).
  grep -q "FAILED" "$out/tests.txt" && { echo "device tests failed"; failed=1; }
fi
if has stress; then
  # Rough sliding with the stress summary on the device (stress_backend "cuda") and, for the
  # ratio, the same stresses on the machine's cores (a loose solve: only the stresses' time counts).
  for n in ${STRESS_SIZES:-2048 8192}; do
    timeout 200 python3 scripts/bench.py --backend cuda --cases rough --sizes $n --tolerance 1e-6 2>&1 |
      tee -a "$out/stress.txt"
  done
  for n in 2048 4096; do
    timeout 120 ./build/gfmd run examples/selfaffine.toml -o "/tmp/host_stress_$n" -q --set grid.nx=$n \
      --set indenter.lambda_short=$(python3 -c "print(16.0 / $n)") --set friction.coefficient=1 \
      --set load.pressure=0.01 --set output.fields=false --set output.png=false --set solver.tolerance=1e-2 \
      --set 'solver.backend="threads"' > /dev/null 2>&1 &&
      python3 -c "import json; s = json.load(open('/tmp/host_stress_$n/summary.json')); \
print(f'host stresses, rough {$n}^2, {s[\"threads\"]} threads: {s[\"stress_time_s\"]:.3f} s')" |
      tee -a "$out/stress.txt"
  done
fi
if has fig2e; then
  python3 -c 'import tomllib' || echo "python3 here lacks tomllib (3.11+): scripts/study.py cannot run"
  export GFMD="$PWD/build/gfmd"
  # No maps and no contact-patch analysis per point (the figure needs neither); the same sets
  # are given where the figure is drawn, so that every run is reused there. What comes back
  # from the lent machine is at most two folders deep: the runs travel as one tarball.
  ( time timeout "${FIG2E_TIMEOUT:-300}" python3 scripts/study.py studies/fig2e.toml -o /tmp/studies --runs-only \
      --set 'solver.backend="cuda"' --set output.png=false --set output.analysis=false ) 2>&1 | tee "$out/fig2e.txt"
  (cd /tmp && find studies \( -name summary.json -o -name status.json -o -name 'sweep.*' \) -print0 |
    xargs -0 tar -czf "$out/fig2e_runs.tgz")
fi
if has fig2e_seeds; then
  export GFMD="$PWD/build/gfmd"
  sets=(--set 'solver.backend="cuda"' --set output.png=false --set output.analysis=false)
  ( time timeout "${AUTHORS_TIMEOUT:-110}" python3 scripts/study.py studies/fig2e_authors.toml -o /tmp/studies \
      --runs-only "${sets[@]}" ) 2>&1 | tee "$out/fig2e_seeds.txt"
  ( time timeout "${SEEDS_TIMEOUT:-230}" python3 scripts/study.py studies/fig2e.toml -o /tmp/studies --runs-only \
      "${sets[@]}" --set sweep.points=4 ) 2>&1 | tee -a "$out/fig2e_seeds.txt"
  (cd /tmp && find studies \( -name summary.json -o -name status.json -o -name 'sweep.*' \) -print0 |
    xargs -0 tar -czf "$out/fig2e_seeds_runs.tgz")
fi
if has bench; then
  for n in 2048 4096 8192; do ./build/bench_cufft $n | tee -a "$out/cufft.txt"; done
  timeout 300 python3 scripts/bench.py --backend cuda --cases rough hertz --sizes 2048 4096 8192 \
    --tolerance 1e-6 2>&1 | tee "$out/bench_cuda.txt"
  # Where the time goes (the device synchronised at each phase): the 2048^2 rough case.
  GFMD_CUDA_PROFILE=1 ./build/gfmd run examples/selfaffine.toml -o /tmp/profile -q --set grid.nx=2048 \
    --set indenter.lambda_short=0.0078125 --set friction.coefficient=1 --set load.pressure=0.01 \
    --set output.fields=false --set output.png=false --set 'solver.backend="cuda"' --set solver.tolerance=1e-6 \
    2>&1 | tee "$out/profile.txt"
fi
if has large; then
  ./build/bench_cufft 16384 10 | tee -a "$out/cufft.txt"
  timeout "${LARGE_TIMEOUT:-400}" python3 scripts/bench.py --backend cuda --cases rough_upwind2 --sizes 8192 16384 \
    --tolerance 1e-6 2>&1 | tee "$out/bench_cuda_large.txt"
fi
if has adhesion; then
  # examples/adhesive_rough.toml at 2048^2 (lambda_s = 32 cells, as in BENCHMARKS.md's host rows),
  # one cold solve each: adhesive on the device, the hard wall alone (work 0) on the device, and
  # adhesive on the cores.
  for spec in "cuda 2e-5" "cuda 0" "threads 2e-5"; do
    set -- $spec
    dir=/tmp/adh_rough_$1_$2
    timeout "${ADHESION_TIMEOUT:-200}" ./build/gfmd run examples/adhesive_rough.toml -o "$dir" -q --set grid.nx=2048 \
      --set interaction.work_of_adhesion=$2 --set output.fields=false --set output.png=false \
      --set output.analysis=false --set "solver.backend=\"$1\"" > /dev/null 2>&1
    python3 -c "import json; s = json.load(open('$dir/summary.json')); \
print(f'rough adhesive 2048^2, {s[\"backend\"]}, work {$2}: {s[\"iterations\"]} CG iterations, ' \
      f'{s.get(\"adhesion_steps\", 0)} adhesive steps, {s[\"wall_time_s\"]:.2f} s, {s[\"threads\"]} threads, ' \
      f'area {s[\"relative_contact_area\"]:.4f}, force {s[\"normal_force\"]:.9g}, converged {s[\"converged\"]}')" |
      tee -a "$out/adhesion.txt" || echo "rough adhesive $spec: no summary" | tee -a "$out/adhesion.txt"
  done
fi
if has laws; then
  for spec in "128 0.1" "256 0.1" "128 0.01"; do
    set -- $spec
    dir=/tmp/peak_$1_$2
    timeout "${LAWS_TIMEOUT:-120}" ./build/gfmd run examples/rolling_static_peak.toml -o "$dir" -q --set grid.nx=$1 \
      --set friction.velocity_scale=$2 --set output.fields=false --set output.png=false \
      --set 'solver.backend="cuda"' > /dev/null 2>&1
    python3 -c "import json; s = json.load(open('$dir/summary.json')); \
print(f'static peak {$1}^2, v_c {$2}, {s[\"backend\"]}: {s[\"iterations\"]} CG iterations, {s[\"outer_iterations\"]} friction steps, ' \
      f'{s[\"tangential_iterations\"]} splitting steps, {s[\"wall_time_s\"]:.2f} s, stick fraction {s[\"stick_fraction\"]:.4f}, ' \
      f'tangential force {s[\"tangential_force\"]:.9g}, converged {s[\"converged\"]}')" |
      tee -a "$out/laws.txt" || echo "static peak $spec: no summary (timed out?)" | tee -a "$out/laws.txt"
  done
fi
if has cpu; then
  timeout 300 python3 scripts/bench.py --backend threads --threads 2 --cases rough --sizes 2048 \
    --tolerance 1e-6 2>&1 | tee "$out/bench_cpu2.txt"
fi
exit $failed
