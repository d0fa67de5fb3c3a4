#!/usr/bin/env bash
# Reprocess a napkin catalogue across a Slurm cluster (deploy/slurm/README.md, README
# "Cluster runs"): a job array of N tasks, each running `napkin run --shard I/N --results
# RESULTS_DIR/shard-I.db` against the read-only catalogue, and a merge job that runs
# after every task succeeded (--dependency=afterok) and merges the results into it.
#
#   reprocess.sh CATALOGUE [--tasks N] [--config C] [--napkin PATH] [--results-dir DIR] [SBATCH OPTION]...
#
# Other options (--partition=P, --account=A, --qos=Q, --time=T, ...) go to both sbatch
# calls. Prints one line per job id. Run it again after a failed task: the tasks resume
# from their results files.
set -euo pipefail

program=$(basename "$0")
script_dir=$(dirname "$(realpath "$0")")

fail() {  # one sentence, exit 2 (usage) or 1
  echo "$program: $1" >&2
  exit "${2:-1}"
}
usage="usage: $program CATALOGUE [--tasks N] [--config C] [--napkin PATH] [--results-dir DIR] [SBATCH OPTION]..."

catalogue=""
tasks=4
config=""
napkin=""
results_dir=""
sbatch_options=()
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) echo "$usage"; exit 0 ;;
    --tasks | --config | --napkin | --results-dir)
      [ $# -ge 2 ] || fail "$1 needs a value; $usage" 2
      value=$2
      option=$1
      shift 2
      ;;
    --tasks=* | --config=* | --napkin=* | --results-dir=*)
      value=${1#*=}
      option=${1%%=*}
      shift
      ;;
    -*) sbatch_options+=("$1"); shift; continue ;;
    *)
      [ -z "$catalogue" ] || fail "one CATALOGUE only ('$catalogue' and '$1'); write sbatch options with '=' (--partition=P)." 2
      catalogue=$1
      shift
      continue
      ;;
  esac
  case "$option" in
    --tasks) tasks=$value ;;
    --config) config=$value ;;
    --napkin) napkin=$value ;;
    --results-dir) results_dir=$value ;;
  esac
done

[ -n "$catalogue" ] || fail "no CATALOGUE given; $usage" 2
case "$tasks" in
  '' | *[!0-9]* | 0*) fail "--tasks must be a whole number of at least 1, not '$tasks'." 2 ;;
esac
[ "${#tasks}" -le 6 ] || fail "--tasks $tasks is more tasks than any cluster runs at once; use at most a few thousand." 2
[ -f "$catalogue" ] || fail "catalogue '$catalogue' does not exist; create it with napkin init and napkin import."
# The tasks open the catalogue immutable: changes still in its -wal would be missing (and
# napkin refuses it in every task); say so before anything is submitted.
for log in "$catalogue-wal" "$catalogue-journal"; do
  [ ! -s "$log" ] || fail "catalogue '$catalogue' has changes not yet written into it (in '$log'); let the process writing it finish, or run \`sqlite3 '$catalogue' 'PRAGMA wal_checkpoint(TRUNCATE)'\`, then submit again."
done
command -v sbatch >/dev/null ||
  fail "sbatch not found; run $program on a Slurm submit host (Debian package slurm-client)."

# Every path absolute: the jobs run on other nodes, in other directories.
catalogue=$(realpath "$catalogue")
if [ -z "$napkin" ]; then
  napkin=$(command -v napkin) || fail "napkin is not on PATH; pass --napkin /shared/path/to/napkin."
fi
{ [ -x "$napkin" ] && [ -f "$napkin" ]; } || fail "--napkin '$napkin' is not an executable file."
napkin=$(realpath "$napkin")
# A config is a preset name or a JSON file; a file is passed by its absolute path.
if [ -n "$config" ] && [ -f "$config" ]; then config=$(realpath "$config"); fi
[ -n "$results_dir" ] || results_dir="$catalogue.results"
mkdir -p "$results_dir" || fail "cannot create the results directory '$results_dir'."
results_dir=$(realpath "$results_dir")

# Resuming re-uses the results files of a previous submission, which are only valid for
# the same number of tasks (shard I of N names other tests for another N).
marker="$results_dir/tasks"
if [ -f "$marker" ] && [ "$(cat "$marker")" != "$tasks" ]; then
  fail "results directory '$results_dir' holds the unmerged results of $(cat "$marker") tasks; run again with --tasks $(cat "$marker"), or give another --results-dir."
fi
echo "$tasks" >"$marker"

shard_args=(--tasks "$tasks" --napkin "$napkin")
[ -z "$config" ] || shard_args+=(--config "$config")

# sbatch --parsable prints "JOBID" or "JOBID;CLUSTER".
array_job=$(sbatch --parsable --array="0-$((tasks - 1))" --output="$results_dir/napkin-shard-%A_%a.out" \
  "${sbatch_options[@]}" "$script_dir/napkin-shard.sbatch" "${shard_args[@]}" "$catalogue" "$results_dir") ||
  fail "sbatch refused the job array (its message is above)."
array_job=${array_job%%;*}
echo "array job $array_job: $tasks tasks, results in $results_dir/shard-{0..$((tasks - 1))}.db"

merge_job=$(sbatch --parsable --dependency="afterok:$array_job" --kill-on-invalid-dep=yes \
  --output="$results_dir/napkin-merge-%j.out" "${sbatch_options[@]}" "$script_dir/napkin-merge.sbatch" \
  --tasks "$tasks" --napkin "$napkin" "$catalogue" "$results_dir") ||
  fail "sbatch refused the merge job (its message is above); the array job $array_job runs, merge its results later with napkin-merge.sbatch."
merge_job=${merge_job%%;*}
echo "merge job $merge_job: merges them into $catalogue after every task succeeded"
