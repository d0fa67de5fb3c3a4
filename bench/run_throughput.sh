#!/usr/bin/env bash
# End-to-end throughput of `napkin run` against the SQLite-only floor, for
# each derived-channel storage choice (issue 12 "I/O at the limit").
#
#   bench/run_throughput.sh [TESTS] [SAMPLES] [THREADS] [WORKDIR] [STORAGE...]
#
# STORAGE: any of float64 float32 none (default: all three).
#
# Builds napkin in Release (build/bench), creates TESTS synthetic tests of
# 9 channels x SAMPLES samples once (napkin synth --scenario random), then for
# each storage choice:
#   - runs `napkin run --threads THREADS --config WORKDIR/config-STORAGE.json`
#     (the default preset with storage.derived_channels = STORAGE) on a fresh
#     copy of the input catalogue, and checks 20 random tests against the
#     transform core (napkin_catalogue_io verify: bit for bit for float64,
#     the stored float32 values for float32, the summaries for none);
#   - runs napkin_catalogue_io io-baseline --storage STORAGE on another fresh
#     copy: the same reads and the same bytes written, without computing;
#     that is the SQLite-only floor;
# and prints one table: run s, floor s, ratio, tests/s, catalogue bytes per
# test, and the float32/float64 tests/s ratio. The load average is printed
# with it: the machine may be shared.
#
# Disk: the input catalogue holds 9 x 8 x SAMPLES bytes per test, and one
# copy at a time exists with its results (at most 36 x 8 x SAMPLES bytes of
# derived channels per test, float64); copies are deleted after use.
set -euo pipefail

TESTS=${1:-1000}
SAMPLES=${2:-20000}
THREADS=${3:-2}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${4:-$ROOT/build/bench-throughput}
shift $(( $# < 4 ? $# : 4 ))
STORAGES=("$@")
(( ${#STORAGES[@]} > 0 )) || STORAGES=(float64 float32 none)
for storage in "${STORAGES[@]}"; do
  case $storage in
    float64 | float32 | none) ;;
    *) echo "unknown storage '$storage' (float64, float32 or none)" >&2; exit 2 ;;
  esac
done
BUILD=$ROOT/build/bench
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

derived_bytes=8
for storage in "${STORAGES[@]}"; do [[ $storage == float64 ]] && derived_bytes=8 && break; derived_bytes=4; done
# input + one copy of it + the largest results + 10% WAL and slack
require_disk "$WORK" $(( TESTS * SAMPLES * (9 * 8 * 2 + 36 * derived_bytes) * 11 / 10 / 1000000 + 200 )) \
  "${TESTS} tests x ${SAMPLES} samples"

build_release "$BUILD" "$(nproc)" napkin napkin_catalogue_io
NAPKIN=$BUILD/cli/napkin
IO=$BUILD/bench/napkin_catalogue_io

remove_db "$WORK/input.db"
now() { date +%s.%N; }

t0=$(now)
"$NAPKIN" --db "$WORK/input.db" synth --scenario random --count "$TESTS" --samples "$SAMPLES"
t1=$(now)
echo "synth: $(echo "$t1 - $t0" | bc) s"

declare -A run_s floor_s bytes_per_test
for storage in "${STORAGES[@]}"; do
  config=$WORK/config-$storage.json
  # The default preset with this storage choice and a name of its own.
  sed -e 's/"name": "default"/"name": "bench-'"$storage"'"/' \
    -e 's/"derived_channels": "[a-z0-9]*"/"derived_channels": "'"$storage"'"/' \
    "$ROOT/config/processing/default.json" > "$config"
  grep -q '"derived_channels": "'"$storage"'"' "$config" || {
    echo "config/processing/default.json has no storage.derived_channels key" >&2
    exit 1
  }

  echo
  echo "== storage $storage: napkin run"
  remove_db "$WORK/run.db"
  cp "$WORK/input.db" "$WORK/run.db"
  sync
  t0=$(now)
  "$NAPKIN" --db "$WORK/run.db" run --threads "$THREADS" --config "$config"
  t1=$(now)
  run_s[$storage]=$(echo "$t1 - $t0" | bc -l)
  sync
  "$IO" verify "$WORK/run.db" --sample 20 --seed 7 --config "$config"
  bytes_per_test[$storage]=$(( ($(stat -c %s "$WORK/run.db") - $(stat -c %s "$WORK/input.db")) / TESTS ))
  remove_db "$WORK/run.db"

  echo "== storage $storage: SQLite-only floor"
  remove_db "$WORK/io.db"
  cp "$WORK/input.db" "$WORK/io.db"
  sync
  t0=$(now)
  "$IO" io-baseline "$WORK/io.db" --batch 16 --storage "$storage"
  t1=$(now)
  floor_s[$storage]=$(echo "$t1 - $t0" | bc -l)
  remove_db "$WORK/io.db"
done
remove_db "$WORK/input.db"

echo
echo "== napkin run: ${TESTS} tests x 9 channels x ${SAMPLES} samples, --threads ${THREADS}," \
  "$(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf "%-8s %9s %9s %7s %9s %16s\n" storage "run s" "floor s" ratio "tests/s" "bytes per test"
for storage in "${STORAGES[@]}"; do
  printf "%-8s %9.2f %9.2f %7.2f %9.2f %16d\n" "$storage" "${run_s[$storage]}" "${floor_s[$storage]}" \
    "$(echo "${run_s[$storage]} / ${floor_s[$storage]}" | bc -l)" "$(echo "$TESTS / ${run_s[$storage]}" | bc -l)" \
    "${bytes_per_test[$storage]}"
done
if [[ -n ${run_s[float32]:-} && -n ${run_s[float64]:-} ]]; then
  printf "float32 / float64 tests/s: %.2f\n" "$(echo "${run_s[float64]} / ${run_s[float32]}" | bc -l)"
fi
