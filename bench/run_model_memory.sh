#!/usr/bin/env bash
# Peak memory of `napkin correlate --model` against the size of the model's
# curve (issue 42, point 14: a 10^7-point model took 1.26 GB): the readers
# stream the file and keep only the curve rated (formats/model_curves.h), so
# the peak is the curve's doubles and a bounded rest, not the file's text and
# every curve.
#
#   bench/run_model_memory.sh [POINTS] [WORKDIR]
#
# Writes a model of POINTS points (default 10,000,000) twice: an LS-DYNA
# keyword file (*KEYWORD with three *DEFINE_CURVE, the rated one of POINTS
# points in 20-character columns, the two others of POINTS / 10) and a model
# CSV (time_s and three columns, one of them rated), both over the test's
# 0.2 s; rates one synthetic test against each under /usr/bin/time -v, and
# against a 1,000-point model for the process's own memory. Prints each peak
# resident set size and its ratio to the rated curve's bytes (POINTS x 2 x 8:
# its times and values as doubles).
#
# NAPKIN_BEFORE_COMMIT=REV also measures napkin as of that commit (built from
# `git archive REV` in build/bench-before; e.g. c9b1ec0, the last before model
# files were capped at 64 MiB), each binary with a catalogue of its own.
#
# Disk: about 60 bytes per point for the two files (600 MB for 10^7).
set -euo pipefail

POINTS=${1:-10000000}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${2:-$ROOT/build/bench-model-memory}
BUILD=$ROOT/build/bench
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

require_time
require_disk "$WORK" $(( POINTS * 60 / 1000000 + 200 )) "two models of ${POINTS} points"

build_release "$BUILD" "$(nproc)" napkin
declare -A BINARY=([now]=$BUILD/cli/napkin)
LABELS=(now)
if [[ -n ${NAPKIN_BEFORE_COMMIT:-} ]]; then
  BEFORE_SRC=$ROOT/build/bench-before/src
  rm -rf "$BEFORE_SRC" && mkdir -p "$BEFORE_SRC"
  git -C "$ROOT" archive "$NAPKIN_BEFORE_COMMIT" | tar -x -C "$BEFORE_SRC"
  cmake -S "$BEFORE_SRC" -B "$ROOT/build/bench-before/build" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF \
    > /dev/null
  cmake --build "$ROOT/build/bench-before/build" -j"$(nproc)" --target napkin > /dev/null
  BINARY[before]=$ROOT/build/bench-before/build/cli/napkin
  LABELS=(before now)
fi

# The rated curve: a half-sine pulse of 80 g over the test's 0.2 s (times in s, values in g for
# the CSV, in m/s^2 for the keyword file read as m,s,kg).
write_models() {
  local points=$1 stem=$2
  awk -v n="$points" 'BEGIN {
    pi = atan2(0, -1); g = 9.80665
    print "*KEYWORD"
    for (c = 1; c <= 3; c++) {
      m = (c == 2) ? n : int(n / 10)
      print "$ curve " c
      print "*DEFINE_CURVE"
      printf "%10d%10d%10.1f%10.1f\n", c, 0, 1.0, 1.0
      for (k = 0; k < m; k++) {
        t = 0.2 * k / (m - 1)
        printf "%20.13g%20.13g\n", t, c * 80 * g * sin(pi * t / 0.2)
      }
    }
    print "*END"
  }' > "$stem.k"
  awk -v n="$points" 'BEGIN {
    pi = atan2(0, -1)
    print "# a model head response"
    print "time_s,acc_body_x_g,acc_resultant_g,acc_body_z_g"
    for (k = 0; k < n; k++) {
      t = 0.2 * k / (n - 1)
      p = sin(pi * t / 0.2)
      printf "%.10g,%.7g,%.7g,%.7g\n", t, 0.5 * 80 * p, 80 * p, 0.25 * 80 * p
    }
  }' > "$stem.csv"
}

write_models "$POINTS" "$WORK/model"
write_models 1000 "$WORK/small"
ls -l "$WORK/model.k" "$WORK/model.csv"

# Peak RSS (kB) of `$1 correlate` against model spec $3 with options $4... on catalogue $2.
peak_kb() {
  local napkin=$1 db=$2 spec=$3
  shift 3
  local test
  test=$("$napkin" --db "$db" query tests --format csv | awk -F, 'NR == 2 {print $1}')
  /usr/bin/time -v "$napkin" --quiet --db "$db" correlate --test "$test" --channel acc_resultant_g \
    --model "$spec" "$@" > "$WORK/correlate.txt" 2> "$WORK/time.txt" \
    || { cat "$WORK/time.txt" >&2; return 1; }
  peak_rss_kb "$WORK/time.txt"
}

curve_kb=$(( POINTS * 16 / 1024 ))
declare -A RESULT
for label in "${LABELS[@]}"; do
  db=$WORK/$label.db
  remove_db "$db"
  "${BINARY[$label]}" --db "$db" synth --scenario random --count 1 --duration 0.2 > /dev/null
  "${BINARY[$label]}" --quiet --db "$db" run > /dev/null
  RESULT[$label,base]=$(peak_kb "${BINARY[$label]}" "$db" "$WORK/small.csv")
  RESULT[$label,k]=$(peak_kb "${BINARY[$label]}" "$db" "$WORK/model.k:2" --model-units m,s,kg || echo 0)
  RESULT[$label,csv]=$(peak_kb "${BINARY[$label]}" "$db" "$WORK/model.csv" || echo 0)
  remove_db "$db"
done

echo
echo "== peak memory of napkin correlate --model, a curve of ${POINTS} points (${curve_kb} kB as doubles)"
for label in "${LABELS[@]}"; do
  base=${RESULT[$label,base]}
  printf "%-6s 1,000-point model: Maximum resident set size %8d kB\n" "$label" "$base"
  for kind in k csv; do
    kb=${RESULT[$label,$kind]}
    if (( kb == 0 )); then
      printf "%-6s model.%-4s refused (see above)\n" "$label" "$kind"
      continue
    fi
    printf "%-6s model.%-4s Maximum resident set size %8d kB: %.2f x the curve, %.2f x above the 1,000-point run\n" \
      "$label" "$kind" "$kb" "$(echo "$kb / $curve_kb" | bc -l)" "$(echo "($kb - $base) / $curve_kb" | bc -l)"
  done
done
rm -f "$WORK/model.k" "$WORK/model.csv" "$WORK/small.k" "$WORK/small.csv"
