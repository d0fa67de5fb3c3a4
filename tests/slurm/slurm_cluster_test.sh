#!/usr/bin/env bash
# CTest `slurm/cluster`: deploy/slurm/reprocess.sh on a real Slurm (README "Cluster runs").
#
#   slurm_cluster_test.sh NAPKIN_BINARY SOURCE_DIR DUMP_TOOL
#
# Starts a private single-node cluster in a temporary directory (its own munged
# socket and key, slurm.conf, free TCP ports chosen now, state, spool, pid and
# log files), adds 40 synthetic tests to a catalogue, reprocesses one copy with
# reprocess.sh in 4 array tasks plus the merge job, runs an unsharded
# `napkin run` on another copy, and requires both catalogues to hold the same
# results, findings and derived channels bit for bit (DUMP_TOOL is napkin_results_dump,
# tests/support/db/results_dump.h: a canonical, exact text dump of what runs write).
# The daemons are stopped by their recorded PIDs (never by name) and the
# temporary directory removed on every exit, failure included.
# Without root or without the Slurm/munge programs the test is skipped (exit 77).
# NAPKIN_SLURM_TEST_KEEP=1 keeps the temporary directory (logs, catalogues) for a look.
set -euo pipefail

readonly kSkip=77
readonly kTests=40
readonly kTasks=4
readonly kSamples=2000
readonly kStartTimeout=60  # seconds for the node to come up idle
readonly kJobsTimeout=120  # seconds for one round of jobs to leave the queue

if [ $# -ne 3 ]; then
  echo "usage: $0 NAPKIN_BINARY SOURCE_DIR DUMP_TOOL" >&2
  exit 2
fi
napkin=$(realpath "$1")
source_dir=$(realpath "$2")
dump_tool=$(realpath "$3")
reprocess="$source_dir/deploy/slurm/reprocess.sh"
export PATH="$PATH:/usr/sbin:/sbin"
started_at=$(date +%s.%N)

skip() {
  echo "SKIPPED: $*"
  exit "$kSkip"
}
[ "$(id -u)" = 0 ] || skip "the private Slurm cluster needs root (SlurmUser=root; slurmd runs the jobs)."
for program in munged slurmctld slurmd sbatch squeue sinfo scontrol scancel; do
  command -v "$program" >/dev/null ||
    skip "'$program' is not installed (Debian packages slurm-wlm and munge; make deps installs them)."
done

# Under /tmp when TMPDIR is too long for munged's socket path (108 bytes with the NUL).
tmp_parent=${TMPDIR:-/tmp}
[ "${#tmp_parent}" -le 60 ] || tmp_parent=/tmp
tmp=$(mktemp -d "$tmp_parent/napkin-slurm.XXXXXX")
chmod 0755 "$tmp"  # munged requires its socket's directories to be searchable by all
pids=()     # munged, slurmctld, slurmd: what cleanup stops
job_ids=()  # what cleanup cancels when the test stops early

print_logs() {
  local log
  for log in "$tmp"/log/*.log "$tmp"/work/results/*.out; do
    [ -f "$log" ] || continue
    echo "----- $log (last 40 lines)"
    tail -n 40 "$log"
  done
  for log in "$tmp"/log/*.stderr; do
    [ -f "$log" ] || continue
    echo "----- $log (last 5 lines)"
    tail -n 5 "$log"
  done
}

cleanup() {
  local status=$?
  trap - EXIT INT TERM
  if [ "$status" -ne 0 ] && [ "$status" -ne "$kSkip" ]; then
    echo "FAILED (exit $status); daemon and job logs:"
    print_logs
  fi
  # Jobs of a failed test are cancelled while slurmctld still runs, so that no
  # slurmstepd or napkin outlives the cluster.
  if [ "${#job_ids[@]}" -gt 0 ] && [ "${#pids[@]}" -ge 2 ] && kill -0 "${pids[1]}" 2>/dev/null; then
    scancel "${job_ids[@]}" 2>/dev/null || true
    local waited=0
    while [ -n "$(squeue -h -o %i 2>/dev/null)" ] && [ "$waited" -lt 20 ]; do
      sleep 0.5
      waited=$((waited + 1))
    done
  fi
  # Stop in reverse order of start: slurmd, slurmctld, munged.
  local i pid
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    pid=${pids[i]}
    kill -TERM "$pid" 2>/dev/null || continue
    local waited=0
    while kill -0 "$pid" 2>/dev/null && [ "$waited" -lt 100 ]; do
      sleep 0.1
      waited=$((waited + 1))
    done
    kill -KILL "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  if [ -n "${NAPKIN_SLURM_TEST_KEEP:-}" ]; then
    echo "kept $tmp (NAPKIN_SLURM_TEST_KEEP)"
  else
    rm -rf "$tmp"
  fi
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# A TCP port no socket of this machine uses (listening or connected), from /proc/net/tcp{,6}.
port_in_use() {
  local hex
  hex=$(printf '%04X' "$1")
  cat /proc/net/tcp /proc/net/tcp6 2>/dev/null | awk -v port=":$hex" '
    NR > 1 && substr($2, length($2) - 4) == port { found = 1 } END { exit !found }'
}
# Below the kernel's ephemeral range, so that no outgoing connection takes it before the
# daemon binds it.
free_port() {
  local port avoid=${1:-0} ephemeral_low
  ephemeral_low=$(awk '{ print $1 }' /proc/sys/net/ipv4/ip_local_port_range 2>/dev/null || echo 32768)
  [ "$ephemeral_low" -gt 11000 ] || ephemeral_low=32768
  for _ in $(seq 1 200); do
    port=$((10000 + RANDOM % (ephemeral_low - 10000)))
    [ "$port" != "$avoid" ] && ! port_in_use "$port" && { echo "$port"; return 0; }
  done
  echo "no free TCP port found in 10000-$((ephemeral_low - 1))" >&2
  return 1
}

seconds_since() { awk -v start="$1" -v now="$(date +%s.%N)" 'BEGIN { printf "%.1f", now - start }'; }

wait_until() {  # wait_until SECONDS DESCRIPTION COMMAND...
  local timeout=$1 what=$2
  shift 2
  local deadline=$(($(date +%s) + timeout))
  until "$@"; do
    if [ "$(date +%s)" -ge "$deadline" ]; then
      echo "timed out after ${timeout} s waiting for $what" >&2
      return 1
    fi
    sleep 0.2
  done
}

# ---- munge: its own key, socket, pid and seed file; in the foreground it logs to stderr.
mkdir -p "$tmp/munge" "$tmp/key" "$tmp/log" "$tmp/state" "$tmp/spool" "$tmp/run" "$tmp/work"
chmod 0755 "$tmp/munge"
chmod 0700 "$tmp/key"
head -c 1024 /dev/urandom >"$tmp/key/munge.key"
chmod 0400 "$tmp/key/munge.key"
munge_socket="$tmp/munge/munge.socket"
munged --foreground --socket="$munge_socket" --key-file="$tmp/key/munge.key" \
  --pid-file="$tmp/key/munged.pid" --seed-file="$tmp/key/munged.seed" >"$tmp/log/munged.log" 2>&1 &
pids+=($!)
munge_up() {
  kill -0 "${pids[0]}" 2>/dev/null || { echo "munged exited" >&2; exit 1; }
  [ -S "$munge_socket" ]
}
wait_until 10 "munged's socket" munge_up

# ---- slurm.conf: one node (this host) in one partition, ports chosen now.
host=$(hostname -s)
cpus=$(nproc)
memory_mb=$(awk '/^MemTotal:/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)
ctld_port=$(free_port)
slurmd_port=$(free_port "$ctld_port")
conf="$tmp/slurm.conf"
touch "$tmp/plugstack.conf"
cat >"$conf" <<EOF
# napkin tests/slurm/slurm_cluster_test.sh: a private single-node cluster.
ClusterName=napkintest
SlurmctldHost=${host}(127.0.0.1)
SlurmctldPort=${ctld_port}
SlurmdPort=${slurmd_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=${munge_socket}
CredType=cred/munge
StateSaveLocation=${tmp}/state
SlurmdSpoolDir=${tmp}/spool
SlurmctldPidFile=${tmp}/run/slurmctld.pid
SlurmdPidFile=${tmp}/run/slurmd.pid
SlurmctldLogFile=${tmp}/log/slurmctld.log
SlurmdLogFile=${tmp}/log/slurmd.log
PlugStackConfig=${tmp}/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
SchedulerParameters=batch_sched_delay=0
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
SlurmctldDebug=info
SlurmdDebug=info
MinJobAge=600
NodeName=${host} NodeAddr=127.0.0.1 CPUs=${cpus} RealMemory=${memory_mb} State=UNKNOWN
PartitionName=napkin Nodes=${host} Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$conf"

# In the foreground (-D) they log to their log files and to stderr, which keeps what comes
# before a log file is open (a refused slurm.conf).
slurmctld -D -f "$conf" >"$tmp/log/slurmctld.stderr" 2>&1 &
pids+=($!)
slurmd -D -f "$conf" >"$tmp/log/slurmd.stderr" 2>&1 &
pids+=($!)
node_idle() {
  kill -0 "${pids[1]}" 2>/dev/null || { echo "slurmctld exited" >&2; exit 1; }
  kill -0 "${pids[2]}" 2>/dev/null || { echo "slurmd exited" >&2; exit 1; }
  [ "$(sinfo -h -N -n "$host" -o %t 2>/dev/null)" = "idle" ]; }
wait_until "$kStartTimeout" "node '$host' to be idle (sinfo)" node_idle
echo "cluster up in $(seconds_since "$started_at") s (node $host, $cpus CPUs, ports $ctld_port and $slurmd_port)"

# ---- the catalogue: 40 small synthetic tests, two copies.
work="$tmp/work"
cd "$work"
"$napkin" --db archive.db synth --scenario random --count "$kTests" --samples "$kSamples"
cp archive.db sharded.db
cp archive.db unsharded.db
# A relative --config path; a residual limit low enough that about half the tests get a
# screening warning, so that findings are compared too.
sed 's/"residual_limit_g": 5.0,/"residual_limit_g": 0.0001,/' "$source_dir/config/processing/default.json" \
  >processing.json
grep -q '"residual_limit_g": 0.0001,' processing.json

# The reference: one unsharded run on one machine.
"$napkin" --db unsharded.db run --config processing.json --threads 2 >run.out

# ---- round 1: task 2 fails (napkin-wrapper refuses shard 2/4 while fail-task-2 exists).
cat >napkin-wrapper <<WRAPPER
#!/usr/bin/env bash
if [ -f "$work/fail-task-2" ] && [[ " \$* " == *" --shard 2/$kTasks "* ]]; then
  echo "napkin-wrapper: injected failure of shard 2/$kTasks" >&2
  exit 1
fi
exec "$napkin" "\$@"
WRAPPER
chmod +x napkin-wrapper
touch fail-task-2

# submit ROUND: reprocess.sh on sharded.db, with two extra sbatch options: a time limit and
# one CPU per task (two tasks read the catalogue at once); sets array_job and merge_job.
submit() {
  local out line
  out=$("$reprocess" sharded.db --tasks "$kTasks" --config processing.json --napkin napkin-wrapper \
    --results-dir results --time=10 --cpus-per-task=1)
  while IFS= read -r line; do echo "round $1: $line"; done <<<"$out"
  array_job=$(awk '$1 == "array" && $2 == "job" { sub(":", "", $3); print $3 }' <<<"$out")
  merge_job=$(awk '$1 == "merge" && $2 == "job" { sub(":", "", $3); print $3 }' <<<"$out")
  { [ -n "$array_job" ] && [ -n "$merge_job" ]; } || { echo "reprocess.sh printed no job ids" >&2; return 1; }
  job_ids+=("$array_job" "$merge_job")
}
queue_empty() { [ -z "$(squeue -h -o %i)" ]; }
# job_states JOB: one "STATE EXITCODE" line per job record (each task of an array).
job_states() {
  scontrol -o show job "$1" | awk '{
    state = ""; code = ""
    for (i = 1; i <= NF; i++) {
      if ($i ~ /^JobState=/) state = substr($i, 10)
      if ($i ~ /^ExitCode=/) code = substr($i, 10)
    }
    print state, code }'
}
expect_states() {  # expect_states JOB EXPECTED_LINES
  local actual
  actual=$(job_states "$1" | sort | uniq -c | awk '{ $1 = $1; print }')
  if [ "$actual" != "$2" ]; then
    echo "job $1: expected states '$2', found:" >&2
    scontrol show job "$1" >&2
    return 1
  fi
}

round_started=$(date +%s.%N)
submit 1
wait_until "$kJobsTimeout" "round 1's jobs to leave the queue" queue_empty
echo "round 1 done in $(seconds_since "$round_started") s"
expect_states "$array_job" $'3 COMPLETED 0:0\n1 FAILED 1:0'
# afterok holds the merge and --kill-on-invalid-dep removes it from the queue.
expect_states "$merge_job" "1 CANCELLED 0:0"
# The shards read the catalogue read-only: its file is byte for byte what it was.
cmp sharded.db archive.db
[ -f results/shard-0.db ] && [ -f results/shard-3.db ]

# ---- round 2: the same command again; the tasks resume from their results files.
rm fail-task-2
round_started=$(date +%s.%N)
submit 2
wait_until "$kJobsTimeout" "round 2's jobs to leave the queue" queue_empty
echo "round 2 done in $(seconds_since "$round_started") s"
expect_states "$array_job" "$kTasks COMPLETED 0:0"
# The tasks that had succeeded in round 1 resumed from their results files: nothing left to do.
for task in 0 1 3; do
  grep -q ' 0 tests to process' "results/napkin-shard-${array_job}_$task.out" ||
    { echo "round 2: task $task did not resume from results/shard-$task.db" >&2; exit 1; }
done
expect_states "$merge_job" "1 COMPLETED 0:0"
scontrol -o show job "$merge_job" | grep -q 'TimeLimit=00:10:00' ||
  { echo "the extra sbatch option --time=10 did not reach the merge job" >&2; exit 1; }
grep -q "napkin-merge: done" "results/napkin-merge-$merge_job.out"
for ((task = 0; task < kTasks; task++)); do
  [ ! -e "results/shard-$task.db" ] || { echo "results/shard-$task.db was not removed after the merge" >&2; exit 1; }
done

# ---- the merged catalogue holds what the unsharded run wrote, bit for bit.
"$dump_tool" sharded.db >sharded.dump
"$dump_tool" unsharded.db >unsharded.dump
results=$(grep -c '^results|' unsharded.dump || true)
findings=$(grep -c '^findings|' unsharded.dump || true)
derived=$(grep -c '^derived_channels|' unsharded.dump || true)
[ "$results" -eq "$kTests" ] || { echo "the unsharded run wrote $results results, not $kTests" >&2; exit 1; }
[ "$findings" -gt 0 ] || { echo "the unsharded run wrote no findings to compare" >&2; exit 1; }
if ! cmp -s sharded.dump unsharded.dump; then
  echo "the merged catalogue differs from the unsharded run's (napkin_results_dump, first lines of diff):" >&2
  diff sharded.dump unsharded.dump | head -n 20 >&2
  exit 1
fi
echo "merged and unsharded catalogues are identical: $results results, $findings findings," \
  "$derived derived channels"
echo "slurm test wall time: $(seconds_since "$started_at") s"
