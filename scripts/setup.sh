#!/usr/bin/env bash
# One command for a newcomer: installs the dependencies (Debian packages), builds gfmd,
# installs the Python package gfmd (import gfmd; the console script gfmd) from that build,
# and runs a real example (a Hertz sphere sliding with friction), printing its results.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
# Debian's Python, offline, from the build above (setup.py builds only the package's targets
# there). --break-system-packages lets pip install into its own area beside Debian's
# (/usr/local as root, ~/.local otherwise); pip uninstall gfmd removes it.
GFMD_BUILD_DIR="$PWD/build" /usr/bin/python3 -m pip install --quiet --no-build-isolation --no-index \
  --break-system-packages --root-user-action=ignore .
(cd / && /usr/bin/python3 -c "import gfmd; print('Python package gfmd', gfmd.__version__, 'in', gfmd.__file__)")
./build/gfmd run examples/hertz_sliding.toml -o out/hertz_sliding
