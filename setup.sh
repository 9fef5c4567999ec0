#!/usr/bin/env bash
# PeriDeal's one set-up entry point.
#
#   ./setup.sh run    install what is missing, build pd_app, run the default example
#   ./setup.sh test   install what is missing, build everything, run the test suite (ctest -j nproc)
#
# Installs Debian packages with apt-get (with sudo when not root) only when
# some are missing, configures build/ (CMake, Release) and builds with all
# cores. A second call rebuilds nothing that is up to date.
# PERIDEAL_BUILD_DIR overrides the build directory (default: build/ here).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build=${PERIDEAL_BUILD_DIR:-$here/build}
example=$here/doc/examples/fragmenting_cylinder_reduced
jobs=$(nproc)

# What the build and the tests need (Debian 12). LAMMPS and ParaView are not
# here: the benchmarks and the picture rendering install their own.
packages=(cmake g++ make libdeal.ii-dev openmpi-bin libmuparser-dev libexodusii-dev gmsh numdiff python3 python3-h5py python3-netcdf4)

# Open MPI refuses to run as root, and more ranks than cores, unless told.
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
# Containers often forbid the cross-memory attach of Open MPI's shared memory.
export OMPI_MCA_btl_vader_single_copy_mechanism=none

usage() {
  sed -n '2,5s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"
}

install_missing() {
  local missing=() p
  for p in "${packages[@]}"; do
    # grep reads all of dpkg's output (no -q): an early exit would give dpkg
    # a SIGPIPE, which pipefail would take for a missing package.
    dpkg -s "$p" 2>/dev/null | grep '^Status: install ok installed' >/dev/null ||
      missing+=("$p")
  done
  if [[ ${#missing[@]} -eq 0 ]]; then
    echo "setup.sh: all packages installed"
    return
  fi
  echo "setup.sh: installing ${missing[*]}"
  local sudo=()
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null ||
      { echo "setup.sh: not root and no sudo: install ${missing[*]} by hand" >&2; exit 1; }
    sudo=(sudo)
  fi
  "${sudo[@]}" apt-get update
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${missing[@]}"
}

# configure_and_build [TARGET]: configure build/ and build TARGET (pd_app
# for the example), or everything (the test programs too).
configure_and_build() {
  cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" --parallel "$jobs" ${1:+--target "$1"}
}

case "${1:-}" in
  run)
    install_missing
    configure_and_build pd_app
    [[ -f $example/params.prm ]] ||
      { echo "setup.sh: the default example $example/params.prm is missing" >&2; exit 1; }
    cd "$example"
    echo "setup.sh: running mpirun -np $jobs $build/pd_app params.prm in $example"
    mpirun -np "$jobs" "$build/pd_app" params.prm
    ;;
  test)
    install_missing
    configure_and_build
    cd "$build"
    # Each test's PROCESSORS property is its rank count: ctest -j runs a
    # 2-rank test alone on 2 cores, 1-rank tests side by side.
    ctest --output-on-failure -j "$jobs"
    ;;
  -h | --help | help)
    usage
    ;;
  *)
    usage >&2
    exit 2
    ;;
esac
