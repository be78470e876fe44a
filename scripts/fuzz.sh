#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan; in build-clang/, shared with
# scripts/test-sanitized.sh) and runs each for N seconds
# (default 60) on its seed corpus in fuzz/corpus/<target>. Exits non-zero on any finding.
#   bash scripts/fuzz.sh [seconds]
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-60}"
bash scripts/configure-clang.sh
cmake --build build-clang -j"$(nproc)" --target fuzz_config fuzz_topography_text fuzz_height_file fuzz_master_curve fuzz_run
# A hostile NetCDF header makes libnetcdf ask calloc for exabytes: in production calloc
# returns NULL and nc_open reports "Memory allocation failure" (an InputError here), so the
# sanitizer's allocator must return NULL too instead of reporting. Our own oversized
# allocations would still end the process (std::bad_alloc escapes the target): a finding.
# intercept_tls_get_addr=0: see scripts/test-sanitized.sh (a misread dynamic-TLS range can
# crash the leak scan at exit).
export ASAN_OPTIONS="allocator_may_return_null=1:intercept_tls_get_addr=0:${ASAN_OPTIONS:-}"
# Inputs that once crashed must stay fixed.
for t in config topography_text height_file master_curve; do
  for f in fuzz/regressions/${t}_*; do
    [ -e "$f" ] || continue
    ./build-clang/fuzz_$t "$f" > /dev/null 2>&1 || { echo "regression $f fails"; exit 1; }
  done
done
for t in config topography_text height_file master_curve run; do
  work=$(mktemp -d)
  cp -r "fuzz/corpus/$t/." "$work/"
  echo "fuzz_$t: ${secs} s"
  ./build-clang/fuzz_$t "$work" -max_total_time="$secs" -max_len=4096 -timeout=10 -rss_limit_mb=4096 \
    -print_final_stats=1 2>&1 | grep -E "stat::number_of_executed_units|stat::new_units_added|ERROR|SUMMARY|Done" || true
  found=$(compgen -G "crash-*" ; compgen -G "leak-*" ; compgen -G "timeout-*" ; compgen -G "oom-*") || true
  if [ -n "$found" ]; then
    echo "fuzz_$t: findings saved in $(pwd): $found"
    exit 1
  fi
  rm -rf "$work"
done
echo "fuzzing: no findings"
