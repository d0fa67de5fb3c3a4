#!/usr/bin/env bash
# End-to-end throughput of `napkin run` (issue: batch scheduler).
#
#   bench/run_throughput.sh [TESTS] [SAMPLES] [THREADS] [WORKDIR]
#
# Builds napkin in Release (build/bench), creates TESTS synthetic tests of
# 9 channels x SAMPLES samples (napkin synth --scenario random), runs
# `napkin run --threads THREADS` and reports tests/s and samples/s; then
# measures what SQLite alone needs to read the same inputs and write the same
# outputs (napkin_catalogue_io io-baseline on a copy of the input catalogue)
# and the ratio of the two wall times; finally checks 20 random tests bit for
# bit against the transform core (napkin_catalogue_io verify).
#
# Disk: each test's derived channels are 36 x 8 x SAMPLES bytes (5.8 MB at
# 20,000 samples) and its raw channels 9 x 8 x SAMPLES; the run and the
# baseline each write the derived channels once.
set -euo pipefail

TESTS=${1:-1000}
SAMPLES=${2:-20000}
THREADS=${3:-2}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${4:-$ROOT/build/bench-throughput}
BUILD=$ROOT/build/bench

need_mb=$(( TESTS * SAMPLES * 8 * (9 * 3 + 36 * 2) / 1000000 + 100 ))
mkdir -p "$WORK"
avail_mb=$(df -Pm "$WORK" | awk 'NR == 2 {print $4}')
echo "disk: need about ${need_mb} MB in $WORK, ${avail_mb} MB available"
if (( avail_mb < need_mb )); then
  echo "not enough disk space for ${TESTS} tests x ${SAMPLES} samples" >&2
  exit 1
fi

cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DNAPKIN_BUILD_BENCH=ON > /dev/null
cmake --build "$BUILD" -j"$(nproc)" --target napkin napkin_catalogue_io > /dev/null
NAPKIN=$BUILD/cli/napkin
IO=$BUILD/bench/napkin_catalogue_io

rm -f "$WORK"/*.db "$WORK"/*.db-wal "$WORK"/*.db-shm
now() { date +%s.%N; }

t0=$(now)
"$NAPKIN" --db "$WORK/input.db" synth --scenario random --count "$TESTS" --samples "$SAMPLES"
t1=$(now)
echo "synth: $(echo "$t1 - $t0" | bc) s"
cp "$WORK/input.db" "$WORK/run.db"
cp "$WORK/input.db" "$WORK/io.db"
sync

t0=$(now)
"$NAPKIN" --db "$WORK/run.db" run --threads "$THREADS"
t1=$(now)
run_s=$(echo "$t1 - $t0" | bc -l)
sync

t0=$(now)
"$IO" io-baseline "$WORK/io.db" --batch 16
t1=$(now)
io_s=$(echo "$t1 - $t0" | bc -l)

"$NAPKIN" --db "$WORK/run.db" status
"$IO" verify "$WORK/run.db" --sample 20 --seed 7

samples_total=$(( TESTS * SAMPLES * 9 ))
echo
echo "== napkin run: ${TESTS} tests x 9 channels x ${SAMPLES} samples, --threads ${THREADS}"
printf "run wall time            %8.2f s\n" "$run_s"
printf "throughput               %8.2f tests/s, %.3g samples/s\n" "$(echo "$TESTS / $run_s" | bc -l)" \
  "$(echo "$samples_total / $run_s" | bc -l)"
printf "SQLite-only I/O time     %8.2f s\n" "$io_s"
printf "run / SQLite-only ratio  %8.2f\n" "$(echo "$run_s / $io_s" | bc -l)"
ls -l "$WORK"/input.db "$WORK"/run.db | awk '{printf "%-40s %8.0f MB\n", $9, $5 / 1e6}'
