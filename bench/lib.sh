# shellcheck shell=bash
# What the bench/run_*.sh scripts share; sourced by them (after setting ROOT,
# the checkout), not run.

# Exits unless /usr/bin/time (Debian package 'time') is installed: it gives
# the scripts the peak memory of a run.
require_time() {
  if [[ ! -x /usr/bin/time ]]; then
    echo "/usr/bin/time is missing: install the Debian package 'time' (make deps)" >&2
    exit 1
  fi
}

# Exits (status 2) unless LARGE ($2) exceeds SMALL ($1).
require_larger() {
  if (( $2 <= $1 )); then
    echo "LARGE ($2) must exceed SMALL ($1)" >&2
    exit 2
  fi
}

# Creates the folder $1 and exits unless it has $2 MB free (for $3, said in
# the message).
require_disk() {
  local avail_mb
  mkdir -p "$1"
  avail_mb=$(df -Pm "$1" | awk 'NR == 2 {print $4}')
  echo "disk: need about $2 MB in $1, ${avail_mb} MB available"
  if (( avail_mb < $2 )); then
    echo "not enough disk space for $3" >&2
    exit 1
  fi
}

# Configures the Release build folder $1 (no tests, benchmarks on) and builds
# the targets $3... with $2 parallel jobs.
build_release() {
  local build=$1 jobs=$2
  shift 2
  cmake -S "$ROOT" -B "$build" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DNAPKIN_BUILD_BENCH=ON > /dev/null
  cmake --build "$build" -j"$jobs" --target "$@" > /dev/null
}

# Removes the catalogue $1 with its WAL and shared-memory files.
remove_db() { rm -f "$1" "$1-wal" "$1-shm"; }

# The "Maximum resident set size" (kB) in $1, the output of /usr/bin/time -v.
peak_rss_kb() { awk -F': ' '/Maximum resident set size/ {print $2}' "$1"; }
