#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan; in build-clang/, shared with
# scripts/test-sanitized.sh) and runs each for N seconds
# (default 60) on its seed corpus in fuzz/corpus/<target>, nproc targets at once. Exits non-zero
# on any finding (saved in fuzz-findings/<target>/).
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
# The targets run nproc at a time (libFuzzer is single-threaded): each in its own copy of the
# corpus, writing any finding (crash-*, leak-*, timeout-*, oom-*) into its own folder, its
# report printed when all have ended.
jobs=$(nproc)
root=$(mktemp -d)
# Stopped early (an error, a signal): the fuzzers already started stop too, before their folders go.
stop_fuzzers() {
  for f in "$root"/*/pid; do
    [ -e "$f" ] && kill "$(cat "$f")" 2> /dev/null
  done
  wait 2> /dev/null
  rm -rf "$root"
}
trap 'stop_fuzzers || true' EXIT
trap 'exit 143' TERM HUP INT
targets=(config topography_text height_file master_curve run)
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  mkdir -p "$root/$t/corpus" "$root/$t/findings"
  cp -r "fuzz/corpus/$t/." "$root/$t/corpus/"
  (
    ./build-clang/fuzz_$t "$root/$t/corpus" -max_total_time="$secs" -max_len=4096 -timeout=10 \
      -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$root/$t/findings/" > "$root/$t/log" 2>&1 &
    echo $! > "$root/$t/pid"
    rc=0
    wait $! || rc=$?
    echo "$rc" > "$root/$t/rc"
  ) &
done
wait || true
failed=0
for t in "${targets[@]}"; do
  echo "fuzz_$t: ${secs} s"
  grep -E "stat::number_of_executed_units|stat::new_units_added|ERROR|SUMMARY|Done" "$root/$t/log" || true
  # Findings are crash-, leak-, timeout- and oom- files (libFuzzer also writes slow-unit- files
  # there: a unit above 10 s that its timeout did not catch; not a finding).
  found=$(cd "$root/$t/findings" && compgen -G "crash-*"; compgen -G "leak-*"; compgen -G "timeout-*"; compgen -G "oom-*") || true
  if [ -n "$found" ]; then
    mkdir -p fuzz-findings/$t
    cp "$root/$t/findings/"* fuzz-findings/$t/
    echo "fuzz_$t: findings saved in $(pwd)/fuzz-findings/$t: $(echo $found)"
    failed=1
  elif [ "$(cat "$root/$t/rc" 2>/dev/null || echo missing)" != 0 ]; then
    echo "fuzz_$t: exited with status $(cat "$root/$t/rc" 2>/dev/null || echo unknown) without a finding:"
    tail -n 20 "$root/$t/log"
    failed=1
  fi
done
[ "$failed" = 0 ] || exit 1
echo "fuzzing: no findings"
