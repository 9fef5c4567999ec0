#!/bin/bash
# Runs the notched plate coupled, all-PD, adaptive and adaptive on a coarse mesh
# (adaptive_refined.prm), one after the other on
# the same ranks, and prints the comparison tables of README.md (compare.py,
# tip_times.py).
#
# usage: doc/examples/notched_plate/run.sh [ranks (default 2)] [pd_app (default build/pd_app)]
# Output in doc/examples/notched_plate/output/, logs coupled.log and all_pd.log
# beside the parameter files. About 2 minutes on 2 cores.
set -eu -o pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ranks=${1:-2}
pd_app=${2:-$here/../../../build/pd_app}
cd "$here"
for run in coupled all_pd adaptive adaptive_refined; do
  echo "running $run.prm on $ranks ranks ..."
  mpirun -np "$ranks" "$pd_app" "$run.prm" > "$run.log"
done
python3 compare.py .
# The runs that start with PD only at the notch (adaptive*.prm) beside the two.
python3 tip_times.py output/all_pd.globals.csv output/coupled.globals.csv output/adaptive.globals.csv \
  output/adaptive_refined.globals.csv
