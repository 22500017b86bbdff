#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for testing the workflow's Slurm profile: munged, slurmctld and
# slurmd on localhost, every file (munge key and socket, slurm.conf, state, spool, logs, job-completion log) in
# one temporary folder, on free ports, so nothing of the system's own configuration is used or changed.
#
# Usage: workflow/scripts/local_slurm.sh start DIR   configure and start; prints "export SLURM_CONF=DIR/slurm.conf"
#        workflow/scripts/local_slurm.sh stop DIR    stop the daemons started by "start DIR" (by their pid files)
# Needs (Debian): slurmctld slurmd slurm-client munge. Run as root (slurmd launches jobs as their user).
# The node has the machine's real short hostname, its CPU count (nproc) and RealMemory from `free -m`; one
# partition "local" (the default). Accounting storage is off (no slurmdbd); completed jobs are recorded by
# jobcomp/filetxt in DIR/jobcomp.log, which is what the test reads to check that jobs went through sbatch.
set -euo pipefail
action="${1:-}"
dir="${2:-}"
[ -n "$action" ] && [ -n "$dir" ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

stop_pidfile() {
  local f="$1"
  [ -f "$f" ] || return 0
  local pid
  pid="$(cat "$f")"
  if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null || true
  fi
  rm -f "$f"
}

if [ "$action" = stop ]; then
  stop_pidfile "$dir/slurmd.pid"
  stop_pidfile "$dir/slurmctld.pid"
  stop_pidfile "$dir/munged.pid"
  exit 0
fi
[ "$action" = start ] || { echo "$0: unknown action '$action' (start or stop)" >&2; exit 2; }

for tool in munged mungekey slurmctld slurmd sbatch scontrol sinfo; do
  command -v "$tool" > /dev/null || {
    echo "local_slurm.sh: $tool not found (install slurmctld slurmd slurm-client munge)" >&2; exit 3; }
done
[ "$(id -u)" -eq 0 ] || { echo "local_slurm.sh: slurmd must run as root to launch jobs; run as root" >&2; exit 3; }

mkdir -p "$dir"
dir="$(cd "$dir" && pwd)"
chmod 0700 "$dir"
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
chmod 0700 "$dir/munge"

free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1]); s.close()'
}

# munge: own key, socket, pid, log and seed files.
[ -f "$dir/munge/munge.key" ] || mungekey --create --keyfile="$dir/munge/munge.key" > /dev/null
chmod 0600 "$dir/munge/munge.key"
munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" --pid-file="$dir/munged.pid" \
  --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed" --force
for _ in $(seq 1 50); do [ -S "$dir/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$dir/munge/munge.socket" ] || { echo "local_slurm.sh: munged did not start (see $dir/munge/munged.log)" >&2; exit 4; }

node="$(hostname -s)"
cpus="$(nproc)"
mem_mb="$(free -m | awk '/^Mem:/ {print $2}')"
ctld_port="$(free_port)"
slurmd_port="$(free_port)"
cat > "$dir/slurm.conf" <<EOF
# Single-node test cluster written by workflow/scripts/local_slurm.sh.
ClusterName=glmbslamtest
SlurmctldHost=${node}(127.0.0.1)
SlurmctldPort=${ctld_port}
SlurmdPort=${slurmd_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=${dir}/munge/munge.socket
StateSaveLocation=${dir}/state
SlurmdSpoolDir=${dir}/spool
SlurmctldPidFile=${dir}/slurmctld.pid
SlurmdPidFile=${dir}/slurmd.pid
SlurmctldLogFile=${dir}/slurmctld.log
SlurmdLogFile=${dir}/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups: process tracking by /proc, no task containment (works in containers without cgroup delegation).
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/linux
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=${dir}/jobcomp.log
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge=3600
MpiDefault=none
SwitchType=switch/none
NodeName=${node} NodeAddr=127.0.0.1 CPUs=${cpus} RealMemory=${mem_mb} State=UNKNOWN
PartitionName=local Nodes=${node} Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$dir/slurm.conf"
slurmctld -f "$dir/slurm.conf"
slurmd -f "$dir/slurm.conf" -N "$node"
# Wait until the node is idle (slurmd registered).
state=""
for _ in $(seq 1 100); do
  state="$(sinfo -h -n "$node" -o %t 2>/dev/null || true)"
  [ "$state" = idle ] && break
  sleep 0.3
done
if [ "$state" != idle ]; then
  echo "local_slurm.sh: node $node not idle after 30 s (state '$state'); see $dir/slurmctld.log, $dir/slurmd.log" >&2
  exit 4
fi
echo "export SLURM_CONF=$dir/slurm.conf"
