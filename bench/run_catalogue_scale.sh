#!/usr/bin/env bash
# Whether every command's cost per test stays flat as the catalogue grows
# (issue 45; docs/architecture.md "Catalogues of a million tests"):
#
#   bench/run_catalogue_scale.sh [--large] [WORKDIR]
#
# For catalogues of 2,000 and 20,000 tests (and with --large 200,000: about
# 8 GB of disk and an hour or more on 2 cores) of `napkin synth --scenario
# random --samples 500` tests (9 channels x 500 samples), plus the 15 tests of
# `synth --scenario padding-series`, processed with the default preset storing
# no derived channels (storage.derived_channels none: the numbers show the
# catalogue, not the disk), prints per size:
#   - per test: synth (import), run (--threads 2), run --shard I/4 --results
#     (the four shards of a second config, summed), merge of the four results
#     files; the peak length of the write-ahead log during the run;
#   - latency: status, query hic --where "hic15 > 0" --limit 10, compare of
#     the 15-test padding series (--by variant), GET
#     /api/v1/query/hic?limit=10 of `napkin serve` on a free loopback port
#     (the median of 5 calls each, 31 requests; a command's includes
#     starting napkin);
#   - the time of SQLite's quick_check of the file (every writing command
#     runs it first) and the catalogue's bytes per test by table (dbstat);
# then the ratio of each per-test cost and latency to the smallest
# catalogue's. The goals: per-test costs at 20,000 within 1.3x of 2,000's
# (at 200,000 within 1.5x); status <= 0.5 s and the limited query <= 50 ms
# at 200,000. The load average is printed: the machine may be shared.
#
# napkin: $NAPKIN if set, else the Release build build/release/cli/napkin
# (`make release`), built if missing.
set -euo pipefail

SIZES=(2000 20000)
if [[ ${1:-} == --large ]]; then
  SIZES+=(200000)
  shift
fi
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${1:-$ROOT/build/bench-catalogue-scale}
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

largest=${SIZES[${#SIZES[@]} - 1]}
# The catalogue (37 kB a test), the four results files and the WAL: 45 kB a test, and slack.
require_disk "$WORK" $(( largest * 45 / 1000 + 200 )) "a catalogue of $largest tests"
NAPKIN=${NAPKIN:-$ROOT/build/release/cli/napkin}
if [[ ! -x $NAPKIN ]]; then
  make -C "$ROOT" release JOBS="$(nproc)" > /dev/null
fi
command -v sqlite3 > /dev/null || { echo "sqlite3 is missing: install the Debian package 'sqlite3'" >&2; exit 1; }

now() { date +%s.%N; }
seconds_since() { echo "$(now) - $1" | bc -l; }
# The median of the numbers on stdin.
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# Seconds "$@" takes, the median of 5 runs (output discarded).
latency() {
  for _ in 1 2 3 4 5; do
    local start
    start=$(now)
    "$@" > /dev/null
    seconds_since "$start"
  done | median
}

# The default preset storing no derived channels, and for the shards a second config (another
# plausibility limit, which these tests never reach: another key, the same results).
CONFIG=$WORK/scale.json
SHARD_CONFIG=$WORK/scale-shards.json
sed -e 's/"derived_channels": "[a-z0-9]*"/"derived_channels": "none"/' \
  "$ROOT/config/processing/default.json" > "$CONFIG"
sed -e 's/"max_initial_speed_mps": [0-9.]*/"max_initial_speed_mps": 999.0/' "$CONFIG" > "$SHARD_CONFIG"
grep -q '"derived_channels": "none"' "$CONFIG" && grep -q '"max_initial_speed_mps": 999.0' "$SHARD_CONFIG" || {
  echo "config/processing/default.json has no storage.derived_channels or plausibility.max_initial_speed_mps" >&2
  exit 1
}

declare -A cost
metrics=(synth run shard merge status query compare api)
echo "napkin $("$NAPKIN" --version | head -1); load average $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores"

for n in "${SIZES[@]}"; do
  db=$WORK/scale-$n.db
  remove_db "$db"
  for i in 0 1 2 3; do remove_db "$WORK/shard-$i.db"; done
  echo
  echo "== $n tests (load average $(cut -d' ' -f1-3 /proc/loadavg))"

  start=$(now)
  "$NAPKIN" --quiet --db "$db" synth --scenario random --count "$n" --samples 500 > /dev/null
  "$NAPKIN" --quiet --db "$db" synth --scenario padding-series > /dev/null
  total=$(( n + 15 ))
  cost[synth,$n]=$(echo "$(seconds_since "$start") * 1000 / $total" | bc -l)

  # The run, with the WAL's length sampled every 0.2 s.
  wal_peak=0
  start=$(now)
  "$NAPKIN" --quiet --db "$db" run --config "$CONFIG" --threads 2 &
  run_pid=$!
  while kill -0 "$run_pid" 2> /dev/null; do
    wal=$(stat -c %s "$db-wal" 2> /dev/null || echo 0)
    (( wal > wal_peak )) && wal_peak=$wal
    sleep 0.2
  done
  wait "$run_pid"
  cost[run,$n]=$(echo "$(seconds_since "$start") * 1000 / $total" | bc -l)

  start=$(now)
  for i in 0 1 2 3; do
    "$NAPKIN" --quiet --db "$db" run --config "$SHARD_CONFIG" --threads 2 --shard "$i/4" --results "$WORK/shard-$i.db"
  done
  cost[shard,$n]=$(echo "$(seconds_since "$start") * 1000 / $total" | bc -l)
  start=$(now)
  "$NAPKIN" --quiet --db "$db" merge "$WORK"/shard-{0,1,2,3}.db > /dev/null
  cost[merge,$n]=$(echo "$(seconds_since "$start") * 1000 / $total" | bc -l)

  cost[status,$n]=$(latency "$NAPKIN" --db "$db" status --config "$CONFIG")
  cost[query,$n]=$(latency "$NAPKIN" --db "$db" query hic --where "hic15 > 0" --limit 10)
  cost[compare,$n]=$(latency "$NAPKIN" --db "$db" compare --series padding-series --by variant)

  log=$WORK/serve-$n.log
  "$NAPKIN" --db "$db" serve --listen 127.0.0.1:0 2> "$log" &
  serve_pid=$!
  port=
  for (( i = 0; i < 100 && ${#port} == 0; i++ )); do
    sleep 0.1
    port=$(sed -n 's|.*listening on http://127.0.0.1:\([0-9]*\).*|\1|p' "$log" | head -1)
  done
  if [[ -z $port ]]; then
    kill -TERM "$serve_pid" 2> /dev/null || true
    echo "napkin serve did not start:" >&2
    cat "$log" >&2
    exit 1
  fi
  url="http://127.0.0.1:$port/api/v1/query/hic?limit=10"
  curl -sf -o /dev/null "$url"  # the first request opens the catalogue
  # The median of 31 requests, so that a loaded machine's pauses fall outside it.
  cost[api,$n]=$(for _ in $(seq 31); do curl -sf -o /dev/null -w '%{time_total}\n' "$url"; done | median)
  kill -TERM "$serve_pid"
  wait "$serve_pid" || true

  printf "per test: synth %.2f ms, run %.2f ms, run --shard x4 %.2f ms, merge of 4 results files %.3f ms\n" \
    "${cost[synth,$n]}" "${cost[run,$n]}" "${cost[shard,$n]}" "${cost[merge,$n]}"
  printf "latency: status %.3f s, query --limit 10 %.3f s, compare %.3f s, /api/v1/query/hic?limit=10 %.4f s\n" \
    "${cost[status,$n]}" "${cost[query,$n]}" "${cost[compare,$n]}" "${cost[api,$n]}"
  # What every writing command costs first (README "Errors"): SQLite's quick_check of the file.
  start=$(now)
  sqlite3 "$db" "PRAGMA quick_check(1)" > /dev/null
  check_s=$(seconds_since "$start")
  bytes=$(stat -c %s "$db")
  printf "write-ahead log at most %.1f MB during the run; quick_check %.2f s (%.2f s a GB)\n" \
    "$(echo "$wal_peak / 1000000" | bc -l)" "$check_s" "$(echo "$check_s * 1000000000 / $bytes" | bc -l)"
  printf "catalogue %.1f MB, %.0f bytes a test:\n" "$(echo "$bytes / 1000000" | bc -l)" \
    "$(echo "$bytes / $total" | bc -l)"
  sqlite3 "$db" "SELECT '  ' || coalesce((SELECT tbl_name FROM sqlite_schema WHERE name = d.name), d.name), \
    printf('%.0f', sum(pgsize) * 1.0 / $total) FROM dbstat AS d GROUP BY 1 HAVING sum(pgsize) > $total \
    ORDER BY sum(pgsize) DESC" | tr '|' ' '
  for i in 0 1 2 3; do remove_db "$WORK/shard-$i.db"; done
  remove_db "$db"
done

smallest=${SIZES[0]}
echo
echo "== ratios to $smallest tests (per-test costs; latencies as they are)"
printf "%-8s" "tests"
for metric in "${metrics[@]}"; do printf " %8s" "$metric"; done
echo
for n in "${SIZES[@]}"; do
  printf "%-8s" "$n"
  for metric in "${metrics[@]}"; do printf " %8.2f" "$(echo "${cost[$metric,$n]} / ${cost[$metric,$smallest]}" | bc -l)"; done
  echo
done
echo "load average $(cut -d' ' -f1-3 /proc/loadavg)"
