#!/bin/bash
# The machine's limits per core (doc/performance.md, "The machine's limits"):
# STREAM's triad bandwidth, the double-precision FMA peak, square roots and
# divisions per ns, and doubles gathered per ns at random indices from L1, L2,
# L3 and memory. Runs bench/machine_limits.cc alone and then as two processes
# at once (both cores busy), each REPS times, and prints the medians as a
# markdown table.
#
# usage: bench/machine_limits.sh [REPS]     (default 3; about 8 s a run)
set -eu -o pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
reps=${1:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The project's flags for its hot loops (CMakeLists.txt).
g++ -O3 -march=native -fno-math-errno -fopenmp-simd -o "$work/limits" "$here/machine_limits.cc"

for r in $(seq "$reps"); do
  "$work/limits" > "$work/alone.$r"
  "$work/limits" > "$work/pair_a.$r" &
  "$work/limits" > "$work/pair_b.$r"
  wait
done

/usr/bin/python3 - "$work" "$reps" <<'EOF'
import statistics, sys
work, reps = sys.argv[1], int(sys.argv[2])
def read(name):
    out = {}
    for r in range(1, reps + 1):
        for line in open(f"{work}/{name}.{r}"):
            key, value = line.split()
            out.setdefault(key, []).append(float(value))
    return {k: statistics.median(v) for k, v in out.items()}
alone, a, b = read("alone"), read("pair_a"), read("pair_b")
label = {
    "triad_bandwidth_GBps": "STREAM triad (GB/s)",
    "fma_peak_GFlops": "FMA peak, double (GFlop/s)",
    "sqrt_per_ns": "square roots per ns",
    "div_per_ns": "divisions per ns",
    "gather_L1_per_ns": "doubles gathered per ns, 16 KiB array (L1)",
    "gather_L2_per_ns": "... 1 MiB array (L2)",
    "gather_L3_per_ns": "... 16 MiB array (L3)",
    "gather_memory_per_ns": "... 1 GiB array (memory)",
}
print(f"| per core (medians of {reps}) | one process alone | two at once, each |")
print("|---|---|---|")
for key, name in label.items():
    both = statistics.median([a[key], b[key]])
    print(f"| {name} | {alone[key]:.3g} | {both:.3g} |")
EOF
