#!/usr/bin/env bash
# Runs the whole test suite: C++ GoogleTest cases under CTest, then the Python end-to-end
# study checks under pytest. Builds first if needed.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x build/gfmd_tests ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build -j"$(nproc)"
# Several test processes share the cores: let idle OpenMP threads sleep instead of spinning.
export OMP_WAIT_POLICY=PASSIVE
ctest --test-dir build --output-on-failure -j"$(nproc)"
# End-to-end checks of the quick studies (Debian's Python with numpy and matplotlib).
/usr/bin/python3 -m pytest -q tests/python
