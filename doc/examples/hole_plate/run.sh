#!/bin/bash
# Runs the plate with the off-centre hole all-PD and adaptive at each spacing,
# one after the other on the same ranks, and prints the table of README.md
# (analyze.py), which also draws hole_plate.png.
#
# usage: doc/examples/hole_plate/run.sh [ranks (default 2)] [pd_app (default build/pd_app)] [spacings in mm (default "0.5 0.25")]
#        [scenes (default "all_pd adaptive")]
# Output in doc/examples/hole_plate/output/<run>-<spacing>mm/ with its log.
set -eu -o pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ranks=${1:-2}
pd_app=$(realpath "${2:-$here/../../../build/pd_app}")
spacings=${3:-0.5 0.25}
scenes=${4:-all_pd adaptive}
for h in $spacings; do
  for scene in $scenes; do
    run=$here/output/$scene-${h}mm
    mkdir -p "$run"
    # The spacing h mm: cells 4 h (refined twice to h), 100/(4 h) x 40/(4 h),
    # one cell thick (4 points, 4 h); horizon 4 h; the body force on the
    # outermost row 3 MPa / h.
    read -r nx ny thick delta force row < <(python3 -c "h = $h; print(round(25 / h), round(10 / h), '%.6g' % (4e-3 * h), '%.6g' % (4e-3 * h), '%.6g' % (1e-3 * h), '%.6g' % (0.02 - 0.6e-3 * h))")
    sed -e "s|set Subdivisions = 100, 40, 1|set Subdivisions = $nx, $ny, 1|" \
        -e "s|Upper corner = 0.1, 0.02, 0.001|Upper corner = 0.1, 0.02, $thick|" \
        -e "s|set Horizon = 0.001|set Horizon = $delta|" \
        -e "s|3e6/0.00025|3e6/$force|" \
        -e "s|0.01985|$row|" \
        -e "s|set Directory = output|set Directory = .|" "$here/$scene.prm" > "$run/params.prm"
    echo "running $scene, spacing $h mm, on $ranks ranks ..."
    (cd "$run" && mpirun -np "$ranks" "$pd_app" params.prm > log)
  done
done
python3 "$here/analyze.py"
