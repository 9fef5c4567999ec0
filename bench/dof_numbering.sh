#!/bin/bash
# deal.II's DoF numbering with two elements in the mesh against one
# (bench/dof_numbering.cc; doc/adaptivity.md, "Not yet"): builds the program
# against the installed deal.II in a temporary folder and runs it on RANKS
# ranks (default 2) on a mesh of NX x NY x NZ cells (default 100 x 200 x 10,
# the Kalthoff-Winkler plate at 1 mm).
#
# usage: bench/dof_numbering.sh [RANKS [NX NY NZ]]
set -eu -o pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ranks=${1:-2}
shift || true
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cat > "$work/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.13)
find_package(deal.II REQUIRED)
deal_ii_initialize_cached_variables()
project(dof_numbering CXX)
add_executable(dof_numbering $here/dof_numbering.cc)
deal_ii_setup_target(dof_numbering RELEASE)
CMAKE
cmake -S "$work" -B "$work/build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$work/build" > /dev/null
mpirun -np "$ranks" "$work/build/dof_numbering" "$@"
