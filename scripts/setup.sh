#!/usr/bin/env bash
# One command for a newcomer: installs the dependencies (Debian packages), builds gfmd
# and runs a real example (a Hertz sphere sliding with friction), printing its results.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
./build/gfmd run examples/hertz_sliding.toml -o out/hertz_sliding
