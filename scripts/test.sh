#!/usr/bin/env bash
# Runs the whole test suite (C++ GoogleTest cases under CTest). Builds first if needed.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x build/gfmd_tests ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build -j"$(nproc)"
# Several test processes share the cores: let idle OpenMP threads sleep instead of spinning.
export OMP_WAIT_POLICY=PASSIVE
ctest --test-dir build --output-on-failure -j"$(nproc)"
