#!/bin/bash
# Refinement study of the Taylor bar (params.prm): for each number n of cells
# across the radius, mesh meshes/taylor_bar.geo with Gmsh, run params.prm with
# the horizon (3 h, h = r0 / n), the wall layer and the rear layer scaled to
# h, and print the final length and footprint radius at 80 us, both from the
# globals (L0 + rear_uz, r0 + foot_ux) and from the deformed points (plot.py),
# with the largest equivalent plastic strain, the energy balance and the cost.
#
# usage: doc/examples/taylor_bar/run_study.sh [options]
#   -n, --cells LIST     cells across the radius          (default: "4 6 8")
#   -r, --ranks N        MPI ranks                        (default: 2)
#   -s, --set LINE       an extra line for the copper material, e.g.
#                        -s "Hourglass coefficient = 0.005" or
#                        -s "Stabilization = Silling"; may be repeated
#       --pd-app PATH    (default: build/pd_app)
#   -o, --out DIR        (default: taylor-study-<date-time>)
#   -h, --help
# Prints a markdown table (also DIR/table.md) and draws DIR/convergence.png
# (length and footprint against h) and DIR/n<n>.png (plot.py's picture);
# meshes, logs and outputs in DIR/n<n>/.
set -u -o pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../../.." && pwd)
CELLS="4 6 8"
RANKS=2
PD_APP="$root/build/pd_app"
OUT=""
EXTRA=()
usage() { sed -n '2,/^set -u/p' "${BASH_SOURCE[0]}" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    -n|--cells) CELLS=$(echo "$2" | tr ',' ' '); shift 2;;
    -r|--ranks) RANKS=$2; shift 2;;
    -s|--set) EXTRA+=("$2"); shift 2;;
    --pd-app) PD_APP=$2; shift 2;;
    -o|--out) OUT=$2; shift 2;;
    -h|--help) usage; exit 0;;
    *) echo "run_study.sh: unknown option $1" >&2; usage >&2; exit 2;;
  esac
done
[ -x "$PD_APP" ] || { echo "run_study.sh: no pd_app at $PD_APP (build first)" >&2; exit 1; }
command -v gmsh > /dev/null || { echo "run_study.sh: gmsh not found (apt-get install gmsh)" >&2; exit 1; }
PYTHON=/usr/bin/python3
"$PYTHON" -c "import matplotlib, numpy" 2> /dev/null ||
  { echo "run_study.sh: $PYTHON lacks matplotlib or numpy (apt-get install python3-matplotlib)" >&2; exit 1; }
OUT=${OUT:-taylor-study-$(date +%Y%m%d-%H%M%S)}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1

settings="default stabilization (Hourglass, 0.02)"
[ ${#EXTRA[@]} -gt 0 ] && settings=$(printf '%s; ' "${EXTRA[@]}")
table="$OUT/table.md"
{
  echo "date: $(date -Iseconds); $(nproc) cores; $RANKS rank(s); commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown); $settings"
  echo
  echo "| n | points | h [mm] | horizon [mm] | final length [mm] (globals / points) | footprint radius [mm] (globals / points) | max eq. plastic strain | plastic dissipation [J] | energy balance | wall time [s] | peak memory [MiB] |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
} > "$table"
cat "$table"

for n in $CELLS; do
  dir="$OUT/n$n"
  mkdir -p "$dir"
  gmsh -3 -format msh22 -setnumber n "$n" "$root/meshes/taylor_bar.geo" -o "$dir/taylor_bar.msh" > "$dir/gmsh.log" 2>&1 ||
    { echo "run_study.sh: gmsh failed, see $dir/gmsh.log" >&2; exit 1; }
  # h = r0 / n across the radius (the layers along the axis are within 1%
  # of it, taylor_bar.geo); the wall region is the first layer (centroids at
  # about h / 2, the next at 3 h / 2), the rear region the last.
  read -r h delta wall rear < <(awk -v n="$n" 'BEGIN {
    h = 3.2e-3 / n; printf "%.9e %.9e %.9e %.9e\n", h, 3.015 * h, h, 32.4e-3 - h }')
  "$PYTHON" - "$here/params.prm" "$dir/params.prm" "$dir/taylor_bar.msh" "$delta" "$wall" "$rear" "${EXTRA[@]}" << 'EOF'
import re, sys
src, dst, mesh, delta, wall, rear = sys.argv[1:7]
extra = sys.argv[7:]
s = open(src).read()
def sub(pattern, repl):
    global s
    s, k = re.subn(pattern, repl, s, count=1, flags=re.M)
    assert k == 1, pattern
sub(r"^(\s*set Horizon\s*=).*$", r"\g<1> " + delta)
sub(r"^(\s*set Mesh file\s*=).*$", r"\g<1> " + mesh)
sub(r"(subsection rear\n(?:.*\n)*?\s*set Lower corner = -1, -1,).*$", r"\g<1> " + rear)
sub(r"(subsection wall\n(?:.*\n)*?\s*set Upper corner = 1, 1,).*$", r"\g<1> " + wall)
sub(r"^(\s*set Directory\s*=).*$", r"\g<1> output")
if extra:
    sub(r"^(\s*set Hardening modulus\s*=.*)$", r"\g<1>" + "".join("\n    set " + e for e in extra))
open(dst, "w").write(s)
EOF
  (cd "$dir" && /usr/bin/time -f "%e" -o time.txt mpirun -np "$RANKS" "$PD_APP" params.prm > run.log 2>&1) ||
    { echo "run_study.sh: n = $n failed, see $dir/run.log" >&2; continue; }
  "$PYTHON" "$here/plot.py" "$dir/output/taylor_bar.pvd" "$OUT/n$n.png" > "$dir/plot.txt"
  "$PYTHON" - "$dir" "$n" "$h" "$delta" >> "$table" << 'EOF'
import csv, re, sys
d, n, h, delta = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
row = list(csv.DictReader(open(d + "/output/taylor_bar.globals.csv")))[-1]
log = open(d + "/run.log").read()
plot = open(d + "/plot.txt").read()
num = lambda pattern, text: float(re.search(pattern, text).group(1))
points = int(num(r"points:\s+(\d+)", log))
L = 32.4 + 1e3 * float(row["rear_uz"])
R = 3.2 + 1e3 * max(float(row["foot_ux"]), float(row["foot_uy"]))
print("| %s | %d | %.3f | %.3f | %.2f / %.2f | %.2f / %.2f | %.2f | %.1f | %.1e | %.0f | %.0f |" % (
    n, points, 1e3 * h, 1e3 * delta, L, num(r"final length\s+([0-9.]+)", plot), R,
    num(r"footprint radius\s+([0-9.]+)", plot), num(r"plastic strain ([0-9.]+)", plot),
    float(row["material_dissipation"]), num(r"energy balance error:\s+(\S+)", log),
    float(open(d + "/time.txt").read().split()[-1]), num(r"peak memory:\s+([0-9.]+) MiB", log)))
EOF
  tail -1 "$table"
done

"$PYTHON" - "$table" "$OUT/convergence.png" << 'EOF'
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = [l.split("|")[1:-1] for l in open(sys.argv[1]) if l.startswith("| ") and l[2].isdigit()]
if rows:
    h = [float(r[2]) for r in rows]
    L = [float(r[4].split("/")[1]) for r in rows]
    R = [float(r[5].split("/")[1]) for r in rows]
    fig, ax = plt.subplots(1, 2, figsize=(8, 3.2))
    ax[0].plot(h, L, "o-", label="PeriDeal (deformed points)")
    ax[1].plot(h, R, "o-", label="PeriDeal (deformed points)")
    for a, name in zip(ax, ["final length (mm)", "footprint radius (mm)"]):
        a.set_xlabel("cell size h (mm), horizon 3 h")
        a.set_ylabel(name)
        a.set_xlim(left=0)
        a.grid(alpha=0.3)
    ax[0].axhspan(21.42, 21.47, color="0.8", label="FE codes (see README)")
    ax[1].axhspan(7.0, 7.12, color="0.8", label="FE codes (see README)")
    ax[1].legend(fontsize=7, loc="lower left")
    fig.suptitle("Taylor bar at 80 us: refinement", fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)
EOF
echo "table: $table"
