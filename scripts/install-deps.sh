#!/usr/bin/env bash
# Installs every build and run-time dependency of gfmd from Debian's packages.
# Safe to run repeatedly; needs root (or sudo) on a Debian 12 machine.
set -euo pipefail
PKGS=(
  build-essential cmake pkg-config
  libfftw3-dev            # FFTs (with the threads library)
  libnetcdf-dev           # fields.nc and NetCDF topographies
  libhdf5-dev             # H5dont_atexit (NetCDF-4 storage; see src/io/netcdf.cpp)
  libzip-dev libxml2-dev  # x3p height maps (ISO 25178-72: zip + XML)
  nlohmann-json3-dev      # summary.json
  libcli11-dev            # command line
  libtoml11-dev           # case files
  libgtest-dev libgmock-dev libbenchmark-dev
  libhypre-dev            # Reynolds flow linear solves
  libopenmpi-dev openmpi-bin libfftw3-mpi-dev   # distributed runs: mpirun, FFTW-MPI (docs/mpi.md)
  python3-numpy python3-matplotlib python3-netcdf4 python3-pytest pybind11-dev python3-dev
  python3-pip python3-setuptools python3-wheel python3-tqdm   # pip install . (offline) and progress bars
  clang-14 libclang-rt-14-dev libomp-14-dev   # fuzzing (libFuzzer) and sanitizers
  clang-format            # style check (scripts/check-format.sh)
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PKGS[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
