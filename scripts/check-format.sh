#!/usr/bin/env bash
# Fails if any C++ source of the project differs from clang-format's output (.clang-format).
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.cu' '*.cuh')
clang-format --dry-run --Werror "${files[@]}"
echo "check-format: ${#files[@]} files clean"
