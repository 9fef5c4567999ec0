#!/bin/bash
# Mesh refinement study of the dog-bone tensile test (params.prm): for each
# number n of cells through the thickness, mesh meshes/dogbone.geo with Gmsh,
# run one quasistatic load step with the horizon, grips and gauge scaled to
# the spacing h = 3.15 mm / n, and print Young's modulus from the gauge
# strain and the reaction force against the classical 9KG/(3K+G).
#
# usage: doc/examples/dogbone_tensile/run_study.sh [options]
#   -n, --layers LIST    cells through the thickness      (default: "4 6 8")
#   -r, --ranks N        MPI ranks                        (default: 2)
#   -w, --influence F    LPS influence function omega(r)  (default: params.prm's)
#   -m, --matrix-free N  from this n on, Jacobian = Matrix free, each Newton
#                        step solved to 1e-6 in at most 5000 GMRES iterations
#                        (block Jacobi needs hundreds on this slender
#                        specimen; 1e-10 is out of reach) (default: none)
#       --pd-app PATH    (default: build/pd_app)
#   -o, --out DIR        (default: dogbone-study-<date-time>)
#   -h, --help
# Prints a markdown table (also DIR/table.md); meshes, logs and CSVs in
# DIR/n<n>/.
set -u -o pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../../.." && pwd)
LAYERS="4 6 8"
RANKS=2
MF_FROM=1000
INFLUENCE=""
PD_APP="$root/build/pd_app"
OUT=""
usage() { sed -n '2,/^set -u/p' "${BASH_SOURCE[0]}" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    -n|--layers) LAYERS=$(echo "$2" | tr ',' ' '); shift 2;;
    -r|--ranks) RANKS=$2; shift 2;;
    -m|--matrix-free) MF_FROM=$2; shift 2;;
    -w|--influence) INFLUENCE=$2; shift 2;;
    --pd-app) PD_APP=$2; shift 2;;
    -o|--out) OUT=$2; shift 2;;
    -h|--help) usage; exit 0;;
    *) echo "run_study.sh: unknown option $1" >&2; usage >&2; exit 2;;
  esac
done
[ -x "$PD_APP" ] || { echo "run_study.sh: no pd_app at $PD_APP (build first)" >&2; exit 1; }
command -v gmsh > /dev/null || { echo "run_study.sh: gmsh not found (apt-get install gmsh)" >&2; exit 1; }
OUT=${OUT:-dogbone-study-$(date +%Y%m%d-%H%M%S)}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none

K=150e9
G=69.23e9
E_classical=$(awk -v K=$K -v G=$G 'BEGIN { printf "%.6e", 9 * K * G / (3 * K + G) }')

table="$OUT/table.md"
{
  echo "date: $(date -Iseconds); $(nproc) cores; $RANKS rank(s); commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo
  echo "| n | h [mm] | horizon [mm] | omega | points | Jacobian | gauge strain | stress [MPa] | E [GPa] | E / 9KG/(3K+G) - 1 | Newton its | Krylov its | wall time [s] | peak memory [MiB] |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$table"
cat "$table"

for n in $LAYERS; do
  dir="$OUT/n$n"
  mkdir -p "$dir"
  gmsh -3 -format msh22 -setnumber n "$n" "$root/meshes/dogbone.geo" -o "$dir/dogbone.msh" > "$dir/gmsh.log" 2>&1 ||
    { echo "run_study.sh: gmsh failed, see $dir/gmsh.log" >&2; exit 1; }
  # Spacing: the largest cell edge of the reduced section (its cells, as in
  # dogbone.geo, are 31.75 mm / round(31.75 mm / t) by 6.35 mm / round(6.35
  # mm / t) by t = 3.15 mm / n); horizon 3.015 times it (bonds of exactly 3
  # spacings in the family whatever the round-off); the grips two horizons
  # deep; the gauge slabs 1.2 h thick centred at +-24.76 mm / 2.
  read -r h delta grip g0 g1 < <(awk -v n="$n" 'BEGIN {
    t = 3.15e-3 / n; hx = 31.75e-3 / int(31.75e-3 / t + 0.5); hy = 6.35e-3 / int(6.35e-3 / t + 0.5);
    h = t; if (hx > h) h = hx; if (hy > h) h = hy; d = 3.015 * h;
    printf "%.9e %.9e %.9e %.9e %.9e\n", h, d, 50.8e-3 - 2 * d, 12.38e-3 - 0.6 * h, 12.38e-3 + 0.6 * h }')
  jacobian=Assembled
  linear="set Linear tolerance = 1e-10"
  if [ "$n" -ge "$MF_FROM" ]; then
    jacobian="Matrix free"
    linear="set Linear tolerance = 1e-6\n    set Maximum linear iterations = 5000"
  fi
  influence=()
  [ -n "$INFLUENCE" ] && influence=(-e "s|set Influence function = .*|set Influence function = $INFLUENCE|")
  sed -e "s|set Horizon = .*|set Horizon = $delta|" "${influence[@]}" \
      -e "s|set Mesh file = .*|set Mesh file = $dir/dogbone.msh|" \
      -e "s|set Upper corner = -46.0136875e-3, 1, 1|set Upper corner = -$grip, 1, 1|" \
      -e "s|set Lower corner = 46.0136875e-3, -1, -1|set Lower corner = $grip, -1, -1|" \
      -e "s|set Lower corner = -12.85625e-3, -1, -1|set Lower corner = -$g1, -1, -1|" \
      -e "s|set Upper corner = -11.90375e-3, 1, 1|set Upper corner = -$g0, 1, 1|" \
      -e "s|set Lower corner = 11.90375e-3, -1, -1|set Lower corner = $g0, -1, -1|" \
      -e "s|set Upper corner = 12.85625e-3, 1, 1|set Upper corner = $g1, 1, 1|" \
      -e "s|set Number of steps = 2|set Number of steps = 1|" \
      -e "s|^subsection Solver|subsection Solver\n  subsection Implicit\n    set Jacobian = $jacobian\n    $linear\n  end|" \
      -e "s|set Variables = Displacement|set Variables =|" \
      -e "s|  set Base name = dogbone|  set Base name = dogbone\n  set Directory = $dir|" \
      "$here/params.prm" > "$dir/params.prm"
  # Every substitution must have happened: the scene would silently be another.
  for v in "$delta" "$grip" "$g0" "$g1" "$jacobian" "$dir/dogbone.msh" "Influence function = $INFLUENCE"; do
    grep -qF -- "$v" "$dir/params.prm" || { echo "run_study.sh: params.prm no longer matches this script ($v)" >&2; exit 1; }
  done
  ( cd "$dir" && mpirun -np "$RANKS" "$PD_APP" params.prm > pd.log 2>&1 ) ||
    { echo "run_study.sh: pd_app failed for n = $n, see $dir/pd.log" >&2; exit 1; }
  awk -F, -v Ec="$E_classical" -v n="$n" -v h="$h" -v d="$delta" -v jac="$jacobian" \
      -v omega="$(sed -n 's/^ *set Influence function *= *//p' "$dir/params.prm")" \
      -v pts="$(awk '/^  points:/ { print $2; exit }' "$dir/pd.log")" \
      -v wall="$(awk -F'|' '/Total wallclock time elapsed since start/ { gsub(/[ s]/, "", $3); print $3; exit }' "$dir/pd.log")" \
      -v mem="$(awk '/peak memory:/ { print $3; exit }' "$dir/pd.log")" '
    NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    { last = $0 }
    END {
      split(last, v, ",")
      strain = (v[c["u_right"]] - v[c["u_left"]]) / (v[c["x_right"]] - v[c["x_left"]])
      stress = v[c["reaction_rx"]] / (6.35e-3 * 3.15e-3)
      E = stress / strain
      printf "| %d | %.4f | %.4f | %s | %d | %s | %.5e | %.2f | %.2f | %+.2f%% | %d | %d | %s | %s |\n",
             n, h * 1e3, d * 1e3, omega, pts, jac, strain, stress / 1e6, E / 1e9, 100 * (E / Ec - 1),
             v[c["newton_iterations"]], v[c["linear_iterations"]], wall, mem
    }' "$dir/dogbone.globals.csv" | tee -a "$table"
done
echo
echo "9KG/(3K+G) = $(awk -v E="$E_classical" 'BEGIN { printf "%.2f", E / 1e9 }') GPa (K = 150 GPa, G = 69.23 GPa). Table: $table"
