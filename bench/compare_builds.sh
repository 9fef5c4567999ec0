#!/bin/bash
# Old build against new build on one scene, interleaved, in one script: the
# time loop, the bond-update rate and chosen TimerOutput sections of each
# run, their medians, and whether the two builds' globals are identical.
#
#   bench/compare_builds.sh [options] OLD_PD_APP NEW_PD_APP SCENE.prm
#
#   -r, --ranks LIST     MPI ranks                        (default: "1 2")
#   -R, --reps N         repetitions, old and new alternating (default: 3)
#   -s, --sections LIST  TimerOutput sections to report, comma separated
#                        (default: "force,contact search,contact force")
#   -o, --out DIR        working directory                (default: a new one in /tmp)
#
# The scene should write its globals (Output/Write globals = true); the
# first repetition of each rank count compares them byte for byte.
# Example (the cube of bench/cube_explicit.sh with contact, old clean clone):
#   bench/compare_builds.sh /tmp/old/build/pd_app build/pd_app /tmp/bench/perideal_pmb_dmg_n40_np2_r1/pd.prm
set -euo pipefail

RANKS="1 2"
REPS=3
SECTIONS="force,contact search,contact force"
OUT=""
while [ $# -gt 0 ]; do
  case $1 in
    -r|--ranks)    RANKS=$2; shift 2;;
    -R|--reps)     REPS=$2; shift 2;;
    -s|--sections) SECTIONS=$2; shift 2;;
    -o|--out)      OUT=$2; shift 2;;
    -h|--help)     sed -n '2,18p' "$0"; exit 0;;
    -*)            echo "Error: unknown option $1" >&2; exit 2;;
    *)             break;;
  esac
done
if [ $# -ne 3 ]; then
  echo "Error: give OLD_PD_APP NEW_PD_APP SCENE.prm (--help)" >&2
  exit 2
fi
old=$(readlink -f "$1"); new=$(readlink -f "$2"); scene=$(readlink -f "$3")
for f in "$old" "$new" "$scene"; do
  [ -e "$f" ] || { echo "Error: $f does not exist" >&2; exit 2; }
done
[ -n "$OUT" ] || OUT=$(mktemp -d /tmp/compare_builds.XXXXXX)
mkdir -p "$OUT"
cd "$OUT"

echo "date: $(date -Iseconds)"
echo "old: $old"
echo "new: $new"
echo "scene: $scene"
echo "load at start: $(cat /proc/loadavg)"

# Seconds of a TimerOutput section in a log (the first table: rank 0).
section() {
  awk -F'|' -v s="$2" '{ name = $2; gsub(/^ +| +$/, "", name) }
    name == s { t = $4; gsub(/[ s]/, "", t); print t; found = 1; exit }
    END { if (!found) print "-" }' "$1"
}
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

IFS=, read -r -a section_list <<< "$SECTIONS"
for np in $RANKS; do
  for rep in $(seq 1 "$REPS"); do
    for build in old new; do
      app=$old; [ "$build" = new ] && app=$new
      dir=${build}_np${np}_r${rep}
      rm -rf "$dir"; mkdir "$dir"
      (cd "$dir" && mpirun -np "$np" "$app" "$scene" > run.log 2>&1) ||
        { echo "Error: $build, $np ranks, repetition $rep failed (see $OUT/$dir/run.log)" >&2; exit 1; }
      # The summary writes "time loop 8.7 s", "2 min 34 s" or "1 h 5 min" (format_seconds).
      loop=$(sed -n 's/.*time loop \([^)]*\)).*/\1/p' "$dir/run.log" | head -1 |
        awk '{t = 0; for (i = 1; i < NF; i += 2) t += $i * ($(i + 1) == "h" ? 3600 : $(i + 1) == "min" ? 60 : 1); print t}')
      rate=$(sed -n 's/.*bond updates per second: \([0-9.]*\) M.*/\1/p' "$dir/run.log" | head -1)
      line="$(date +%T) $build np=$np rep $rep: loop $loop s, $rate M bond updates/s"
      for s in "${section_list[@]}"; do line="$line, $s $(section "$dir/run.log" "$s") s"; done
      echo "$line"
      echo "$build $np $loop $rate" >> runs.txt
    done
    if [ "$rep" = 1 ]; then
      a=$(find "old_np${np}_r1" -name '*.globals.csv' | head -1)
      b=$(find "new_np${np}_r1" -name '*.globals.csv' | head -1)
      if [ -z "$a" ] || [ -z "$b" ]; then echo "globals: none written ($np ranks)"
      elif cmp -s "$a" "$b"; then echo "globals: identical ($np ranks)"
      else echo "globals: DIFFER ($np ranks): diff $OUT/$a $OUT/$b"; fi
    fi
  done
done

echo
echo "| ranks | build | loop [s] (median) | M bond updates/s (median) | $(printf '%s [s] | ' "${section_list[@]}")"
echo "|---|---|---|---|$(printf -- '---|%.0s' "${section_list[@]}")"
for np in $RANKS; do
  for build in old new; do
    row="| $np | $build | $(awk -v b=$build -v n=$np '$1 == b && $2 == n { print $3 }' runs.txt | median) | $(awk -v b=$build -v n=$np '$1 == b && $2 == n { print $4 }' runs.txt | median) |"
    for s in "${section_list[@]}"; do
      row="$row $(for d in ${build}_np${np}_r*; do section "$d/run.log" "$s"; done | grep -v '^-$' | median) |"
    done
    echo "$row"
  done
done
echo "load at end: $(cat /proc/loadavg)"
