#!/usr/bin/env bash
# Configures build-clang/: clang 14 with AddressSanitizer + UBSan and libFuzzer's coverage
# instrumentation (GFMD_FUZZ), tests included. scripts/test-sanitized.sh builds the tests there and
# scripts/fuzz.sh the fuzz targets, over one instrumented library. (The coverage hooks cost the
# tests nothing but time: outside a fuzzer the sanitizer runtime's default hooks do nothing.)
set -euo pipefail
cd "$(dirname "$0")/.."
CC=clang-14 CXX=clang++-14 cmake -S . -B build-clang -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGFMD_SANITIZE=ON \
  -DGFMD_FUZZ=ON -DGFMD_BUILD_TESTS=ON > /dev/null
