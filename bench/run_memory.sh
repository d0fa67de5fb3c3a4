#!/usr/bin/env bash
# Peak memory of `napkin run` does not grow with the number of tests
# (issue 12): the scheduler holds a bounded number of tests in memory.
#
#   bench/run_memory.sh [SMALL] [LARGE] [SAMPLES] [THREADS] [WORKDIR] [CONFIG]
#
# Creates a catalogue of SMALL synthetic tests (default 1,000) of 9 channels x
# SAMPLES samples (default 20,000) and runs `napkin run` on it under
# /usr/bin/time -v; then the same with a new catalogue of LARGE tests
# (default 5,000; one catalogue at a time on disk); prints "Maximum resident
# set size" of both runs. CONFIG: the processing config (default: the
# default preset). The catalogues are deleted after use.
#
# Disk: LARGE x SAMPLES x (9 + 36) x 8 bytes at most (float64 derived
# channels); about 22 GB for 5,000 x 20,000 with the default float32.
set -euo pipefail

SMALL=${1:-1000}
LARGE=${2:-5000}
SAMPLES=${3:-20000}
THREADS=${4:-2}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${5:-$ROOT/build/bench-memory}
CONFIG=${6:-default}
BUILD=$ROOT/build/bench
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

require_time
require_larger "$SMALL" "$LARGE"
require_disk "$WORK" $(( LARGE * SAMPLES * 8 * (9 + 36) * 11 / 10 / 1000000 + 200 )) \
  "${LARGE} tests x ${SAMPLES} samples"

build_release "$BUILD" "$(nproc)" napkin
NAPKIN=$BUILD/cli/napkin
DB=$WORK/memory.db
remove_db "$DB"
trap 'remove_db "$DB"' EXIT

# Prints the peak resident set size (kB) of `napkin run` on a new catalogue of $1 tests.
peak_kb() {
  remove_db "$DB"
  "$NAPKIN" --db "$DB" synth --scenario random --count "$1" --samples "$SAMPLES" > /dev/null
  /usr/bin/time -v "$NAPKIN" --quiet --db "$DB" run --threads "$THREADS" --config "$CONFIG" \
    2> "$WORK/time.txt" || { cat "$WORK/time.txt" >&2; return 1; }
  remove_db "$DB"
  peak_rss_kb "$WORK/time.txt"
}

small_kb=$(peak_kb "$SMALL")
large_kb=$(peak_kb "$LARGE")

echo
echo "== peak memory of napkin run, 9 channels x ${SAMPLES} samples, --threads ${THREADS}, config ${CONFIG}"
printf "%6d tests: Maximum resident set size %8d kB\n" "$SMALL" "$small_kb"
printf "%6d tests: Maximum resident set size %8d kB\n" "$LARGE" "$large_kb"
printf "ratio %.3f\n" "$(echo "$large_kb / $small_kb" | bc -l)"
