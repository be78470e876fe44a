#!/usr/bin/env bash
# Packs what the device checks need on a lent GPU machine, which has the CUDA toolkit but
# none of our Debian libraries: the shared libraries of build/gfmd and build/gfmd_tests
# and build/bench_kernels (cuFFT and the driver excepted: the machine has its own) into .devcarry/devlibs.tar.xz, with
# glibc and its loader apart in sys/ for a machine whose C library is older. Then:
#   run(command="bash scripts/gpu_check.sh", carry=[".devcarry", "build/gfmd", "build/gfmd_tests", "build/bench_cufft", "build/bench_kernels"])
set -euo pipefail
cd "$(dirname "$0")/.."
grep -qx '/.devcarry/' .git/info/exclude 2>/dev/null || echo '/.devcarry/' >> .git/info/exclude
tmp=$(mktemp -d)
mkdir -p "$tmp/devlibs/lib" "$tmp/devlibs/sys" .devcarry
for b in build/gfmd build/gfmd_tests build/bench_kernels; do ldd "$b" | awk '$3 ~ /^\// {print $3}'; done | sort -u | grep -v -e cufft -e libcuda |
  while read -r l; do
    case $(basename "$l") in
      libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|librt.so.*|libstdc++.so.*|libgcc_s.so.*|libresolv.so.*)
        cp -L "$l" "$tmp/devlibs/sys/" ;;
      *) cp -L "$l" "$tmp/devlibs/lib/" ;;
    esac
  done
cp -L /lib64/ld-linux-x86-64.so.2 "$tmp/devlibs/sys/"
tar -C "$tmp" -cJf .devcarry/devlibs.tar.xz devlibs
# The tests read the examples through the source path they were built from: gpu_check.sh links it.
sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' build/CMakeCache.txt > .devcarry/source_dir
rm -rf "$tmp"
ls -la .devcarry/devlibs.tar.xz
