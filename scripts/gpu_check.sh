#!/usr/bin/env bash
# The CUDA backend's checks on a lent GPU machine (docs/gpu.md): the Device tests (device vs
# host on the example cases), then the benchmarks (bare cuFFT, rough sliding on the device
# and on 2 host cores). Needs build/gfmd, build/gfmd_tests, build/bench_cufft and
# .devcarry/devlibs.tar.xz (scripts/gpu_pack.sh). Writes its logs to $OUT (or /tmp/gpu_out).
#   bash scripts/gpu_check.sh [tests] [bench] [large] [cpu]     (default: all but large)
set -uo pipefail
cd "$(dirname "$0")/.."
out=${OUT:-/tmp/gpu_out}
mkdir -p "$out"
steps=("$@")
[ ${#steps[@]} -eq 0 ] && steps=(tests bench cpu)
has() { [[ " ${steps[*]} " == *" $1 "* ]]; }
tar -C /tmp -xJf .devcarry/devlibs.tar.xz
export LD_LIBRARY_PATH=/tmp/devlibs/lib:/usr/local/cuda/lib64:${LD_LIBRARY_PATH:-}
# The tests read the examples and run the program where they were built.
if [ ! -e /work/main ]; then mkdir -p /work && ln -s "$PWD" /work/main; fi
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader | tee "$out/gpu.txt"
./build/gfmd --version || { echo "gfmd does not start here"; ldd ./build/gfmd | grep -i "not found"; exit 1; }
export OMP_WAIT_POLICY=PASSIVE PYTHONUNBUFFERED=1
if has tests; then
  timeout 300 ./build/gfmd_tests --gtest_filter='Device.*' 2>&1 | tee "$out/tests.txt"
  grep -q "FAILED" "$out/tests.txt" && { echo "device tests failed"; exit 1; }
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
  timeout 400 python3 scripts/bench.py --backend cuda --cases rough --sizes 16384 --tolerance 1e-6 2>&1 |
    tee "$out/bench_cuda_large.txt"
fi
if has cpu; then
  timeout 300 python3 scripts/bench.py --backend threads --threads 2 --cases rough --sizes 2048 \
    --tolerance 1e-6 2>&1 | tee "$out/bench_cpu2.txt"
fi
