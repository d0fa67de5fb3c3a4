#!/usr/bin/env bash
# Peak memory of `napkin run` and the bytes it stores for one long test of an
# acceleration-only head (array 3a-cg: 3 channels; docs/formats.md
# "Derived-channel storage").
#
#   bench/run_memory_acceleration_only.sh [SAMPLES] [WORKDIR] [BUILD]
#
# Synthesises one random-motion test of SAMPLES samples per channel (default
# 2,000,000: 48 MB of raw float64 channels), runs it under /usr/bin/time -v
# with the default config (float32 derived channels), and prints the
# "Maximum resident set size", the bound 8 x raw channel bytes + 150 MB, and
# the derived channels stored (rows and bytes, read with sqlite3). BUILD: the
# Release build folder (default build/bench of this checkout, configured and
# built here). The catalogue is deleted after use.
set -euo pipefail

SAMPLES=${1:-2000000}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${2:-$ROOT/build/bench-memory}
BUILD=${3:-$ROOT/build/bench}
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

for tool in /usr/bin/time sqlite3; do
  if ! command -v "$tool" > /dev/null; then
    echo "$tool is missing (Debian packages 'time', 'sqlite3')" >&2
    exit 1
  fi
done

[[ $# -ge 3 ]] || build_release "$BUILD" 2 napkin
NAPKIN=$BUILD/cli/napkin
mkdir -p "$WORK"
DB=$WORK/acceleration-only.db
remove_db "$DB"
trap 'remove_db "$DB"' EXIT

"$NAPKIN" --db "$DB" synth --scenario random --array 3a-cg --count 1 --samples "$SAMPLES" > /dev/null
/usr/bin/time -v "$NAPKIN" --quiet --db "$DB" run --threads 2 2> "$WORK/time.txt" > /dev/null ||
  { cat "$WORK/time.txt" >&2; exit 1; }
peak_kb=$(peak_rss_kb "$WORK/time.txt")
raw_bytes=$(( SAMPLES * 3 * 8 ))
bound_kb=$(( (8 * raw_bytes + 150 * 1000 * 1000) / 1024 ))
read -r rows bytes < <(sqlite3 -separator ' ' "$DB" \
  "SELECT count(*), coalesce(sum(length(samples)), 0) FROM derived_channels")

echo "== napkin run, one 3a-cg test of ${SAMPLES} samples x 3 channels ($(( raw_bytes / 1000000 )) MB raw), --threads 2"
printf "Maximum resident set size %8d kB (bound 8 x raw + 150 MB: %d kB)\n" "$peak_kb" "$bound_kb"
printf "derived channels stored: %d rows, %d bytes\n" "$rows" "$bytes"
