#!/usr/bin/env bash
# A real cluster in a test: starts a one-node Slurm on 127.0.0.1 (munged, slurmctld, slurmd, configured in
# a temporary folder), submits scripts/slurm's surfelize job array and its merge job, waits, and compares
# the merged file with a one-machine `pbs surfelize` byte for byte; then stops every daemon it started.
# Exits 77 (ctest: skipped) with the reason where it cannot start the daemons (not root, no Slurm).
#   slurm_cluster.sh PBS_BINARY SOURCE_DIR
# Environment: PBS_CLUSTER_SCENE (default: default), PBS_CLUSTER_SHARDS (shard counts to run, default
# "4"), PBS_CLUSTER_OPTIONS (pbs surfelize options; default small ones), PBS_CLUSTER_CPUS (CPUs a task asks
# for, default 1), PBS_CLUSTER_LIMIT (seconds a submission may take, default 150).
set -euo pipefail
pbs=$(realpath "$1") source=$(realpath "$2")
scene=${PBS_CLUSTER_SCENE:-default}
shard_counts=${PBS_CLUSTER_SHARDS:-4}
options=${PBS_CLUSTER_OPTIONS---min-triangles 100000 --resolution 32 --max-surfels 100000}
cpus=${PBS_CLUSTER_CPUS:-1}
limit=${PBS_CLUSTER_LIMIT:-150}

skip() {
  echo "SKIPPED: $*" >&2
  exit 77
}
[ "$(id -u)" -eq 0 ] || skip "a Slurm of its own needs root (slurmd runs jobs as their users)"
for command in mungekey munged slurmctld slurmd sbatch squeue sinfo; do
  command -v "$command" >/dev/null || skip "$command not found (install slurm-wlm and munge: scripts/setup.sh)"
done

work=$(mktemp -d /tmp/pbs-slurm.XXXXXX)
# Every daemon this test started, by the pid it wrote, SIGTERM first, SIGKILL after 10 s; then the folder.
# The pids are read once, before any signal: a daemon removes its pid file as it exits, so a file read after
# the SIGTERM may be gone (a failed read here made a passing run exit 1).
stop_daemons() {
  local pids=() pidfile pid
  for pidfile in "$work"/slurmd.pid "$work"/slurmctld.pid "$work"/munged.pid; do
    if pid=$(cat "$pidfile" 2>/dev/null) && [ -n "$pid" ]; then pids+=("$pid"); fi
  done
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
  done
  rm -rf "$work"
}
trap stop_daemons EXIT

# Seconds since `date +%s%N` said $1, to the millisecond.
elapsed() {
  local ms=$((($(date +%s%N) - $1) / 1000000))
  printf '%d.%03d s' $((ms / 1000)) $((ms % 1000))
}

# A port nothing listens on, from a random start (bash's /dev/tcp: connecting fails where none listens).
free_port() {
  local port=$((20000 + RANDOM % 20000))
  while (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; do port=$((port + 1)); done
  echo "$port"
}

mkdir -p "$work"/state "$work"/spool "$work"/munge
# munged wants its socket reachable by every user (jobs authenticate through it): x for all on the path.
chmod 755 "$work" "$work"/munge
mungekey -c -f -k "$work"/munge/munge.key
munged --key-file="$work"/munge/munge.key --socket="$work"/munge/munge.socket --pid-file="$work"/munged.pid \
  --log-file="$work"/munged.log --seed-file="$work"/munge/munge.seed ||
  skip "munged did not start: $(tail -n 3 "$work"/munged.log 2>/dev/null)"

host=$(hostname -s)
# slurmctld must be named by this host's name, and with NoCtldInAddrAny it listens on the address that name
# resolves to: only where that is a loopback address does nothing listen beyond this machine.
address=$(getent hosts "$host" | awk '{print $1; exit}')
case "$address" in
  127.*) ;;
  *) skip "$host resolves to '${address:-nothing}', not a loopback address: slurmctld would listen beyond 127.0.0.1" ;;
esac
ctld_port=$(free_port)
slurmd_port=$(free_port)
[ "$slurmd_port" != "$ctld_port" ] || slurmd_port=$((ctld_port + 1))
cat >"$work"/slurm.conf <<CONF
ClusterName=pbs-test
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.socket
CredType=cred/munge
CommunicationParameters=NoInAddrAny,NoCtldInAddrAny
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work"/slurm.conf
slurmctld -f "$SLURM_CONF" || skip "slurmctld did not start: $(tail -n 3 "$work"/slurmctld.log 2>/dev/null)"
slurmd -f "$SLURM_CONF" -N "$host" || skip "slurmd did not start: $(tail -n 3 "$work"/slurmd.log 2>/dev/null)"
for _ in $(seq 150); do
  [ "$(sinfo -h -o %t 2>/dev/null)" = "idle" ] && break
  sleep 0.2
done
[ "$(sinfo -h -o %t 2>/dev/null)" = "idle" ] || skip "the node did not come up: $(tail -n 3 "$work"/slurmd.log)"
echo "slurm up on 127.0.0.1 (slurmctld port $ctld_port, slurmd port $slurmd_port) in $work"

# The one-machine file to compare with.
start=$(date +%s%N)
# shellcheck disable=SC2086
"$pbs" surfelize "$scene" -o "$work"/single.surfels --quiet $options >/dev/null
echo "one machine: $(elapsed "$start")"

# Whether any of the jobs $1 (squeue's list) is still queued or running. A squeue that fails (slurmctld slow to
# answer on a loaded machine) counts as "still there": taken as an empty queue, it ended the wait before the
# merge had run.
pending() {
  local out
  out=$(squeue -h -j "$1" 2>&1) || return 0
  [ -n "$out" ]
}

export PBS="$pbs"
for shards in $shard_counts; do
  parts="$work/parts-$shards"
  start=$(date +%s%N)
  # shellcheck disable=SC2086
  array=$(sbatch --parsable --chdir="$work" --cpus-per-task="$cpus" --output="$work/shard-$shards-%a.log" \
    --array=0-$((shards - 1)) "$source"/scripts/slurm/surfelize.sbatch "$shards" "$scene" "$parts" --json $options)
  merge=$(sbatch --parsable --chdir="$work" --output="$work/merge-$shards.log" --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes "$source"/scripts/slurm/merge.sbatch "$parts" "$work/merged-$shards.surfels")
  for _ in $(seq $((limit * 5))); do
    pending "$array,$merge" || break
    sleep 0.2
  done
  seconds=$(elapsed "$start")
  if pending "$array,$merge"; then
    echo "FAILED: $shards shards still queued or running after $limit s" >&2
    squeue -j "$array,$merge" >&2 || true
    exit 1
  fi
  if [ ! -f "$work/merged-$shards.surfels" ] || ! cmp "$work/single.surfels" "$work/merged-$shards.surfels"; then
    echo "FAILED: $shards shards: no merged file, or another than the one-machine file" >&2
    tail -n 5 "$work"/shard-"$shards"-*.log "$work/merge-$shards.log" >&2 || true
    exit 1
  fi
  echo "$shards shards: submitted, run and merged in $seconds (merged file identical to one machine's)"
  for log in "$work"/shard-"$shards"-*.log; do
    # Each shard's --json: its time and its estimate (one core), as one line.
    tr -d ' \n' <"$log" | grep -o '"estimated_seconds":[0-9.e+-]*\|"seconds":[0-9.e+-]*\|"arrays_written":[0-9]*\|"captures":[0-9]*' |
      tr '\n' ' ' | sed "s|^|  $(basename "$log" .log): |"
    echo
  done
  sed "s|^|  |" "$work/merge-$shards.log"
done
