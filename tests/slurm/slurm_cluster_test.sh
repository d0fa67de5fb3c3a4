#!/usr/bin/env bash
# CTest `slurm/cluster`: deploy/slurm/reprocess.sh on a real Slurm (README "Cluster runs").
#
#   slurm_cluster_test.sh NAPKIN_BINARY SOURCE_DIR COMPARE_TOOL
#
# Starts a private single-node cluster in a temporary directory (its own munged
# socket and key, slurm.conf, free TCP ports chosen now, state, spool, pid and
# log files), adds 40 synthetic tests to a catalogue, reprocesses one copy with
# reprocess.sh in 4 array tasks plus the merge job, runs an unsharded
# `napkin run` on another copy, and requires both catalogues to hold the same
# results, findings and derived channels bit for bit (COMPARE_TOOL).
# The daemons are stopped by their recorded PIDs (never by name) and the
# temporary directory removed on every exit, failure included.
# Without root or without the Slurm/munge programs the test is skipped (exit 77).
set -euo pipefail

readonly kSkip=77
readonly kTests=40
readonly kTasks=4
readonly kSamples=2000
readonly kStartTimeout=60  # seconds for the node to come up idle
readonly kJobsTimeout=180  # seconds for the jobs to leave the queue

if [ $# -ne 3 ]; then
  echo "usage: $0 NAPKIN_BINARY SOURCE_DIR COMPARE_TOOL" >&2
  exit 2
fi
napkin=$(realpath "$1")
source_dir=$(realpath "$2")
compare_tool=$(realpath "$3")
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

tmp=$(mktemp -d "${TMPDIR:-/tmp}/napkin-slurm.XXXXXX")
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
  rm -rf "$tmp"
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
free_port() {
  local port avoid=${1:-0}
  for _ in $(seq 1 200); do
    port=$((20000 + RANDOM % 40000))
    [ "$port" != "$avoid" ] && ! port_in_use "$port" && { echo "$port"; return 0; }
  done
  echo "no free TCP port found in 20000-59999" >&2
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

# ---- munge: its own key, socket, pid, seed and log file.
mkdir -p "$tmp/munge" "$tmp/key" "$tmp/log" "$tmp/state" "$tmp/spool" "$tmp/run" "$tmp/work"
chmod 0755 "$tmp/munge"
chmod 0700 "$tmp/key"
head -c 1024 /dev/urandom >"$tmp/key/munge.key"
chmod 0400 "$tmp/key/munge.key"
munge_socket="$tmp/munge/munge.socket"
munged --foreground --socket="$munge_socket" --key-file="$tmp/key/munge.key" \
  --pid-file="$tmp/key/munged.pid" --seed-file="$tmp/key/munged.seed" \
  --log-file="$tmp/log/munged.log" >>"$tmp/log/munged.log" 2>&1 &
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

slurmctld -D -f "$conf" >>"$tmp/log/slurmctld.log" 2>&1 &
pids+=($!)
slurmd -D -f "$conf" >>"$tmp/log/slurmd.log" 2>&1 &
pids+=($!)
node_idle() {
  kill -0 "${pids[1]}" 2>/dev/null || { echo "slurmctld exited" >&2; exit 1; }
  kill -0 "${pids[2]}" 2>/dev/null || { echo "slurmd exited" >&2; exit 1; }
  [ "$(sinfo -h -N -n "$host" -o %t 2>/dev/null)" = "idle" ]; }
wait_until "$kStartTimeout" "node '$host' to be idle (sinfo)" node_idle
echo "cluster up in $(seconds_since "$started_at") s (node $host, $cpus CPUs, ports $ctld_port and $slurmd_port)"
cd "$tmp/work"
id=$(sbatch --parsable --output="$tmp/work/hello.out" --wrap='echo hello from $SLURM_JOB_ID on $(hostname)')
job_ids+=("$id")
echo "job $id"
jobs_gone() { [ -z "$(squeue -h -o %i 2>/dev/null)" ]; }
wait_until 60 "jobs" jobs_gone
cat hello.out
scontrol show job "$id" | grep -E 'JobState|ExitCode'
