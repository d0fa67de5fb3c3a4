#!/usr/bin/env bash
# What `napkin serve` (docs/serve.md) answers and how fast, on loopback only, bounded in count and
# time (issue 33's benchmarks):
#
#   bench/run_serve.sh [RUN_TESTS] [REQUESTS] [WORKDIR]
#
# 1. Latency: a settled recording (denton-3222, 9 channels x 20,000 samples) to its row in the
#    API, beyond the settle time (--settle 1; the inbox looks every second while a test settles),
#    and with a marker file (<id>.ready), 5 tests each.
# 2. GET /api/v1/query/hic?limit=100 and GET /healthz from 32 keep-alive loopback clients:
#    REQUESTS requests each (default 20,000, at most 60 s) on a catalogue of 100 processed tests;
#    requests per second, p50 and p99.
# 3. The same while the inbox imports and processes RUN_TESTS more tests (default 1,000, 2,000
#    samples each, moved into the inbox as one folder): the load stops at REQUESTS, 60 s or when
#    the run is done, whichever comes first.
# 4. The service's resident memory before and after 10,000 more requests (query, test summary,
#    status, metrics, report version in turn).
# Release build (build/bench), the service with its default 4 request threads.
set -euo pipefail

RUN_TESTS=${1:-1000}
REQUESTS=${2:-20000}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${3:-$ROOT/build/bench-serve}
BUILD=$ROOT/build/bench
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

require_disk "$WORK" $(( RUN_TESTS * 2 + 200 )) "${RUN_TESTS} recordings of 2,000 samples"
build_release "$BUILD" "$(nproc)" napkin napkin_serve_bench
NAPKIN=$BUILD/cli/napkin
TOOL=$BUILD/bench/napkin_serve_bench
# A folder of this run's own (its log stays there): nothing else in WORKDIR is written or removed.
RUN_DIR=$(mktemp -d "$WORK/serve-run.XXXXXX")
DB=$RUN_DIR/serve.db
INBOX=$RUN_DIR/inbox
STAGING=$RUN_DIR/staging
mkdir -p "$INBOX/bench" "$STAGING"
echo '{"array": "denton-3222"}' > "$INBOX/napkin.json"
"$NAPKIN" --db "$DB" init > /dev/null

"$NAPKIN" --db "$DB" serve --listen 127.0.0.1:0 --inbox "$INBOX" --settle 1 2> "$RUN_DIR/serve.log" &
SERVE_PID=$!
stop_service() {
  kill -TERM "$SERVE_PID" 2> /dev/null && wait "$SERVE_PID" || true
  rm -rf "$INBOX" "$STAGING"  # this run's own; its log stays
  remove_db "$DB"
}
trap stop_service EXIT
PORT=
for (( i = 0; i < 100 && ${#PORT} == 0; i++ )); do
  sleep 0.1
  PORT=$(sed -n 's|.*listening on http://127.0.0.1:\([0-9]*\).*|\1|p' "$RUN_DIR/serve.log" | head -1)
done
[[ -n $PORT ]] || { echo "napkin serve did not start:" >&2; cat "$RUN_DIR/serve.log" >&2; exit 1; }
echo "napkin serve (pid $SERVE_PID) on 127.0.0.1:$PORT, log $RUN_DIR/serve.log"

echo
echo "== 1. settled recording (9 channels x 20,000 samples) to its row in /api/v1/tests/ID"
"$TOOL" latency "$PORT" "$STAGING" "$INBOX/bench/latency" 20000 5 1 1 | tail -1
"$TOOL" latency "$PORT" "$STAGING" "$INBOX/bench/latency-marker" 20000 5 1 101 marker | tail -1

echo
echo "== 2. /api/v1/query/hic?limit=100 and /healthz, 32 loopback clients, a catalogue of 100 processed tests"
"$TOOL" write-tests "$STAGING/base" 90 2000 1000
mv "$STAGING/base" "$INBOX/bench/base"
"$TOOL" wait "$PORT" 100 300 > /dev/null
"$TOOL" load "$PORT" "/api/v1/query/hic?limit=100" 32 "$REQUESTS" 60
"$TOOL" load "$PORT" "/healthz" 32 "$REQUESTS" 60

echo
echo "== 3. the same while the inbox imports and processes $RUN_TESTS more tests (2,000 samples each)"
"$TOOL" write-tests "$STAGING/run" "$RUN_TESTS" 2000 5000
start=$(date +%s.%N)
mv "$STAGING/run" "$INBOX/bench/run"
"$TOOL" load "$PORT" "/api/v1/query/hic?limit=100" 32 "$REQUESTS" 60
processed_during=$(( $("$TOOL" processed "$PORT") - 100 ))
"$TOOL" wait "$PORT" $(( 100 + RUN_TESTS )) 1800 > /dev/null
printf "the inbox had processed %d of the %d tests when the load ended; all in %.1f s\n" \
  "$processed_during" "$RUN_TESTS" "$(echo "$(date +%s.%N) - $start" | bc -l)"

echo
echo "== 4. resident memory of the service before and after 10,000 requests"
before_kb=$("$TOOL" rss "$SERVE_PID")
for path in "/api/v1/query/hic?limit=100" "/api/v1/tests/bench-1000" "/api/v1/status" "/metrics" \
  "/api/v1/report/version?series=bench"; do
  "$TOOL" load "$PORT" "$path" 8 2000 120 > /dev/null
done
after_kb=$("$TOOL" rss "$SERVE_PID")
"$TOOL" load "$PORT" "/api/v1/query/hic?limit=100" 8 10000 120 > /dev/null
again_kb=$("$TOOL" rss "$SERVE_PID")
printf "VmRSS %.1f MiB before, %.1f MiB after 10,000 requests, %.1f MiB after 10,000 more\n" \
  "$(echo "$before_kb / 1024" | bc -l)" "$(echo "$after_kb / 1024" | bc -l)" "$(echo "$again_kb / 1024" | bc -l)"
