#!/bin/bash
# Two builds of pd_app on the cube-explicit benchmark in one script: a
# refactor must keep the speed and the memory (doc/performance.md).
#
# usage: bench/old_vs_new.sh OLD_PD_APP NEW_PD_APP [-n N] [-R REPS] [-m MODELS] [-r RANKS] [-o DIR]
#   -n N        points per edge                 (default: 60)
#   -R REPS     repetitions, old and new interleaved in each (default: 3)
#   -m MODELS   "pmb lps"                       (default: both)
#   -r RANKS    "1 2"                           (default: both)
#   -o DIR      results (default: bench/results/old_vs_new-<date-time>)
#
# Every repetition runs bench/cube_explicit.sh (variant elastic: no bond
# breaks, 200 steps, --no-physics) with the old build, then with the new one,
# so both see about the same machine load. The table gives, per model and
# rank count, the median over the repetitions of the bond updates per second
# and of the peak memory per bond, and the verdicts: the new rate within 3% of
# the old one (or above it), the bytes per bond not higher (within 0.5%, the
# resolution of the peak resident memory). For any other scene, with its
# TimerOutput sections and a byte comparison of the globals:
# bench/compare_builds.sh.
set -euo pipefail

[[ $# -ge 2 ]] || { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 2; }
OLD=$(realpath "$1")
NEW=$(realpath "$2")
shift 2
N=60 REPS=3 MODELS="pmb lps" RANKS="1 2"
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=$HERE/results/old_vs_new-$(date +%Y%m%d-%H%M%S)
while [[ $# -gt 0 ]]; do
  case $1 in
    -n) N=$2; shift 2 ;;
    -R) REPS=$2; shift 2 ;;
    -m) MODELS=$2; shift 2 ;;
    -r) RANKS=$2; shift 2 ;;
    -o) OUT=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
for app in "$OLD" "$NEW"; do
  [[ -x $app ]] || { echo "not an executable: $app" >&2; exit 2; }
done
mkdir -p "$OUT"
echo "old: $OLD"
echo "new: $NEW"
echo "n = $N, $REPS repetitions, models $MODELS, ranks $RANKS; results in $OUT"

for ((rep = 1; rep <= REPS; ++rep)); do
  for build in old new; do
    app=$OLD
    [[ $build == new ]] && app=$NEW
    "$HERE/cube_explicit.sh" -m "$MODELS" -v elastic -n "$N" -r "$RANKS" -c perideal --no-physics \
      --pd-app "$app" -o "$OUT/$build-$rep" >"$OUT/$build-$rep.log" 2>&1 || true # its verdicts on LAMMPS targets; failed runs are in results.tsv
    echo "repetition $rep, $build: done ($(date +%H:%M:%S))"
  done
done

# results.tsv columns by name (the header row); the medians per build, model
# and rank count.
awk -F'\t' '
  FNR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; build = FILENAME; sub(".*/", "", build); next }
  $c["status"] != "ok" { bad[$c["model"] " " $c["ranks"]] = 1; next }
  {
    split(FILENAME, p, "/"); b = p[length(p) - 1]; sub("-[0-9]+$", "", b)
    k = $c["model"] SUBSEP $c["ranks"] SUBSEP b
    n[k]++; upd[k, n[k]] = $c["updates"]; bpb[k, n[k]] = $c["peak_mib"] * 1048576 / $c["bonds"]
    models[$c["model"]]; ranks[$c["ranks"]]
  }
  function median(a, k, m,    v, i, j, t) {
    for (i = 1; i <= m; ++i) v[i] = a[k, i]
    for (i = 1; i <= m; ++i) for (j = i + 1; j <= m; ++j) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
    return m % 2 ? v[(m + 1) / 2] : (v[m / 2] + v[m / 2 + 1]) / 2
  }
  END {
    print ""
    print "| model | ranks | runs | old updates/s | new updates/s | new/old | within 3% | old bytes/bond | new bytes/bond | not higher |"
    print "|---|---|---|---|---|---|---|---|---|---|"
    fail = 0
    for (m in models) for (r in ranks) {
      ko = m SUBSEP r SUBSEP "old"; kn = m SUBSEP r SUBSEP "new"
      if (!(ko in n) || !(kn in n)) { printf "| %s | %s | missing runs |\n", m, r; fail = 1; continue }
      uo = median(upd, ko, n[ko]); un = median(upd, kn, n[kn])
      bo = median(bpb, ko, n[ko]); bn = median(bpb, kn, n[kn])
      speed = un >= 0.97 * uo ? "yes" : "**no**"
      memory = bn <= 1.005 * bo ? "yes" : "**no**"
      if (speed != "yes" || memory != "yes") fail = 1
      printf "| %s | %s | %d + %d | %.2f M | %.2f M | %.3f | %s | %.1f | %.1f | %s |\n",
             toupper(m), r, n[ko], n[kn], uo / 1e6, un / 1e6, un / uo, speed, bo, bn, memory
    }
    for (k in bad) { printf "failed runs: %s\n", k; fail = 1 }
    exit fail
  }' "$OUT"/old-*/results.tsv "$OUT"/new-*/results.tsv
