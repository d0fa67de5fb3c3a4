#!/usr/bin/env bash
# Peak memory of `napkin report` does not grow with the number of tests: the
# page streams to its file one test at a time (formats/html_report.h
# HtmlReportWriter).
#
#   bench/run_memory_report.sh [SMALL] [LARGE] [SAMPLES] [WORKDIR] [BUILD]
#
# Creates a catalogue of SMALL synthetic tests (default 2,000) of 9 channels
# x SAMPLES samples (default 1,000), runs it, and writes the report of every
# test under /usr/bin/time -v; then the same with LARGE tests (default
# 8,000); prints "Maximum resident set size" of both reports and the page
# sizes. BUILD: the Release build folder (default build/bench of this
# checkout, configured and built here). With KEEP_CATALOGUES=1 the run
# catalogues stay in WORKDIR and are reused by the next call (e.g. to measure
# another build's report on the same catalogues); otherwise they are deleted.
set -euo pipefail

SMALL=${1:-2000}
LARGE=${2:-8000}
SAMPLES=${3:-1000}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${4:-$ROOT/build/bench-memory}
BUILD=${5:-$ROOT/build/bench}
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

require_time
require_larger "$SMALL" "$LARGE"
[[ $# -ge 5 ]] || build_release "$BUILD" 2 napkin
NAPKIN=$BUILD/cli/napkin
mkdir -p "$WORK"

# Prints the peak resident set size (kB) and the page's bytes of `napkin
# report` of a catalogue of $1 run tests.
report_peak() {
  local db=$WORK/report-$1x$SAMPLES.db page=$WORK/report-$1.html
  if [[ ! -f $db ]]; then
    "$NAPKIN" --db "$db" synth --scenario random --count "$1" --samples "$SAMPLES" > /dev/null
    "$NAPKIN" --quiet --db "$db" run --threads 2 > /dev/null
  fi
  /usr/bin/time -v "$NAPKIN" --db "$db" report --out "$page" 2> "$WORK/time.txt" > /dev/null ||
    { cat "$WORK/time.txt" >&2; return 1; }
  [[ ${KEEP_CATALOGUES:-0} == 1 ]] || remove_db "$db"
  echo "$(peak_rss_kb "$WORK/time.txt") $(stat -c %s "$page")"
  rm -f "$page"
}

read -r small_kb small_bytes < <(report_peak "$SMALL")
read -r large_kb large_bytes < <(report_peak "$LARGE")

echo
echo "== peak memory of napkin report, tests of 9 channels x ${SAMPLES} samples"
printf "%6d tests: Maximum resident set size %8d kB, page %d bytes\n" "$SMALL" "$small_kb" "$small_bytes"
printf "%6d tests: Maximum resident set size %8d kB, page %d bytes\n" "$LARGE" "$large_kb" "$large_bytes"
printf "ratio %.3f\n" "$(echo "$large_kb / $small_kb" | bc -l)"
