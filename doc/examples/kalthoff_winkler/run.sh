#!/bin/bash
# Runs the Kalthoff-Winkler plate for each model and spacing and prints the
# table of README.md (analyze.py), which also draws kw_damage.png.
#
# usage: doc/examples/kalthoff_winkler/run.sh [ranks (default 2)] [pd_app (default build/pd_app)] [spacings in mm (default "2 1.25 1")]
# Output in doc/examples/kalthoff_winkler/output/<model>-<spacing>mm/ with its log.
# About 7 minutes on 2 cores for the default spacings.
set -eu -o pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ranks=${1:-2}
pd_app=$(realpath "${2:-$here/../../../build/pd_app}")
spacings=${3:-2 1.25 1}
for model in pmb lps energy; do
  for h in $spacings; do
    run=$here/output/$model-${h}mm
    mkdir -p "$run"
    # The spacing h mm: 100/h x 200/h x 10/h cells, horizon 3.015 h.
    read -r nx ny nz delta < <(python3 -c "h = $h; print(round(100 / h), round(200 / h), round(10 / h), '%.6g' % (3.015e-3 * h))")
    sed -e "s|set Subdivisions = 100, 200, 10|set Subdivisions = $nx, $ny, $nz|" \
        -e "s|set Horizon = 0.003015|set Horizon = $delta|" \
        -e "s|set Directory         = output|set Directory         = .|" "$here/params.prm" > "$run/params.prm"
    case $model in
      lps) sed -i -e "s|set Model         = PMB|set Model         = LPS|" \
                  -e "s|    set Young's modulus = 190e9.*|    set Young's modulus = 190e9\n    set Poisson's ratio = 0.25|" "$run/params.prm" ;;
      energy) sed -i -e "s|set Model                        = Critical stretch|set Model                        = Critical energy|" "$run/params.prm" ;;
    esac
    echo "running $model, spacing $h mm, on $ranks ranks ..."
    (cd "$run" && mpirun -np "$ranks" "$pd_app" params.prm > log)
  done
done
python3 "$here/analyze.py"
