#!/bin/bash
# cube-explicit benchmark: PeriDeal and LAMMPS (PERI package) side by side.
#
# Scene (doc/performance.md): n^3 points on [0,1]^3 (box cells, centroids at
# (i+1/2)h, h = 1/n), horizon 3.015 h, density 1; PMB K = 1; LPS K = 1, G = 0.6;
# initial velocity vamp*(x-0.5, y-0.5, z-0.5); velocity Verlet with the fixed
# dt = 0.3560630338 h; 200 steps; no field output.
# Models (PeriDeal "Model" / LAMMPS pair_style):
#   pmb   PMB / peri/pmb            lps  LPS / peri/lps
#   eps   Elastic plastic / peri/eps: K = 1, G = 0.6, yield stress --yield,
#         perfectly plastic (0.002: the surface layers yield first, and by
#         step 200 about 90% of the points at n = 20 and 60)
#   ves   Viscoelastic / peri/ves: K = 1, G = 0.6, Viscous fraction = LAMMPS
#         lambda_i (--viscous-fraction), Relaxation time = LAMMPS tau_i
#         (--relaxation-time)
#   corr  Elastic correspondence (K = 1, G = 0.6, its defaults: Green-Lagrange,
#         hourglass 0.02), PeriDeal only: its ratio column is against
#         PeriDeal's LPS of the same case (run lps too). With damage its
#         points are neglected past damage 0.5 (Peridigm's practice): without,
#         a point left with few bonds has a near-singular shape tensor and
#         the dmg run blows up at step 47
#   elastic     critical stretch 1.0,   vamp 0.01 (no bond breaks)
#   elastic-nd  as elastic, but PeriDeal runs without a damage model (LAMMPS
#               cannot switch its bond-break check off: it runs 'elastic')
#   dmg         critical stretch 0.005, vamp 0.02 (bonds break)
#   dmg-time    as dmg with PeriDeal's Time dependent critical stretch
#               s_c(t) = 0.005 + 0*t: the same bonds break, so the globals must
#               equal dmg's; its rate against dmg's is the cost of a limit
#               refreshed at every step (LAMMPS has no such model: its ratio
#               column is against LAMMPS' dmg)
#   dmg-soft    as dmg with PeriDeal's Linear softening, onset stretch 0.004,
#               critical stretch 0.005: a continuous damage (8 bytes more per
#               bond, a pass of its own before the force); other physics, so
#               only its rate compares (ratio column against LAMMPS' dmg)
#   dmg-energy  as dmg with PeriDeal's Critical energy, G_c = 9 K s_c^2 horizon / 5
#               (the release rate of dmg's critical stretch): a pass of its
#               own before the force, the material's bond energies (PMB and
#               LPS only; ratio column against LAMMPS' dmg)
#
# Every case runs PeriDeal, then LAMMPS right after it (interleaved), so that
# both see about the same machine load; compare ratios, not absolute times.
#
# usage: bench/cube_explicit.sh [options]
#   -m, --models LIST      pmb lps eps ves corr         (default: "pmb lps")
#   -v, --variants LIST    elastic elastic-nd dmg dmg-time dmg-soft dmg-energy  (default: "elastic dmg")
#   -n, --sizes LIST       points per edge              (default: "20 40 60")
#   -r, --ranks LIST       MPI ranks                    (default: "1 2")
#   -R, --reps N           repetitions of every case    (default: 1)
#   -c, --codes LIST       perideal lammps              (default: both)
#       --pd-app PATH      PeriDeal executable          (default: build/pd_app)
#       --yield Y          eps: yield stress            (default: 0.002)
#       --viscous-fraction L  ves: lambda_i             (default: 0.5)
#       --relaxation-time T   ves: tau_i                (default: 1.0)
#       --steps N          time steps                   (default: 200)
#       --globals-freq F   PeriDeal Output/Frequency: 200 writes the globals CSV
#                          (kinetic energy, damage) at steps 0 and 200 only, no
#                          field files; 0 writes nothing    (default: 200)
#       --lps-influence E  PeriDeal LPS influence function in the timed runs: a
#                          muparser expression in r = |xi|/horizon, or 'lammps'
#                          for what LAMMPS uses in effect (1/|xi| times its
#                          partial-volume factor near the horizon)  (default: 1)
#       --pair             after every 1-rank PeriDeal case, run two independent
#                          1-rank processes of it at once, one per core: the
#                          machine's own ceiling for the 2-rank efficiency (no
#                          MPI between them: what they lose is the machine's)
#       --contact          PeriDeal with self contact on (Short range force,
#                          contact radius 0.9 h, spring constant 15 K: what
#                          LAMMPS' pair peri applies to every pair closer than
#                          0.9 of its reference distance, always on)
#       --no-physics       skip the physics check (n = 20, 1 rank, both codes,
#                          kinetic energy every 50 steps; PeriDeal's mean damage
#                          from its Damage field; LPS also with 'lammps' influence;
#                          eps: PeriDeal's yielded share of the points; corr
#                          against PeriDeal's LPS instead of LAMMPS)
#   -o, --out DIR          results directory   (default: bench/results/<date-time>)
#       --summarize DIR    only print the tables of an earlier results directory
#   -h, --help
# Lists may be separated by spaces or commas.  A quick run (a few minutes):
#   bench/cube_explicit.sh -n 20 -v elastic --pd-app build-bench/pd_app
#
# Output: a line per run while running, then markdown tables (also in
# DIR/table.md); raw numbers in DIR/results.tsv, logs and parameter files in
# DIR/<code>_<model>_<variant>_n<n>_np<ranks>_r<rep>/.
#
# Measures: loop time (PeriDeal: bonds x steps / its printed bond-update rate;
# LAMMPS: 'Loop time' of the timed run), bond updates per second = directed
# bonds x steps / loop time, peak memory = sum over ranks of the maximum RSS
# (PeriDeal: its summary; LAMMPS: /usr/bin/time -v per rank), PeriDeal's
# scene memory (the same minus each rank's start-up footprint), and the CPU share
# a run got (LAMMPS: its '% CPU use' of the loop; PeriDeal: user+sys over
# elapsed of the whole process, per rank) because the machine may be shared.
set -u -o pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")

MODELS="pmb lps"
VARIANTS="elastic dmg"
SIZES="20 40 60"
RANKS="1 2"
REPS=1
CODES="perideal lammps"
PD_APP="$root/build/pd_app"
STEPS=200
FREQ=200
PHYSICS=1
PAIR=0
CONTACT=0
LPS_INFLUENCE=1
YIELD=0.002
VFRAC=0.5
TAU=1.0
OUT=""
SUMMARIZE=""

usage() { sed -n '2,/^set -u/p' "${BASH_SOURCE[0]}" | sed '$d' | sed 's/^# \{0,1\}//'; }
list() { echo "$1" | tr ',' ' '; }

while [ $# -gt 0 ]; do
  case "$1" in
    -m|--models)     MODELS=$(list "$2"); shift 2;;
    -v|--variants)   VARIANTS=$(list "$2"); shift 2;;
    -n|--sizes)      SIZES=$(list "$2"); shift 2;;
    -r|--ranks)      RANKS=$(list "$2"); shift 2;;
    -R|--reps)       REPS=$2; shift 2;;
    -c|--codes)      CODES=$(list "$2"); shift 2;;
    --pd-app)        PD_APP=$2; shift 2;;
    --steps)         STEPS=$2; shift 2;;
    --globals-freq)  FREQ=$2; shift 2;;
    --lps-influence) LPS_INFLUENCE=$2; shift 2;;
    --yield)         YIELD=$2; shift 2;;
    --viscous-fraction) VFRAC=$2; shift 2;;
    --relaxation-time)  TAU=$2; shift 2;;
    --no-physics)    PHYSICS=0; shift;;
    --pair)          PAIR=1; shift;;
    --contact)       CONTACT=1; shift;;
    -o|--out)        OUT=$2; shift 2;;
    --summarize)     SUMMARIZE=$2; shift 2;;
    -h|--help)       usage; exit 0;;
    *) echo "Error: unknown option '$1' (see --help)" >&2; exit 2;;
  esac
done

for m in $MODELS; do case $m in pmb|lps|eps|ves|corr) ;; *) echo "Error: unknown model '$m'" >&2; exit 2;; esac; done
for v in $VARIANTS; do case $v in elastic|elastic-nd|dmg|dmg-time|dmg-soft|dmg-energy) ;; *) echo "Error: unknown variant '$v'" >&2; exit 2;; esac; done
for c in $CODES; do case $c in perideal|lammps) ;; *) echo "Error: unknown code '$c'" >&2; exit 2;; esac; done

has() { case " $2 " in *" $1 "*) return 0;; *) return 1;; esac; }

# LAMMPS' peri/lps in effect: omega = 1/|xi| (any constant factor cancels in
# LPS), times vfrac_scale = 3.515 - |xi|/h for ||xi| - delta| <= h/2, applied in
# the weighted volume, the dilatation and the force alike; with delta = 3.015 h
# and r = |xi|/delta this is:
LAMMPS_INFLUENCE='(abs(3.015*r-3.015) <= 0.5 ? 3.515-3.015*r : 1)/r'
[ "$LPS_INFLUENCE" = lammps ] && LPS_INFLUENCE=$LAMMPS_INFLUENCE

# ------------------------------------------------------------------ helpers

# Directed bond count (sum of family sizes) of the n^3 lattice with horizon
# 3.015 h; the logic of lammps/bondcount.py.  20: 816728, 40: 7153608, 60: 24866488.
bond_count() {
  awk -v n="$1" 'BEGIN {
    t = 0; k = 0
    for (a = -3; a <= 3; a++) for (b = -3; b <= 3; b++) for (c = -3; c <= 3; c++) {
      r = a*a + b*b + c*c
      if (r == 0 || r > 3.015*3.015) continue
      k++; t += (n - (a<0?-a:a)) * (n - (b<0?-b:b)) * (n - (c<0?-c:c))
    }
    if (k != 122) { print "bad offset count " k > "/dev/stderr"; exit 1 }
    printf "%d\n", t }'
}

variant_params() { # -> "s_c vamp"
  case $1 in
    elastic|elastic-nd) echo "1.0 0.01";;
    dmg|dmg-time|dmg-soft|dmg-energy) echo "0.005 0.02";;
  esac
}

# PeriDeal parameter file of one case.
write_prm() { # model variant n file output-frequency output-variables lps-influence
  local model=$1 var=$2 n=$3 file=$4 freq=$5 vars=$6 influence=$7
  local sc vamp horizon dt
  read -r sc vamp <<< "$(variant_params "$var")"
  horizon=$(awk -v n="$n" 'BEGIN { printf "%.15g", 3.015 / n }')
  dt=$(awk -v n="$n" 'BEGIN { printf "%.15g", 0.3560630338 / n }')
  {
    echo "# cube-explicit, $model $var, n = $n (generated by bench/cube_explicit.sh)"
    echo "subsection Discretization"
    echo "  set Type = Box"
    echo "  set Horizon = $horizon"
    echo "  subsection Box"
    echo "    set Lower corner = 0,0,0"
    echo "    set Upper corner = 1,1,1"
    echo "    set Subdivisions = $n,$n,$n"
    echo "  end"
    echo "end"
    echo "subsection Materials"
    echo "  set Names = mat"
    echo "  subsection mat"
    case $model in
      pmb) echo "    set Model = PMB";;
      lps) echo "    set Model = LPS"
           echo "    set Shear modulus = 0.6"
           echo "    set Influence function = $influence";;
      eps) echo "    set Model = Elastic plastic"
           echo "    set Shear modulus = 0.6"
           echo "    set Yield stress = $YIELD";;
      ves) echo "    set Model = Viscoelastic"
           echo "    set Shear modulus = 0.6"
           echo "    set Viscous fraction = $VFRAC"
           echo "    set Relaxation time = $TAU";;
      corr) echo "    set Model = Elastic correspondence"
           echo "    set Shear modulus = 0.6";;
    esac
    echo "    set Density = 1"
    echo "    set Bulk modulus = 1"
    echo "  end"
    echo "end"
    if [ "$var" != elastic-nd ]; then
      echo "subsection Damage models"
      echo "  set Names = stretch"
      echo "  subsection stretch"
      if [ "$var" = dmg-time ]; then
        echo "    set Model = Time dependent critical stretch"
        echo "    set Critical stretch = $sc + 0*t"
      elif [ "$var" = dmg-soft ]; then
        echo "    set Model = Linear softening"
        echo "    set Onset stretch = $(awk -v s="$sc" 'BEGIN { print 0.8 * s }')"
        echo "    set Critical stretch = $sc"
      elif [ "$var" = dmg-energy ]; then
        echo "    set Model = Critical energy"
        echo "    set Critical energy release rate = $(awk -v s="$sc" -v h="$horizon" 'BEGIN { printf "%.15g", 9 * s * s * h / 5 }')"
      else
        echo "    set Model = Critical stretch"
        echo "    set Critical stretch = $sc"
      fi
      [ "$model" = corr ] && [ "$var" != elastic ] && echo "    set Critical damage to neglect material point = 0.5"
      echo "  end"
      echo "end"
    fi
    echo "subsection Blocks"
    echo "  set Names = cube"
    echo "  subsection cube"
    echo "    set Material = mat"
    [ "$var" != elastic-nd ] && echo "    set Damage model = stretch"
    echo "  end"
    echo "end"
    echo "subsection Boundary conditions"
    echo "  set Names = vx, vy, vz"
    for c in x y z; do
      echo "  subsection v$c"
      echo "    set Type = Initial velocity"
      echo "    set Component = $c"
      echo "    set Value = $vamp*($c-0.5)"
      echo "  end"
    done
    echo "end"
    if [ "$CONTACT" = 1 ]; then
      echo "subsection Contact models"
      echo "  set Names = short"
      echo "  subsection short"
      echo "    set Model = Short range force"
      echo "    set Contact radius = $(awk -v n="$n" 'BEGIN { printf "%.15g", 0.9 / n }')"
      echo "    set Spring constant = 15"
      echo "  end"
      echo "end"
      echo "subsection Contact"
      echo "  set Self contact model = short"
      echo "end"
    fi
    echo "subsection Solver"
    echo "  set Type = Verlet"
    echo "  set Number of steps = $STEPS"
    echo "  subsection Verlet"
    echo "    set Fixed dt = $dt"
    echo "  end"
    echo "end"
    echo "subsection Output"
    echo "  set Directory = output"
    echo "  set Base name = cube"
    echo "  set Frequency = $freq"
    echo "  set Variables = $vars"
    echo "  set Write globals = true"
    echo "end"
  } > "$file"
}

# "ke0 ke_end se_end broken max_damage dissipation" from a PeriDeal globals CSV
# (- if absent; dissipation 0 for a model that dissipates nothing).
pd_globals() {
  local csv=$1
  if [ ! -s "$csv" ]; then echo "- - - - - -"; return; fi
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
           NR == 2 { ke0 = $col["kinetic_energy"] }
           { ke = $col["kinetic_energy"]; se = $col["strain_energy"];
             br = $col["broken_bonds"]; md = $col["max_damage"]
             ds = ("material_dissipation" in col) ? $col["material_dissipation"] : 0 }
           END { print ke0, ke, se, br, md, ds }' "$csv"
}

# Seconds of a TimerOutput section in a PeriDeal log ("0" if absent).
pd_timer() {
  awk -F'|' -v s="$2" '{ name = $2; gsub(/^ +| +$/, "", name) }
    name == s { t = $4; gsub(/[ s]/, "", t); print t; found = 1; exit }
    END { if (!found) print 0 }' "$1"
}

# Extra LAMMPS variables of a model (its material parameters).
lmp_vars() { # model
  case $1 in
    eps) echo "-var Y $YIELD";;
    ves) echo "-var lambda $VFRAC -var tau $TAU";;
  esac
}
has_lammps() { case $1 in pmb|lps|eps|ves) return 0;; *) return 1;; esac; }

# "step ke pe dave dmax" lines of the last LAMMPS run in a log (raw LAMMPS units).
lmp_thermo_rows() {
  awk '/^ *Step / { delete row; n = 0; inb = 1; next }
       /^Loop time/ { inb = 0; next }
       inb && $1 ~ /^[0-9]+$/ { row[++n] = $1 " " $3 " " $4 " " $5 " " $6 }
       END { for (i = 1; i <= n; i++) print row[i] }' "$1"
}

# Average over ranks of the CPU share (user+sys)/elapsed, in percent, and the
# sum over ranks of the maximum RSS in MiB, from /usr/bin/time -v files.
time_files() { # files...
  awk -F': ' '
    /User time/ { u += $2 } /System time/ { s += $2 }
    /Elapsed \(wall clock\)/ { k = split($2, p, ":"); e = 0; for (i = 1; i <= k; i++) e = e * 60 + p[i]; el += e; nf++ }
    /Maximum resident set size/ { rss += $2 }
    END { if (nf == 0 || el == 0) print "- -"; else printf "%.0f %.1f\n", 100 * (u + s) / el, rss / 1024 }' "$@"
}

loadavg() { cut -d' ' -f1 /proc/loadavg; }

# ---------------------------------------------------------------- summary

COLS="code model variant n ranks rep status loop_s bonds updates peak_mib ke0 ke_end se_end broken dmax dave t_force t_damage t_ghost t_integ t_output cpu_pct load1 scene_mib t_sums diss_end"

summarize() { # results.tsv
  awk -F'\t' -v steps="$STEPS" '
    function median(s,   a, k, i, j, t) {
      k = split(s, a, ",")
      for (i = 2; i <= k; i++) { t = a[i] + 0; for (j = i - 1; j >= 1 && a[j] + 0 > t; j--) a[j+1] = a[j]; a[j+1] = t }
      return (k % 2) ? a[(k+1)/2] : (a[k/2] + a[k/2+1]) / 2
    }
    # (mawk creates arr[key] before it evaluates the right-hand side)
    function add(arr, key, v,   had) { had = (key in arr); if (had) arr[key] = arr[key] "," v; else arr[key] = v }
    function fmt(x, f) { return (x == "" || x == "-") ? "-" : sprintf(f, x) }
    function name(c) { return c == "perideal" ? "PeriDeal" : "LAMMPS" }
    # bytes per bond from peak RSS (and scene memory), with the verdict
    # (the 24 B/bond target is for PMB and LPS; the others only report)
    function bpb(rss, pss, b, m,   x, y) {
      x = rss * 1048576 / b
      if (m != "pmb" && m != "lps") return (pss == "") ? sprintf("%.1f", x) : sprintf("%.1f (%.1f)", x, pss * 1048576 / b)
      if (pss == "") return sprintf("%.1f %s", x, x <= 24 ? "met" : "**not met**")
      y = pss * 1048576 / b
      return sprintf("%.1f (%.1f) %s", x, y, (x <= 24 ? "met" : (y <= 24 ? "met by scene memory" : "**not met**")))
    }
    # The LAMMPS run a PeriDeal case compares with: the same case; for
    # elastic-nd, LAMMPS runs elastic, so an elastic run serves if needed.
    # corr (no LAMMPS model) compares with the PeriDeal LPS run of the same case.
    function peer(m, v, n, r,   k) {
      if (m == "corr") return "perideal" SUBSEP "lps" SUBSEP v SUBSEP n SUBSEP r
      k = "lammps" SUBSEP m SUBSEP v SUBSEP n SUBSEP r
      if (!(k in U) && v == "elastic-nd") k = "lammps" SUBSEP m SUBSEP "elastic" SUBSEP n SUBSEP r
      if (!(k in U) && (v == "dmg-time" || v == "dmg-soft" || v == "dmg-energy")) k = "lammps" SUBSEP m SUBSEP "dmg" SUBSEP n SUBSEP r
      return k
    }
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["status"] != "ok" { failed[$c["code"] " " $c["model"] " " $c["variant"] " n=" $c["n"] " np=" $c["ranks"] " rep " $c["rep"] ": " $c["status"]] = 1; next }
    # two independent 1-rank runs at once: the sum of their rates
    $c["ranks"] == "pair" { add(pairs, $c["model"] SUBSEP $c["variant"] SUBSEP $c["n"], $c["updates"]); next }
    {
      key = $c["code"] SUBSEP $c["model"] SUBSEP $c["variant"] SUBSEP $c["n"] SUBSEP $c["ranks"]
      if (!(key in seen)) { seen[key] = 1; order[++nk] = key }
      add(loops, key, $c["loop_s"]); add(mems, key, $c["peak_mib"]); reps[key]++
      if (("scene_mib" in c) && $c["scene_mib"] != "-" && $c["scene_mib"] != "") add(scene, key, $c["scene_mib"])
      add(cpus, key, ($c["cpu_pct"] == "-" ? 100 : $c["cpu_pct"]))
      add(loads, key, $c["load1"])
      bonds[key] = $c["bonds"]
      ke0[key] = $c["ke0"]; ke[key] = $c["ke_end"]; se[key] = $c["se_end"]
      br[key] = $c["broken"]; dmax[key] = $c["dmax"]; dave[key] = $c["dave"]
      add(tf, key, $c["t_force"]); add(td, key, $c["t_damage"]); add(tg, key, $c["t_ghost"])
      add(ti, key, $c["t_integ"]); add(to, key, $c["t_output"])
      add(ts, key, ("t_sums" in c) && $c["t_sums"] != "" ? $c["t_sums"] : 0)
      ds[key] = ("diss_end" in c) && $c["diss_end"] != "" && $c["diss_end"] != "-" ? $c["diss_end"] : 0
    }
    END {
      # order: model, variant, n, ranks, code (PeriDeal first)
      for (i = 1; i <= nk; i++) {
        split(order[i], f, SUBSEP)
        sk[i] = sprintf("%s %s %06d %03d %s", f[2], f[3], f[4], f[5], f[1] == "perideal" ? "a" : "b")
      }
      for (i = 2; i <= nk; i++) { t = order[i]; u = sk[i]; for (j = i - 1; j >= 1 && sk[j] > u; j--) { order[j+1] = order[j]; sk[j+1] = sk[j] } order[j+1] = t; sk[j+1] = u }
      for (i = 1; i <= nk; i++) {
        key = order[i]; L[key] = median(loops[key]); U[key] = bonds[key] * steps / L[key]; M[key] = median(mems[key])
        C[key] = median(cpus[key]); UC[key] = U[key] / (C[key] / 100)
        P[key] = (key in scene) ? median(scene[key]) : ""
      }
      print "### Performance (median over repetitions)"
      print ""
      print "Ratio = PeriDeal/LAMMPS bond updates per second per core (same case, same ranks; CORR: over PeriDeal LPS); efficiency = updates/s on 2 ranks / (2 x on 1 rank). CPU = CPU share the run got (100% = a whole core per rank); the \"per CPU-s\" columns divide by it, an estimate for an idle machine."
      print ""
      print "| code | model | variant | n | ranks | reps | loop [s] | bond updates/s | per core | peak mem [MiB] | bytes/bond | ratio | 2-rank eff. | CPU | per CPU-s per core | ratio per CPU-s | eff. per CPU-s | load |"
      print "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
      for (i = 1; i <= nk; i++) {
        key = order[i]; split(key, f, SUBSEP)
        other = peer(f[2], f[3], f[4], f[5])
        ratio = "-"; ratioc = "-"
        if (f[1] == "perideal" && (other in U)) { ratio = sprintf("%.2f", U[key] / U[other]); ratioc = sprintf("%.2f", UC[key] / UC[other]) }
        eff = "-"; effc = "-"
        one = f[1] SUBSEP f[2] SUBSEP f[3] SUBSEP f[4] SUBSEP 1
        if (f[5] == 2 && (one in U)) { eff = sprintf("%.0f%%", 100 * U[key] / (2 * U[one])); effc = sprintf("%.0f%%", 100 * UC[key] / (2 * UC[one])) }
        printf "| %s | %s | %s | %d | %d | %d | %.3f | %.1f M | %.1f M | %.0f | %.1f | %s | %s | %.0f%% | %.1f M | %s | %s | %s |\n",
          name(f[1]), toupper(f[2]), f[3], f[4], f[5], reps[key], L[key],
          U[key] / 1e6, U[key] / 1e6 / f[5], M[key], M[key] * 1048576 / bonds[key], ratio, eff,
          C[key], UC[key] / 1e6 / f[5], ratioc, effc, median(loads[key])
      }
      print ""
      print "### Targets (PeriDeal; wall clock, and in brackets per CPU-second)"
      print ""
      print "Bytes per bond: peak RSS summed over ranks; in brackets the scene memory, the same minus what each rank holds before it reads the scene (the libraries deal.II, Trilinos, p4est, MPI: about 150 MiB per rank)."
      print ""
      print "Machine ceiling (--pair): the summed rate of two independent 1-rank runs at once over twice the 1-rank rate; the efficiency no 2-rank run can beat on this machine but by chance. Relative: the 2-rank rate over that summed rate."
      print ""
      print "| model | variant | n | ratio per core, 1 rank (>= 2) | ratio per core, 2 ranks (>= 2) | bytes/bond, 1 rank (PMB, LPS <= 24) | bytes/bond, 2 ranks (PMB, LPS <= 24) | 2-rank efficiency (>= 90%) | LAMMPS 2-rank efficiency | machine ceiling | 2-rank rate / pair rate |"
      print "|---|---|---|---|---|---|---|---|---|---|---|"
      for (i = 1; i <= nk; i++) {
        key = order[i]; split(key, f, SUBSEP)
        if (f[1] != "perideal") continue
        base = f[2] SUBSEP f[3] SUBSEP f[4]
        if (base in done) continue
        done[base] = 1
        p1 = "perideal" SUBSEP base SUBSEP 1; p2 = "perideal" SUBSEP base SUBSEP 2
        l1 = peer(f[2], f[3], f[4], 1);       l2 = peer(f[2], f[3], f[4], 2)
        # corr: no target, its rate over the PeriDeal LPS rate (awk creates
        # U[k] when it reads it: test "in" first)
        r1 = "-"; r2 = "-"
        if ((p1 in U) && (l1 in U))
          r1 = sprintf("%.2f (%.2f) %s", U[p1] / U[l1], UC[p1] / UC[l1], f[2] == "corr" ? "of LPS" : (U[p1] / U[l1] >= 2 ? "met" : "**not met**"))
        if ((p2 in U) && (l2 in U))
          r2 = sprintf("%.2f (%.2f) %s", U[p2] / U[l2], UC[p2] / UC[l2], f[2] == "corr" ? "of LPS" : (U[p2] / U[l2] >= 2 ? "met" : "**not met**"))
        bb = (p1 in U) ? bpb(M[p1], P[p1], bonds[p1], f[2]) : "-"
        b2 = (p2 in U) ? bpb(M[p2], P[p2], bonds[p2], f[2]) : "-"
        e  = ((p1 in U) && (p2 in U)) ? sprintf("%.0f%% (%.0f%%) %s", 100 * U[p2] / (2 * U[p1]), 100 * UC[p2] / (2 * UC[p1]), U[p2] / (2 * U[p1]) >= 0.9 ? "met" : "**not met**") : "-"
        le = (f[2] != "corr" && (l1 in U) && (l2 in U)) ? sprintf("%.0f%% (%.0f%%)", 100 * U[l2] / (2 * U[l1]), 100 * UC[l2] / (2 * UC[l1])) : "-"
        ceil = "-"; rel = "-"
        if ((base in pairs) && (p1 in U)) ceil = sprintf("%.0f%%", 100 * median(pairs[base]) / (2 * U[p1]))
        if ((base in pairs) && (p2 in U)) rel = sprintf("%.0f%%", 100 * U[p2] / median(pairs[base]))
        printf "| %s | %s | %d | %s | %s | %s | %s | %s | %s | %s | %s |\n", toupper(f[2]), f[3], f[4], r1, r2, bb, b2, e, le, ceil, rel
      }
      print ""
      print "### Where PeriDeal spends the time loop (TimerOutput of rank 0, median; seconds and share of the loop)"
      print ""
      print "| model | variant | n | ranks | loop [s] | force | damage | ghost exchange | global sums | time integration | output | rest of the loop |"
      print "|---|---|---|---|---|---|---|---|---|---|---|---|"
      for (i = 1; i <= nk; i++) {
        key = order[i]; split(key, f, SUBSEP)
        if (f[1] != "perideal") continue
        a = median(tf[key]); b = median(td[key]); g = median(tg[key]); t = median(ti[key]); o = median(to[key])
        q = median(ts[key])
        rest = L[key] - a - b - g - q - t - o
        printf "| %s | %s | %d | %d | %.3f | %.3f (%.0f%%) | %.3f (%.0f%%) | %.3f (%.0f%%) | %.3f (%.0f%%) | %.3f (%.0f%%) | %.4f (%.2f%%) | %.3f (%.0f%%) |\n",
          toupper(f[2]), f[3], f[4], f[5], L[key], a, 100*a/L[key], b, 100*b/L[key], g, 100*g/L[key],
          q, 100*q/L[key], t, 100*t/L[key], o, 100*o/L[key], rest, 100*rest/L[key]
      }
      print ""
      print "### Physics at step " steps " of the timed runs (energies in PeriDeal units: LAMMPS ke, pe x h^3)"
      print ""
      print "| model | variant | n | ranks | KE(0) PeriDeal | KE(0) LAMMPS | KE(" steps ") PeriDeal | KE(" steps ") LAMMPS | PeriDeal/LAMMPS | KE+SE+D(" steps ")/KE(0) PeriDeal | max damage PeriDeal / LAMMPS | broken bonds PeriDeal (fraction) | mean damage LAMMPS |"
      print "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
      for (i = 1; i <= nk; i++) {
        key = order[i]; split(key, f, SUBSEP)
        if (f[1] != "perideal") continue
        other = "lammps" SUBSEP f[2] SUBSEP f[3] SUBSEP f[4] SUBSEP f[5]
        if (!(other in U)) other = peer(f[2], f[3], f[4], f[5])
        h = (other in U) && f[2] != "corr"
        r = (h && ke[other] != "-" && ke[other] + 0 > 0 && ke[key] != "-") ? sprintf("%.4f", ke[key] / ke[other]) : "-"
        tot = (ke[key] != "-" && ke0[key] + 0 > 0) ? sprintf("%.5f", (ke[key] + se[key] + ds[key]) / ke0[key]) : "-"
        frac = (br[key] == "-") ? "-" : sprintf("%.0f (%.4f)", br[key], br[key] / (bonds[key] / 2))
        printf "| %s | %s | %d | %d | %s | %s | %s | %s | %s | %s | %s / %s | %s | %s |\n",
          toupper(f[2]), f[3], f[4], f[5], fmt(ke0[key], "%.6g"), h ? fmt(ke0[other], "%.6g") : "-",
          fmt(ke[key], "%.6g"), h ? fmt(ke[other], "%.6g") : "-", r, tot,
          fmt(dmax[key], "%.4f"), h ? fmt(dmax[other], "%.4f") : "-", frac, h ? fmt(dave[other], "%.4f") : "-"
      }
      nf = 0; for (k in failed) nf++
      if (nf) { print ""; print "Failed runs:"; for (k in failed) print "- " k }
    }' "$1"
}

# Statistics of a point field of a PeriDeal run (the .vtu pieces of the last
# step): "mean max share" with share the fraction of points where it is > 0.
# deal.II writes cell data as point data (8 equal vertex values per cell),
# which leaves the mean, the maximum and the share unchanged.
pd_field() { # output dir, field name
  python3 - "$1" "$2" <<'EOF' 2>/dev/null || echo "- - -"
import base64, glob, re, struct, sys, zlib
d, name = sys.argv[1], sys.argv[2]
stems = sorted(set(re.sub(r'\.\d+\.vtu$', '', f) for f in glob.glob(d + '/cube_*.vtu')))
vals = []
for f in glob.glob(stems[-1] + '.*.vtu'):
    text = open(f).read()
    m = re.search(r'(<DataArray[^>]*Name="' + re.escape(name) + r'"[^>]*>)\s*([^<]*)<', text)
    head, raw = m.group(1), m.group(2).strip()
    fmt = 'f' if 'Float32' in head else 'd'
    if 'format="binary"' in head:
        # zlib-compressed base64 blocks; the header (uint32: blocks, block size,
        # last block size, compressed sizes) is encoded on its own
        nb = struct.unpack('<I', base64.b64decode(raw[:8])[:4])[0]
        hlen = ((4 * (3 + nb) + 2) // 3) * 4
        h = base64.b64decode(raw[:hlen])
        sizes = struct.unpack('<%dI' % nb, h[12:12 + 4 * nb])
        data = base64.b64decode(raw[hlen:])
        out = b''; pos = 0
        for s in sizes:
            out += zlib.decompress(data[pos:pos + s]); pos += s
        vals += struct.unpack('<%d%s' % (len(out) // struct.calcsize(fmt), fmt), out)
    else:
        vals += [float(v) for v in raw.split()]
print('%.6g %.6g %.6g' % (sum(vals) / len(vals), max(vals), sum(1 for v in vals if v > 0) / len(vals)))
EOF
}

# One PeriDeal run of the physics check (n = 20, 1 rank, output every 50
# steps) in DIR, unless it is there already.
physics_pd_run() { # model variant influence dir
  local m=$1 v=$2 infl=$3 dir=$4 vars=""
  [ -s "$dir/output/cube.globals.csv" ] && return
  mkdir -p "$dir"
  [ "$v" = dmg ] && vars="Damage"
  [ "$m" = eps ] && vars="${vars:+$vars, }Equivalent plastic strain"
  write_prm "$m" "$v" 20 "$dir/pd.prm" 50 "$vars" "$infl"
  (cd "$dir" && mpirun -np 1 --bind-to core "$PD_APP" pd.prm > pd.log 2>&1)
}

# Physics check: n = 20, 1 rank, both codes; kinetic energy every 50 steps, and
# for dmg the damage. LPS runs twice in PeriDeal: with the influence function of
# the timed runs and with LAMMPS' effective one. Elastic plastic and
# Viscoelastic have omega = 1 (no key): they differ from LAMMPS as LPS with
# influence 1 does, and in the plastic or viscous part (doc/performance.md).
# Elastic correspondence has no LAMMPS model: it is compared with PeriDeal's
# LPS (influence 1), the same K and G.
physics_check() { # out dir
  local out=$1 m v setups s infl dir refdir sc vamp ref
  local md="$out/physics.md"
  {
    echo "### Physics check: n = 20, 1 rank, kinetic energy at steps 0, 50, ..., $STEPS (PeriDeal units)"
    echo
    echo "PeriDeal's LPS influence \"1\" (its default) and \"lammps\" = $LAMMPS_INFLUENCE (LAMMPS' 1/|xi| with its partial-volume factor); Elastic plastic and Viscoelastic have omega = 1. EPS yield stress $YIELD; VES viscous fraction (lambda_i) $VFRAC, relaxation time (tau_i) $TAU. D = PeriDeal's material dissipation (plastic or viscous); LAMMPS' pe of EPS and VES is its stored energy only."
    echo
    echo "| model | variant | PeriDeal setup | reference | max rel. KE difference | KE($STEPS) PeriDeal | KE($STEPS) reference | (KE+SE+D)($STEPS)/KE(0) PeriDeal | D($STEPS)/KE(0) PeriDeal | (KE+PE)($STEPS)/KE(0) reference | mean damage PeriDeal / reference | max damage PeriDeal / reference | EPS: points yielded, max eps_p |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
  } > "$md"
  for m in $MODELS; do
    for v in $VARIANTS; do
      read -r sc vamp <<< "$(variant_params "$v")"
      if has_lammps "$m"; then
        ref=LAMMPS
        refdir="$out/physics_lammps_${m}_${v}"
        if [ ! -s "$refdir/lmp.log" ]; then
          mkdir -p "$refdir"
          (cd "$refdir" && lmp -in "$here/lammps/in.cube_$m" -var n 20 -var s00 "$sc" -var vamp "$vamp" \
             -var nsteps "$STEPS" $(lmp_vars "$m") -log lmp.log -screen none > lmp.out 2>&1)
        fi
        lmp_thermo_rows "$refdir/lmp.log" | awk '{ V = 1 / 8000; print $1, $2 * V, $3 * V, $4, $5 }' > "$refdir/thermo.txt"
      else
        ref="PeriDeal LPS (influence 1)"
        refdir="$out/physics_perideal_lps_${v}_default"
        physics_pd_run lps "$v" 1 "$refdir"
        local rmean="-"; [ "$v" = dmg ] && read -r rmean _ _ <<< "$(pd_field "$refdir/output" Damage)"
        awk -F, -v dave="$rmean" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
          { print $col["step"], $col["kinetic_energy"], $col["strain_energy"], dave, $col["max_damage"] }' \
          "$refdir/output/cube.globals.csv" > "$refdir/thermo.txt"
      fi
      if [ "$m" = lps ]; then setups="default lammps"; else setups="default"; fi
      [ "$m" = lps ] && [ "$LPS_INFLUENCE" != 1 ] && setups="timed lammps"
      for s in $setups; do
        case $s in
          default) infl=1;;
          timed)   infl=$LPS_INFLUENCE;;
          lammps)  infl=$LAMMPS_INFLUENCE;;
        esac
        dir="$out/physics_perideal_${m}_${v}_${s}"
        physics_pd_run "$m" "$v" "$infl" "$dir"
        local mean="-"; [ "$v" = dmg ] && read -r mean _ _ <<< "$(pd_field "$dir/output" Damage)"
        local plastic="-"
        if [ "$m" = eps ]; then
          local pm pmax pshare; read -r pm pmax pshare <<< "$(pd_field "$dir/output" "Equivalent plastic strain")"
          plastic=$(awk -v s="$pshare" -v x="$pmax" 'BEGIN { printf "%.1f%%, %.3g", 100 * s, x }')
        fi
        local label="-"
        case $m in
          lps) label="influence $([ "$s" = lammps ] && echo lammps || echo "$infl")";;
          eps|ves) label="omega 1";;
        esac
        awk -F, -v th="$refdir/thermo.txt" -v m="${m^^}" -v v="$v" -v s="$label" -v ref="$ref" -v mean="$mean" \
            -v steps="$STEPS" -v plastic="$plastic" '
          BEGIN { while ((getline line < th) > 0) { split(line, a, " "); lke[a[1]] = a[2]; lpe[a[1]] = a[3]; ldave[a[1]] = a[4]; ldmax[a[1]] = a[5] } }
          NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
          { st = $col["step"] + 0; ke[st] = $col["kinetic_energy"]; se[st] = $col["strain_energy"]; dm[st] = $col["max_damage"]
            ds[st] = ("material_dissipation" in col) ? $col["material_dissipation"] : 0 }
          END {
            worst = 0
            for (st in lke) if (st in ke) { d = ke[st] / lke[st] - 1; if (d < 0) d = -d; if (d > worst) worst = d }
            printf "| %s | %s | %s | %s | %.2e | %.6g | %.6g | %.5f | %.5f | %.5f | %s / %s | %.4f / %.4f | %s |\n", m, v, s, ref, worst,
              ke[steps], lke[steps], (ke[steps] + se[steps] + ds[steps]) / ke[0], ds[steps] / ke[0],
              (lke[steps] + lpe[steps]) / lke[0], mean, ldave[steps], dm[steps], ldmax[steps], plastic
          }' "$dir/output/cube.globals.csv" >> "$md"
      done
    done
  done
}

# ---------------------------------------------------------------- main

if [ -n "$SUMMARIZE" ]; then
  summarize "$SUMMARIZE/results.tsv"
  if [ -s "$SUMMARIZE/physics.md" ]; then echo; cat "$SUMMARIZE/physics.md"; fi
  exit 0
fi

# Open MPI refuses to run as root without these.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

need_pkg() { # command package
  command -v "$1" > /dev/null 2>&1 && return 0
  echo "$1 not found: installing the Debian package $2" >&2
  local sudo=""; [ "$(id -u)" = 0 ] || sudo=sudo
  $sudo apt-get update -qq && $sudo apt-get install -y -qq "$2" > /dev/null
  command -v "$1" > /dev/null 2>&1 || { echo "Error: cannot install $2" >&2; exit 1; }
}
need_pkg mpirun openmpi-bin
need_pkg /usr/bin/time time
has lammps "$CODES" && need_pkg lmp lammps
if has perideal "$CODES"; then
  [ -x "$PD_APP" ] || { echo "Error: no PeriDeal executable '$PD_APP'. Build it with: mkdir -p build && cd build && cmake -DCMAKE_BUILD_TYPE=Release .. && make -j2 pd_app; or pass --pd-app" >&2; exit 1; }
  PD_APP=$(cd "$(dirname "$PD_APP")" && pwd)/$(basename "$PD_APP")
  bt=$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$(dirname "$PD_APP")/CMakeCache.txt" 2>/dev/null)
  [ "$bt" = Debug ] && echo "Warning: $PD_APP is a Debug build (debug deal.II, -O0); configure with -DCMAKE_BUILD_TYPE=Release to benchmark" >&2
fi
if [ $PHYSICS = 1 ] && has perideal "$CODES" && has lammps "$CODES"; then need_pkg python3 python3; fi

[ -n "$OUT" ] || OUT="$here/results/$(date +%Y%m%d-%H%M%S)"
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
{
  echo "date: $(date -Is)"
  echo "host: $(hostname), cpu: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
  echo "load at start: $(cat /proc/loadavg)"
  if has perideal "$CODES"; then
    src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$(dirname "$PD_APP")/CMakeCache.txt" 2>/dev/null)
    if [ -f "$src/.commit" ]; then commit=$(cat "$src/.commit")
    else commit="$(git -C "$src" rev-parse HEAD 2>/dev/null)$(git -C "$src" status --porcelain -uno 2>/dev/null | grep -q . && echo ' + uncommitted changes')"; fi
    echo "pd_app: $PD_APP (build type: ${bt:-?}, built $(date -r "$PD_APP" -Is) from $src, commit ${commit:-?})"
  fi
  echo "bench script repository: $(git -C "$root" rev-parse --short HEAD 2>/dev/null)"
  echo "lammps: $(dpkg-query -W -f='${Version}' lammps 2>/dev/null)"
  echo "options: --models \"$MODELS\" --yield $YIELD --viscous-fraction $VFRAC --relaxation-time $TAU --variants \"$VARIANTS\" --sizes \"$SIZES\" --ranks \"$RANKS\" --reps $REPS --codes \"$CODES\" --steps $STEPS$([ "$PAIR" = 1 ] && echo ' --pair') --globals-freq $FREQ --lps-influence '$LPS_INFLUENCE'$([ "$CONTACT" = 1 ] && echo ' --contact')"
} > "$OUT/machine.txt"
cat "$OUT/machine.txt"

tsv="$OUT/results.tsv"
[ -s "$tsv" ] || echo "$COLS" | tr ' ' '\t' > "$tsv"

report() { # code m v n np rep status loop upd peak ke cpu
  printf '%s %-8s %-3s %-10s n=%-3s np=%s rep %s: %-6s loop %9.3f s %8.2f M bond updates/s %8.1f MiB  CPU %4s%%  KE(%s) %s\n' \
    "$(date +%T)" "$1" "$2" "$3" "$4" "$5" "$6" "$7" "$8" "$(awk -v u="$9" 'BEGIN { print u / 1e6 }')" "${10}" "${12}" "$STEPS" "${11}"
}

run_perideal() { # model variant n np rep
  local m=$1 v=$2 n=$3 np=$4 rep=$5
  local dir="$OUT/perideal_${m}_${v}_n${n}_np${np}_r${rep}"
  rm -rf "$dir"; mkdir -p "$dir"
  write_prm "$m" "$v" "$n" "$dir/pd.prm" "$FREQ" "" "$LPS_INFLUENCE"
  local load; load=$(loadavg)
  (cd "$dir" && mpirun -np "$np" --bind-to core "$here/lammps/rank_wrap.sh" pd "$PD_APP" pd.prm > pd.log 2>&1)
  local rc=$? status=ok upd bonds peak loop cpu rss
  upd=$(awk '/bond updates per second:/ { print $5; exit }' "$dir/pd.log")
  bonds=$(awk '/^  bonds:/ && /\(directed\)$/ { b = $2 } END { print b }' "$dir/pd.log")
  peak=$(awk '/peak memory:/ { print $3; exit }' "$dir/pd.log")
  local scene; scene=$(awk '/scene memory:/ { print $3; exit }' "$dir/pd.log"); scene=${scene:--}
  read -r cpu rss <<< "$(time_files "$dir"/pd.rank*.time)"
  if [ $rc != 0 ] || [ -z "$upd" ] || [ -z "$bonds" ] || [ -z "$peak" ]; then
    status="failed(rc=$rc)"; upd=0; bonds=${bonds:-0}; peak=${peak:-0}; loop=0
  else
    # The summary prints the loop time to 0.1 s only; the rate has 4 digits.
    loop=$(awk -v b="$bonds" -v s="$STEPS" -v u="$upd" 'BEGIN { printf "%.6g", b * s / (u * 1e6) }')
    upd=$(awk -v u="$upd" 'BEGIN { printf "%.6g", u * 1e6 }')
  fi
  local ke0 ke se br md ds
  read -r ke0 ke se br md ds <<< "$(pd_globals "$dir/output/cube.globals.csv")"
  local tf td tg ti to ts
  tf=$(pd_timer "$dir/pd.log" force); td=$(pd_timer "$dir/pd.log" damage)
  tg=$(pd_timer "$dir/pd.log" "ghost exchange"); ti=$(pd_timer "$dir/pd.log" "time integration")
  to=$(pd_timer "$dir/pd.log" output); ts=$(pd_timer "$dir/pd.log" "global sums")
  printf '%s\n' "perideal $m $v $n $np $rep $status $loop $bonds $upd $peak $ke0 $ke $se $br $md - $tf $td $tg $ti $to $cpu $load $scene $ts $ds" | tr ' ' '\t' >> "$tsv"
  report perideal "$m" "$v" "$n" "$np" "$rep" "$status" "$loop" "$upd" "$peak" "$ke" "$cpu"
}

# Two independent 1-rank runs of one case at the same time, one per core.
run_perideal_pair() { # model variant n rep
  local m=$1 v=$2 n=$3 rep=$4 k pids=() total=0 status=ok rate bonds
  local dir="$OUT/perideal_${m}_${v}_n${n}_pair_r${rep}"
  rm -rf "$dir"
  local load; load=$(loadavg)
  for k in 0 1; do
    mkdir -p "$dir/$k"
    write_prm "$m" "$v" "$n" "$dir/$k/pd.prm" "$FREQ" "" "$LPS_INFLUENCE"
    (cd "$dir/$k" && taskset -c "$k" "$PD_APP" pd.prm > pd.log 2>&1) &
    pids+=($!)
  done
  for k in 0 1; do wait "${pids[$k]}" || status="failed(rc=$?)"; done
  for k in 0 1; do
    rate=$(awk '/bond updates per second:/ { print $5; exit }' "$dir/$k/pd.log")
    [ -n "$rate" ] || { status=failed; rate=0; }
    total=$(awk -v t="$total" -v r="$rate" 'BEGIN { printf "%.6g", t + r * 1e6 }')
  done
  bonds=$(awk '/^  bonds:/ && /\(directed\)$/ { b = $2 } END { print b }' "$dir/0/pd.log")
  printf '%s\n' "perideal $m $v $n pair $rep $status - ${bonds:-0} $total - - - - - - - - - - - - - $load - - -" | tr ' ' '\t' >> "$tsv"
  printf '%s perideal %-3s %-10s n=%-3s two 1-rank runs at once, rep %s: %-6s %8.2f M bond updates/s in all\n' \
    "$(date +%T)" "$m" "$v" "$n" "$rep" "$status" "$(awk -v u="$total" 'BEGIN { print u / 1e6 }')"
}

run_lammps() { # model variant n np rep
  local m=$1 v=$2 n=$3 np=$4 rep=$5
  local dir="$OUT/lammps_${m}_${v}_n${n}_np${np}_r${rep}"
  rm -rf "$dir"; mkdir -p "$dir"
  local sc vamp; read -r sc vamp <<< "$(variant_params "$v")"
  local load; load=$(loadavg)
  (cd "$dir" && mpirun -np "$np" --bind-to core "$here/lammps/rank_wrap.sh" lmp \
     lmp -in "$here/lammps/in.cube_$m" -var n "$n" -var s00 "$sc" -var vamp "$vamp" -var nsteps "$STEPS" \
     $(lmp_vars "$m") -log lmp.log -screen none > lmp.out 2>&1)
  local rc=$? status=ok loop bonds upd peak cpu rss
  loop=$(awk '/^Loop time of/ { t = $4 } END { print t }' "$dir/lmp.log" 2>/dev/null)
  cpu=$(awk '/% CPU use with/ { c = $1 } END { sub(/%/, "", c); print (c == "" ? "-" : c) }' "$dir/lmp.log" 2>/dev/null)
  bonds=$(bond_count "$n")
  read -r _ peak <<< "$(time_files "$dir"/lmp.rank*.time)"
  if [ $rc != 0 ] || [ -z "$loop" ]; then
    status="failed(rc=$rc)"; loop=0; upd=0; peak=0
  else
    upd=$(awk -v b="$bonds" -v s="$STEPS" -v t="$loop" 'BEGIN { printf "%.6g", b * s / t }')
  fi
  # LAMMPS PERI: rmass = density, so its ke is sum 1/2 rho v^2 without the
  # volume; times h^3 it is PeriDeal's kinetic energy.
  local ke0=- ke=- pe=- dave=- dmax=-
  read -r ke0 ke pe dave dmax <<< "$(lmp_thermo_rows "$dir/lmp.log" 2>/dev/null | awk -v n="$n" -v s="$STEPS" '
    { r[$1] = $0 } END { V = 1 / (n * n * n); if (!(0 in r) || !(s in r)) { print "- - - - -"; exit }
      split(r[0], a, " "); split(r[s], b, " "); printf "%.10g %.10g %.10g %s %s\n", a[2] * V, b[2] * V, b[3] * V, b[4], b[5] }')"
  printf '%s\n' "lammps $m $v $n $np $rep $status $loop $bonds $upd $peak $ke0 $ke $pe - $dmax $dave 0 0 0 0 0 $cpu $load - 0 0" | tr ' ' '\t' >> "$tsv"
  report lammps "$m" "$v" "$n" "$np" "$rep" "$status" "$loop" "$upd" "$peak" "$ke" "$cpu"
}

for rep in $(seq 1 "$REPS"); do
  for n in $SIZES; do
    for m in $MODELS; do
      for v in $VARIANTS; do
        for np in $RANKS; do
          has perideal "$CODES" && run_perideal "$m" "$v" "$n" "$np" "$rep"
          has perideal "$CODES" && [ "$PAIR" = 1 ] && [ "$np" = 1 ] && run_perideal_pair "$m" "$v" "$n" "$rep"
          has lammps "$CODES" && has_lammps "$m" && [ "$v" != dmg-time ] && [ "$v" != dmg-soft ] && [ "$v" != dmg-energy ] && run_lammps "$m" "$v" "$n" "$np" "$rep"
        done
      done
    done
  done
done

if [ $PHYSICS = 1 ] && has perideal "$CODES" && has lammps "$CODES"; then
  echo "$(date +%T) physics check (n = 20, 1 rank)"
  physics_check "$OUT"
fi

echo "load at end: $(cat /proc/loadavg)" >> "$OUT/machine.txt"
echo
{
  echo "Results: $OUT"
  echo
  cat "$OUT/machine.txt"
  echo
  summarize "$tsv"
  if [ -s "$OUT/physics.md" ]; then echo; cat "$OUT/physics.md"; fi
} | tee "$OUT/table.md"
