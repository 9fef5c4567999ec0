#!/bin/bash
# Newton's convergence order per material model (doc/implicit.md, "Tangent and
# Newton's order per model"): one quasistatic load step of every registered
# material on a small bar in a nonlinear regime, the residual norm of every
# Newton iteration and the observed order
#   p_k = log(r_k / r_{k-1}) / log(r_{k-1} / r_{k-2}),
# and the tangent the run used (analytic, or finite differences: the set-up
# report's 'tangent:' line). PMB and LPS also run with Tangent = Finite
# differences, for comparison.
#
# Scene: a 1 x 0.4 x 0.4 bar of 10 x 4 x 4 points (h = 0.1), horizon 3.015 h;
# the two layers x < 0.2 held (u = 0), the two layers x > 0.8 moved by
# (0.08, 0.15, 0) in one load step: 8% stretch and a lateral offset of 15% of
# the length, so the bar bends and turns (geometric nonlinearity) and Newton
# starts far from the solution. K = 1, G = 0.5 (PMB: K = 1 only), rho = 1.
# Elastic plastic (and its correspondence twin): yield stress 0.01 (the step crosses it: yield strain about
# 0.008), hardening 0.1. Viscoelastic: relaxation time 1 = the load step,
# viscous fraction 0.5. Newton tolerance 1e-13 (relative), line search on,
# GMRES (a finite-difference tangent need not be exactly symmetric) with AMG,
# linear tolerance 1e-14, so that the order is Newton's, not the Krylov
# solver's, down to round-off. Orders are printed while r_k > 1e-12 r_0
# (below that the residual is at round-off and the ratio means nothing).
#
# usage: bench/newton_order.sh [--pd-app PATH] [-r RANKS] [-o DIR]
#   --pd-app PATH   (default: build/pd_app)
#   -r, --ranks N   MPI ranks (default: 1)
#   -o, --out DIR   (default: bench/results/newton-<date-time>)
# Prints a markdown table (also DIR/table.md); logs in DIR/<case>/. A model
# of the registry that this script has no keys for is reported, not skipped
# silently.
set -u -o pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
PD_APP="$root/build/pd_app"
RANKS=1
OUT=""
usage() { sed -n '2,/^set -u/p' "${BASH_SOURCE[0]}" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --pd-app) PD_APP=$2; shift 2;;
    -r|--ranks) RANKS=$2; shift 2;;
    -o|--out) OUT=$2; shift 2;;
    -h|--help) usage; exit 0;;
    *) echo "Error: unknown option '$1' (see --help)" >&2; exit 2;;
  esac
done
PD_APP=$(realpath "$PD_APP" 2>/dev/null || echo "$PD_APP")
[ -x "$PD_APP" ] || { echo "Error: no PeriDeal executable '$PD_APP' (build it, or pass --pd-app)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
[ -n "$OUT" ] || OUT="$here/results/newton-$(date +%Y%m%d-%H%M%S)"
mkdir -p "$OUT"; OUT=$(cd "$OUT" && pwd)

# The material keys of each model (besides Model and Density).
keys_of() {
  case "$1" in
    "PMB") echo "Bulk modulus = 1";;
    "LPS"|"Elastic correspondence") echo "Bulk modulus = 1;Shear modulus = 0.5";;
    "Elastic plastic") echo "Bulk modulus = 1;Shear modulus = 0.5;Yield stress = 0.01;Hardening modulus = 0.1";;
    "Elastic plastic correspondence") echo "Bulk modulus = 1;Shear modulus = 0.5;Yield stress = 0.01;Hardening modulus = 0.1";;
    "Viscoelastic") echo "Bulk modulus = 1;Shear modulus = 0.5;Relaxation time = 1;Viscous fraction = 0.5";;
    *) return 1;;
  esac
}

# The registered materials, from the Model key's documentation in the
# parameter reference ("The material model: one of A, B, C.").
registered=$("$PD_APP" --print-parameters 2>/dev/null |
  awk '/# The material model: one of/ { m = 1 } m { line = line " " $0 } m && /\.$/ { print line; exit }' |
  sed -E 's/.*one of //; s/\.$//; s/ *# */ /g; s/ +/ /g; s/, /|/g; s/^ //')
[ -n "$registered" ] || { echo "Error: cannot read the registered materials from $PD_APP --print-parameters" >&2; exit 1; }

write_prm() { # model tangent file
  local model=$1 tangent=$2 file=$3 k
  {
    cat <<EOF
subsection Discretization
  set Type = Box
  set Horizon = 0.3015
  subsection Box
    set Lower corner = 0, 0, 0
    set Upper corner = 1, 0.4, 0.4
    set Subdivisions = 10, 4, 4
  end
  subsection Regions
    set Names = left, right
    subsection left
      set Type = Box
      set Lower corner = -1, -1, -1
      set Upper corner = 0.2, 1, 1
    end
    subsection right
      set Type = Box
      set Lower corner = 0.8, -1, -1
      set Upper corner = 2, 1, 1
    end
  end
end
subsection Materials
  set Names = solid
  subsection solid
    set Model = $model
    set Density = 1
EOF
    IFS=';' read -ra k <<<"$(keys_of "$model")"
    for kv in "${k[@]}"; do echo "    set $kv"; done
    cat <<EOF
  end
end
subsection Blocks
  set Names = bar
  subsection bar
    set Material = solid
  end
end
subsection Boundary conditions
  set Names = lx, ly, lz, rx, ry, rz
EOF
    for c in x y z; do
      printf '  subsection l%s\n    set Type = Prescribed displacement\n    set Region = left\n    set Component = %s\n    set Value = 0\n  end\n' $c $c
    done
    for cv in "x 0.08*t" "y 0.15*t" "z 0"; do
      set -- $cv
      printf '  subsection r%s\n    set Type = Prescribed displacement\n    set Region = right\n    set Component = %s\n    set Value = %s\n  end\n' $1 $1 "$2"
    done
    cat <<EOF
end
subsection Solver
  set Type = QuasiStatic
  set Number of steps = 1
  set Final time = 1
  subsection Implicit
    set Tolerance = 1e-13
    set Maximum Newton iterations = 40
    set Linear solver = GMRES
    set Linear tolerance = 1e-14
    set Maximum linear iterations = 5000
    set Tangent = $tangent
  end
end
subsection Output
  set Frequency = 0
  set Variables =
end
EOF
  } >"$file"
}

table="$OUT/table.md"
{
  echo "| model | tangent | iterations | r_k / r_0 (k = 1, 2, ...) | order p_k (k = 2, 3, ...) | time |"
  echo "|---|---|---|---|---|---|"
} >"$table"
cat "$table"
IFS='|' read -ra models <<<"$registered"
for model in "${models[@]}"; do
  if ! keys_of "$model" >/dev/null; then
    echo "| $model | (no keys in bench/newton_order.sh: add them to keys_of) | | | | |" | tee -a "$table"
    continue
  fi
  tangents="Analytic"
  [[ $model == PMB || $model == LPS ]] && tangents="Analytic|Finite differences"
  IFS='|' read -ra tlist <<<"$tangents"
  for tangent in "${tlist[@]}"; do
    case_dir="$OUT/$(echo "$model-$tangent" | tr ' ' '_')"
    mkdir -p "$case_dir"
    write_prm "$model" "$tangent" "$case_dir/case.prm"
    start=$(date +%s.%N)
    (cd "$case_dir" && mpirun -np "$RANKS" "$PD_APP" case.prm >run.stdout 2>run.stderr)
    rc=$?
    seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f s", b - a }')
    if [ $rc -ne 0 ]; then
      echo "| $model | $tangent | failed: $(grep -m1 '^Error' "$case_dir/run.stderr" "$case_dir/run.stdout" | cut -c1-120) | | | $seconds |" | tee -a "$table"
      continue
    fi
    used=$(grep -m1 -E '^ +tangent: ' "$case_dir/run.stdout" | sed -E 's/^ +tangent: +//')
    awk -v model="$model" -v used="$used" -v seconds="$seconds" '
      /Newton [0-9]+: \|R\| = / {
        for (f = 1; f <= NF; ++f) if ($f == "=") { r[n++] = $(f + 1) + 0; break }
      }
      END {
        ratios = ""; orders = ""
        for (k = 1; k < n; ++k) ratios = ratios sprintf("%s%.2g", k > 1 ? " " : "", r[k] / r[0])
        for (k = 2; k < n; ++k)
          if (r[k] > 1e-12 * r[0] && r[k - 1] != r[k - 2])
            orders = orders sprintf("%s%.2f", orders == "" ? "" : " ", log(r[k] / r[k - 1]) / log(r[k - 1] / r[k - 2]))
        printf "| %s | %s | %d | %s | %s | %s |\n", model, used, n - 1, ratios, orders, seconds
      }' "$case_dir/run.stdout" | tee -a "$table"
  done
done
echo
echo "table: $table"
