#!/bin/bash
# A private single-node Slurm for `make test-slurm` (Debian, root, no systemd needed).
#   tools/slurm-ci.sh start   install slurmctld/slurmd/slurm-client/munge if missing, start
#                             munged, slurmctld and slurmd on 127.0.0.1 with all state under
#                             $SLURM_CI_BASE (default /tmp/vito-slurm-ci); prints SLURM_CONF=...
#   tools/slurm-ci.sh stop    stop those daemons (by their PIDs) and remove $SLURM_CI_BASE
# Exit code 77 from `start`: Slurm cannot be had here (not root, no apt-get); callers skip.
# Ports: SLURM_CI_CTLD_PORT (default 6817), SLURM_CI_D_PORT (6818).
set -eu

BASE=${SLURM_CI_BASE:-/tmp/vito-slurm-ci}
CTLD_PORT=${SLURM_CI_CTLD_PORT:-6817}
D_PORT=${SLURM_CI_D_PORT:-6818}
HOST=$(hostname -s)

alive() { [ -n "${1:-}" ] && [ -e "/proc/$1/comm" ]; }
pid_of() { [ -f "$1" ] && cat "$1" || true; }

install_packages() {
    if command -v slurmctld >/dev/null && command -v slurmd >/dev/null \
        && command -v sbatch >/dev/null && command -v munged >/dev/null; then
        return 0
    fi
    if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null; then
        echo "slurm-ci: Slurm is not installed and cannot be (needs root and apt-get)" >&2
        exit 77
    fi
    # The packages must not start daemons of their own (no systemd here anyway).
    local made_policy=0
    if [ ! -e /usr/sbin/policy-rc.d ]; then
        printf '#!/bin/sh\nexit 101\n' >/usr/sbin/policy-rc.d
        chmod 755 /usr/sbin/policy-rc.d
        made_policy=1
    fi
    local rc=0
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
        --no-install-recommends slurmctld slurmd slurm-client munge >/dev/null; } || rc=$?
    [ $made_policy = 1 ] && rm -f /usr/sbin/policy-rc.d
    if [ $rc != 0 ]; then
        echo "slurm-ci: apt-get could not install Slurm (rc $rc)" >&2
        exit 77
    fi
}

start() {
    install_packages
    stop_daemons
    rm -rf "$BASE"
    mkdir -p "$BASE"/{munge,state,spool,run,log}
    chmod 755 "$BASE/munge"
    if ! mungekey --create --keyfile="$BASE/munge/munge.key" 2>/dev/null; then
        dd if=/dev/urandom of="$BASE/munge/munge.key" bs=1024 count=1 status=none
    fi
    chmod 600 "$BASE/munge/munge.key"
    cat >"$BASE/slurm.conf" <<EOF
ClusterName=ci
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$D_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$BASE/munge/munge.socket.2
StateSaveLocation=$BASE/state
SlurmdSpoolDir=$BASE/spool
SlurmctldPidFile=$BASE/run/slurmctld.pid
SlurmdPidFile=$BASE/run/slurmd.pid
SlurmctldLogFile=$BASE/log/slurmctld.log
SlurmdLogFile=$BASE/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$BASE/log/jobcomp.txt
MpiDefault=none
CommunicationParameters=NoInAddrAny,NoCtldInAddrAny
ReturnToService=2
MinJobAge=600
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=ci Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
    munged --socket="$BASE/munge/munge.socket.2" --key-file="$BASE/munge/munge.key" \
        --pid-file="$BASE/munge/munged.pid" --seed-file="$BASE/munge/munge.seed" \
        --log-file="$BASE/munge/munged.log"
    export SLURM_CONF="$BASE/slurm.conf"
    slurmctld -f "$SLURM_CONF"
    slurmd -f "$SLURM_CONF"
    for _ in $(seq 200); do
        if sinfo -h -o '%T' 2>/dev/null | grep -qx idle \
            && alive "$(pid_of "$BASE/run/slurmctld.pid")" \
            && alive "$(pid_of "$BASE/run/slurmd.pid")"; then
            echo "SLURM_CONF=$SLURM_CONF"
            return 0
        fi
        sleep 0.1
    done
    echo "slurm-ci: the node did not become idle; logs in $BASE/log" >&2
    exit 1
}

stop_daemons() {
    [ -f "$BASE/slurm.conf" ] && SLURM_CONF="$BASE/slurm.conf" scancel -p ci 2>/dev/null || true
    for f in "$BASE/run/slurmd.pid" "$BASE/run/slurmctld.pid" "$BASE/munge/munged.pid"; do
        local pid
        pid=$(pid_of "$f")
        alive "$pid" || continue
        kill "$pid" 2>/dev/null || true
        for _ in $(seq 100); do alive "$pid" || break; sleep 0.1; done
        alive "$pid" && kill -9 "$pid" 2>/dev/null || true
    done
}

case "${1:-}" in
    start) start ;;
    stop) stop_daemons; rm -rf "$BASE" ;;
    *) echo "usage: $0 start|stop" >&2; exit 2 ;;
esac
