#!/bin/bash
# Implicit solver benchmark: Krylov iterations of the quasistatic solver as
# the mesh is refined, assembled with CG and Trilinos ML AMG (rigid-body near
# null space) or Jacobi, and matrix-free (CG, block Jacobi); assembly and
# solve time; memory per degree of freedom.
#
# Scene: the unit cube, n^3 points, horizon 3.015 h; the layer x < 2h held
# (u = 0), the layer x > 1 - 2h pulled to u_x = 1e-3; one load step; K = 1
# (LPS: G = 0.35). Newton tolerance 1e-8, CG relative tolerance 1e-8. Scene
# memory: the peak minus what the process holds before it reads the scene
# (the libraries).
#
# usage: bench/implicit_amg.sh [options]
#   -m, --models LIST           pmb lps                (default: "pmb lps")
#   -n, --sizes LIST            points per edge, per model "pmb:10,20,30 lps:8,12,16"
#                               (default: that)
#   -p, --preconditioners LIST  AMG Jacobi MF          (default: "AMG Jacobi MF")
#                               MF: no matrix, Jacobian-free Newton-Krylov
#                               (CG, block Jacobi from the analytic diagonal)
#   -r, --ranks N               MPI ranks              (default: 1)
#       --pd-app PATH           (default: build/pd_app)
#   -o, --out DIR               (default: bench/results/implicit-<date-time>)
#   -h, --help
# Prints a markdown table (also DIR/table.md); logs in DIR/<case>/.
set -u -o pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
MODELS="pmb lps"
SIZES="pmb:10,20,30 lps:8,12,16"
PRECS="AMG Jacobi MF"
RANKS=1
PD_APP="$root/build/pd_app"
OUT=""
usage() { sed -n '2,/^set -u/p' "${BASH_SOURCE[0]}" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    -m|--models) MODELS=$(echo "$2" | tr ',' ' '); shift 2;;
    -n|--sizes) SIZES=$2; shift 2;;
    -p|--preconditioners) PRECS=$(echo "$2" | tr ',' ' '); shift 2;;
    -r|--ranks) RANKS=$2; shift 2;;
    --pd-app) PD_APP=$2; shift 2;;
    -o|--out) OUT=$2; shift 2;;
    -h|--help) usage; exit 0;;
    *) echo "Error: unknown option '$1' (see --help)" >&2; exit 2;;
  esac
done
[ -x "$PD_APP" ] || { echo "Error: no PeriDeal executable '$PD_APP' (build it, or pass --pd-app)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -n "$OUT" ] || OUT="$here/results/implicit-$(date +%Y%m%d-%H%M%S)"
mkdir -p "$OUT"; OUT=$(cd "$OUT" && pwd)

sizes_of() { echo "$SIZES" | tr ' ' '\n' | sed -n "s/^$1://p" | tr ',' ' '; }

write_prm() { # model n preconditioner file
  local m=$1 n=$2 p=$3 f=$4 h
  h=$(awk -v n="$n" 'BEGIN { printf "%.15g", 1 / n }')
  {
    echo "subsection Discretization"
    echo "  set Type = Box"
    echo "  set Horizon = $(awk -v h="$h" 'BEGIN { printf "%.15g", 3.015 * h }')"
    echo "  subsection Box"
    echo "    set Lower corner = 0,0,0"
    echo "    set Upper corner = 1,1,1"
    echo "    set Subdivisions = $n,$n,$n"
    echo "  end"
    echo "  subsection Regions"
    echo "    set Names = left, right"
    echo "    subsection left"
    echo "      set Type = Expression"
    echo "      set Expression = x < 2*$h"
    echo "    end"
    echo "    subsection right"
    echo "      set Type = Expression"
    echo "      set Expression = x > 1 - 2*$h"
    echo "    end"
    echo "  end"
    echo "end"
    echo "subsection Materials"
    echo "  set Names = mat"
    echo "  subsection mat"
    if [ "$m" = pmb ]; then echo "    set Model = PMB"; else echo "    set Model = LPS"; echo "    set Shear modulus = 0.35"; fi
    echo "    set Density = 1"
    echo "    set Bulk modulus = 1"
    echo "  end"
    echo "end"
    echo "subsection Blocks"
    echo "  set Names = cube"
    echo "  subsection cube"
    echo "    set Material = mat"
    echo "  end"
    echo "end"
    echo "subsection Boundary conditions"
    echo "  set Names = lx, ly, lz, rx"
    for c in x y z; do
      echo "  subsection l$c"
      echo "    set Type = Prescribed displacement"
      echo "    set Region = left"
      echo "    set Component = $c"
      echo "    set Value = 0"
      echo "  end"
    done
    echo "  subsection rx"
    echo "    set Type = Prescribed displacement"
    echo "    set Region = right"
    echo "    set Component = x"
    echo "    set Value = 1e-3*t"
    echo "  end"
    echo "end"
    echo "subsection Solver"
    echo "  set Type = QuasiStatic"
    echo "  set Number of steps = 1"
    echo "  subsection Implicit"
    if [ "$p" = MF ]; then echo "    set Jacobian = Matrix free"; else echo "    set Preconditioner = $p"; fi
    echo "    set Linear tolerance = 1e-8"
    echo "    set Maximum linear iterations = 5000"
    echo "  end"
    echo "end"
    echo "subsection Output"
    echo "  set Directory = output"
    echo "  set Frequency = 0"
    echo "  set Write globals = false"
    echo "end"
  } > "$f"
}

timer() { awk -F'|' -v s="$2" '{ n = $2; gsub(/^ +| +$/, "", n) } n == s { t = $4; gsub(/[ s]/, "", t); print t; exit }' "$1"; }

{
  echo "date: $(date -Is); $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $RANKS rank(s); commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null)"
  echo
  echo "| model | n | points | DoFs | nonzeros | preconditioner | Newton its | Krylov its per Newton it | tangent [s] | linear solve [s] | matrix [MiB] | peak memory [MiB] | scene memory per DoF [bytes] |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$OUT/table.md"
cat "$OUT/table.md"
for m in $MODELS; do
  for n in $(sizes_of "$m"); do
    for p in $PRECS; do
      dir="$OUT/${m}_n${n}_$p"; mkdir -p "$dir"
      write_prm "$m" "$n" "$p" "$dir/pd.prm"
      (cd "$dir" && mpirun -np "$RANKS" --bind-to core "$PD_APP" pd.prm > pd.log 2>&1)
      rc=$?
      its=$(grep -c "^  Newton [1-9]" "$dir/pd.log")
      cg=$(sed -n 's/^  Newton [1-9][0-9]*: .*(\(CG\|GMRES\) \([0-9]*\) iterations.*/\2/p' "$dir/pd.log" | tr '\n' ' ')
      pts=$((n * n * n))
      nnz=$(sed -n 's/^  tangent: .*, \([0-9]*\) nonzeros (\([0-9.e+]*\) MiB).*/\1/p' "$dir/pd.log")
      mat=$(sed -n 's/^  tangent: .*, \([0-9]*\) nonzeros (\([0-9.e+]*\) MiB).*/\2/p' "$dir/pd.log")
      peak=$(sed -n 's/^  peak memory: *\([0-9.]*\) MiB.*/\1/p' "$dir/pd.log")
      scene=$(sed -n 's/^  scene memory: *\([0-9.]*\) MiB.*/\1/p' "$dir/pd.log")
      ta=$(timer "$dir/pd.log" "implicit: tangent"); tl=$(timer "$dir/pd.log" "implicit: linear solve")
      [ $rc = 0 ] || { its="failed (rc $rc)"; }
      line="| ${m^^} | $n | $pts | $((3 * pts)) | ${nnz:--} | $p | $its | ${cg:--} | ${ta:--} | ${tl:--} | ${mat:--} | ${peak:--} | $(awk -v p="${scene:-0}" -v d=$((3 * pts)) 'BEGIN { printf "%.0f", p * 1048576 / d }') |"
      echo "$line" | tee -a "$OUT/table.md"
    done
  done
done
echo; echo "Results: $OUT"
