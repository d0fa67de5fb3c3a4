#!/usr/bin/env bash
# The exact solver against the LC_COMP core, as built and with glibc's malloc
# thresholds raised (issue 31 point 5), in one run of this script.
#
#   bench/run_solver_scale.sh [REPEATS] [LC_COMP_DIR]
#
# LC_COMP_DIR (default ../shared/reference/lc_comp beside the checkout) holds
# the Fortran program reconstructed from the report's Appendix B
# (lc_comp.f90) and its input generator (gen_case.py). This script
#   - builds napkin_bench in Release (build/bench) and lc_comp with
#     gfortran -O2 (Debian package gfortran),
#   - writes a 200,000-sample input of 200 alternating pulses on the Denton
#     array (gen_case.py; numpy of /usr/bin/python3),
#   - then REPEATS times (default 3), one after the other: lc_comp with
#     LC_COMP_TIMING set (its own clock around the computation, read and
#     write left out: samples/s of the core), napkin_bench's exact solver as
#     built and with GLIBC_TUNABLES raising glibc's mmap and trim thresholds
#     (BM_ExactSolverNap20000, best of 5 repetitions, the Kinematics kept
#     from test to test as engine/solver.h offers),
# and prints the best rate of each and the ratios: exact with / without the
# tunables (within 10 % when the solve maps no new pages) and exact / LC_COMP
# in both settings. The load average is printed with them: the machine may
# be shared.
set -euo pipefail

REPEATS=${1:-3}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
LC_COMP_DIR=${2:-$ROOT/../shared/reference/lc_comp}
BUILD=$ROOT/build/bench
WORK=$ROOT/build/bench-scale
TUNABLES=glibc.malloc.mmap_threshold=67108864:glibc.malloc.trim_threshold=268435456
SAMPLES=200000
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

if [[ ! -f $LC_COMP_DIR/lc_comp.f90 || ! -f $LC_COMP_DIR/gen_case.py ]]; then
  echo "no lc_comp.f90 and gen_case.py in $LC_COMP_DIR: pass the folder of the LC_COMP reconstruction" >&2
  exit 2
fi
command -v gfortran > /dev/null || { echo "gfortran is missing: install the Debian package 'gfortran'" >&2; exit 1; }
mkdir -p "$WORK"
build_release "$BUILD" "$(nproc)" napkin_bench
gfortran -O2 -o "$WORK/lc_comp" "$LC_COMP_DIR/lc_comp.f90"
/usr/bin/python3 "$LC_COMP_DIR/gen_case.py" --geom denton --n "$SAMPLES" --periods 200 --alternate \
  -o "$WORK/input.txt"

# M samples/s of napkin's exact solver under GLIBC_TUNABLES=$1 (empty: as
# built): the best of 5 repetitions.
exact_rate() {
  GLIBC_TUNABLES=$1 "$BUILD/bench/napkin_bench" --benchmark_filter='^BM_ExactSolverNap20000$' \
    --benchmark_repetitions=5 --benchmark_color=false 2> /dev/null | sed -n 's/.*exact solver: \([0-9.]*\) M samples.*/\1/p'
}

best() { if [[ -z $1 || $(echo "$2 > $1" | bc -l) == 1 ]]; then echo "$2"; else echo "$1"; fi; }
best_lc= best_plain= best_tuned=
for (( i = 1; i <= REPEATS; i++ )); do
  # "LC_COMP_TIMING npts=N read/compute/total(s): R C T"
  compute_s=$(LC_COMP_TIMING=1 "$WORK/lc_comp" "$WORK/input.txt" "$WORK/output.txt" denton notrunc 2>&1 > /dev/null |
    awk '/LC_COMP_TIMING/ {print $(NF - 1)}')
  lc=$(echo "$SAMPLES / $compute_s / 1000000" | bc -l)
  plain=$(exact_rate "")
  tuned=$(exact_rate "$TUNABLES")
  printf "repeat %d: LC_COMP core %.2f, exact %.2f as built, %.2f with the tunables (M samples/s)\n" \
    "$i" "$lc" "$plain" "$tuned"
  best_lc=$(best "$best_lc" "$lc")
  best_plain=$(best "$best_plain" "$plain")
  best_tuned=$(best "$best_tuned" "$tuned")
done
rm -f "$WORK/output.txt"

echo
echo "== exact solver vs LC_COMP core (gfortran -O2, $SAMPLES samples), best of $REPEATS," \
  "$(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf "LC_COMP core:                    %6.2f M samples/s\n" "$best_lc"
printf "exact solver, as built:          %6.2f M samples/s\n" "$best_plain"
printf "exact solver, GLIBC_TUNABLES:    %6.2f M samples/s\n" "$best_tuned"
printf "exact as built / with tunables:  %6.3f\n" "$(echo "$best_plain / $best_tuned" | bc -l)"
printf "exact / LC_COMP, as built:       %6.3f\n" "$(echo "$best_plain / $best_lc" | bc -l)"
printf "exact / LC_COMP, with tunables:  %6.3f\n" "$(echo "$best_tuned / $best_lc" | bc -l)"
