#!/usr/bin/env bash
# What the Python module costs per test (issue 22): napkin.transform of N
# tests in a Python loop against `napkin run` of the same tests, one thread
# each, same Release build, same default config.
#
#   bench/run_python.sh [N] [SAMPLES] [WORKDIR]
#
# Creates a catalogue of N synthetic tests (default 1,000; denton-3222, 9
# channels x SAMPLES samples, default 2,000), times `napkin run --threads 1`
# on it, then reads every test's inputs with napkin.Catalogue.test_inputs
# (not timed) and times napkin.transform of each (bench/tools/python_loop.py);
# prints both per-test times and their ratio (Python / run). `run` also
# writes each result (float32 derived channels) to the catalogue, which the
# loop does not: a ratio at or below 1.10 says the binding adds at most 10 %.
set -euo pipefail

N=${1:-1000}
SAMPLES=${2:-2000}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${3:-$ROOT/build/bench-python}
BUILD=$ROOT/build/bench-python-build
# shellcheck source=bench/lib.sh
source "$ROOT/bench/lib.sh"

mkdir -p "$WORK"
cmake -S "$ROOT" -B "$BUILD" -DNAPKIN_BUILD_PYTHON=ON > /dev/null  # then build_release's options
build_release "$BUILD" "$(nproc)" napkin napkin_python
NAPKIN=$BUILD/cli/napkin
DB=$WORK/python.db
remove_db "$DB"
trap 'remove_db "$DB"' EXIT

"$NAPKIN" --db "$DB" synth --scenario random --array denton-3222 --count "$N" --samples "$SAMPLES" > /dev/null
start=$(date +%s.%N)
"$NAPKIN" --quiet --db "$DB" run --threads 1
run_s=$(echo "$(date +%s.%N) - $start" | bc -l)
python_s=$(PYTHONPATH=$BUILD/python /usr/bin/python3 "$ROOT/bench/tools/python_loop.py" "$DB")

echo
echo "== napkin.transform in a Python loop vs napkin run --threads 1: $N tests, 9 channels x $SAMPLES samples"
printf "napkin run:        %8.3f ms per test (%.2f s, results written)\n" "$(echo "$run_s * 1000 / $N" | bc -l)" "$run_s"
printf "napkin.transform:  %8.3f ms per test (%.2f s)\n" "$(echo "$python_s * 1000 / $N" | bc -l)" "$python_s"
printf "ratio %.3f (Python / run)\n" "$(echo "$python_s / $run_s" | bc -l)"
