#!/usr/bin/env bash
# A one-node SLURM cluster on this machine, for the tests and CI: one slurmctld and one
# slurmd run as root, with a munged of their own, all configured and kept in one folder
# (default target/slurm-local; GLYPHCAST_SLURM_DIR overrides it).
#
#   bash tools/slurm-local.sh start    # installs slurm-wlm and munge when missing, starts
#                                      # the daemons, waits until the node is idle
#   bash tools/slurm-local.sh stop     # stops the daemons this folder started (by pid)
#   bash tools/slurm-local.sh status   # running or not (exit 0 or 1), and sinfo
#   bash tools/slurm-local.sh env      # prints `export SLURM_CONF=...` for eval
#
# The clients (sbatch, squeue, scancel, sinfo) find this cluster through SLURM_CONF:
# `eval "$(bash tools/slurm-local.sh env)"` after `start`. A cluster set up otherwise
# needs none of this: the cohort scripts use whatever sbatch and squeue are on the PATH.
#
# The node: ProctrackType=proctrack/linuxproc, TaskPlugin=task/none (no cgroup.conf),
# SelectType=select/cons_tres over cores and memory, no accounting (no slurmdbd), CPUs
# the machine's core count and RealMemory 3/4 of its memory. Ports 16817 and 16818
# (GLYPHCAST_SLURM_PORT, GLYPHCAST_SLURM_PORT+1), so that a cluster already on this
# machine (6817/6818) is not disturbed.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
dir="${GLYPHCAST_SLURM_DIR:-$root/target/slurm-local}"
port="${GLYPHCAST_SLURM_PORT:-16817}"
conf="$dir/etc/slurm.conf"

usage() {
    echo "usage: bash tools/slurm-local.sh start|stop|status|env" >&2
    exit 2
}
[ $# -eq 1 ] || usage

die() {
    echo "error: $*" >&2
    exit 1
}

# Debian's packages: slurmctld, slurmd and the clients (slurm-wlm), munged (munge).
install_packages() {
    local missing=()
    command -v slurmctld >/dev/null 2>&1 || missing+=(slurm-wlm)
    command -v slurmd >/dev/null 2>&1 || missing+=(slurm-wlm)
    command -v sbatch >/dev/null 2>&1 || missing+=(slurm-wlm)
    command -v munged >/dev/null 2>&1 || missing+=(munge)
    [ -x /usr/sbin/munged ] || missing+=(munge)
    [ ${#missing[@]} -eq 0 ] && return 0
    [ "$(id -u)" = 0 ] || die "slurm-wlm and munge are missing; install them (as root: apt-get install slurm-wlm munge)"
    command -v apt-get >/dev/null 2>&1 || die "slurm-wlm and munge are missing and there is no apt-get to install them"
    echo "== installing slurm-wlm and munge" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        slurm-wlm munge >&2
}

# The pid in FILE if that process is alive, else nothing.
live_pid() {
    local pid
    [ -f "$1" ] || return 0
    pid="$(cat "$1")"
    if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
        echo "$pid"
    fi
}

write_config() {
    local host cpus mem_kb mem_mb
    host="$(hostname -s)"
    cpus="$(nproc)"
    mem_kb="$(awk '/^MemTotal:/ {print $2}' /proc/meminfo)"
    mem_mb=$((mem_kb / 1024 * 3 / 4))
    mkdir -p "$dir/etc" "$dir/state" "$dir/spool" "$dir/log" "$dir/run" "$dir/munge"
    chmod 700 "$dir/munge"
    # The key the daemons and the clients share (1 KiB of random bytes, munged's format).
    if [ ! -s "$dir/munge/munge.key" ]; then
        (umask 077 && head -c 1024 /dev/urandom >"$dir/munge/munge.key.tmp")
        mv "$dir/munge/munge.key.tmp" "$dir/munge/munge.key"
    fi
    cat >"$conf.tmp" <<EOF
# Written by tools/slurm-local.sh: a one-node cluster for glyphcast's tests.
ClusterName=glyphcast-local
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/slurmd
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
DefMemPerCPU=1024
SchedulerType=sched/backfill
MpiDefault=none
SwitchType=switch/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=60
InactiveLimit=0
KillWait=10
MinJobAge=300
MaxArraySize=10001
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
    mv "$conf.tmp" "$conf"
}

start() {
    install_packages
    [ "$(id -u)" = 0 ] || die "the local cluster's daemons run as root; run this as root"
    write_config
    local munged=/usr/sbin/munged
    if [ -z "$(live_pid "$dir/run/munged.pid")" ]; then
        # --force: munged otherwise refuses a socket folder outside /run/munge.
        "$munged" --force --key-file="$dir/munge/munge.key" \
            --socket="$dir/munge/munge.socket" --pid-file="$dir/run/munged.pid" \
            --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed" \
            || die "munged did not start (see $dir/log/munged.log)"
    fi
    if [ -z "$(live_pid "$dir/run/slurmctld.pid")" ]; then
        slurmctld -f "$conf" || die "slurmctld did not start (see $dir/log/slurmctld.log)"
    fi
    if [ -z "$(live_pid "$dir/run/slurmd.pid")" ]; then
        slurmd -f "$conf" || die "slurmd did not start (see $dir/log/slurmd.log)"
    fi
    # Up to 60 s for the node to register and become idle.
    local state="" i
    for i in $(seq 1 120); do
        state="$(SLURM_CONF="$conf" sinfo -h -N -o %T 2>/dev/null | head -1 || true)"
        case "$state" in
        idle) break ;;
        down* | drain* | fail*)
            # A node left down by an earlier run of this folder: it is ours to resume.
            SLURM_CONF="$conf" scontrol update nodename="$(hostname -s)" state=resume \
                >/dev/null 2>&1 || true ;;
        esac
        sleep 0.5
    done
    if [ "$state" != idle ]; then
        echo "error: the node is '${state:-not registered}' after 60 s; the logs:" >&2
        tail -n 5 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 || true
        exit 1
    fi
    echo "== local SLURM cluster up: export SLURM_CONF=$conf" >&2
}

stop() {
    local name pid i
    # Reverse order: the node, the controller, then the authentication they used.
    for name in slurmd slurmctld munged; do
        pid="$(live_pid "$dir/run/$name.pid")"
        [ -n "$pid" ] || continue
        kill -TERM "$pid" 2>/dev/null || true
        for i in $(seq 1 40); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.25
        done
        if kill -0 "$pid" 2>/dev/null; then
            echo "warning: $name ($pid) still running after 10 s; sending KILL" >&2
            kill -KILL "$pid" 2>/dev/null || true
        fi
        rm -f "$dir/run/$name.pid"
    done
}

case "$1" in
start) start ;;
stop) stop ;;
status)
    for name in munged slurmctld slurmd; do
        [ -n "$(live_pid "$dir/run/$name.pid")" ] || { echo "$name: not running"; exit 1; }
    done
    SLURM_CONF="$conf" sinfo
    ;;
env) printf 'export SLURM_CONF=%q\n' "$conf" ;;
*) usage ;;
esac
