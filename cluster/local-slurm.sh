#!/usr/bin/env bash
# A real single-node SLURM on this machine, to prove simpick's SLURM profile (profiles/slurm).
#
#   cluster/local-slurm.sh start    install (Debian slurm-wlm, munge) if needed, write a one-node
#                                   slurm.conf, start munged, slurmctld and slurmd; wait until idle
#   cluster/local-slurm.sh stop     stop the three daemons
#   cluster/local-slurm.sh status   sinfo
#
# Needs root (it writes /etc/slurm and starts daemons). Nothing here is needed on a real cluster:
# there the site's SLURM is used and only profiles/slurm is pointed at its partition and account.
set -euo pipefail

STATE=/var/lib/simpick-slurm          # spool and state of this throw-away cluster
CONF=/etc/slurm/slurm.conf
NODE=$(hostname -s)

die() { echo "local-slurm: $*" >&2; exit 1; }

install() {
    if command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v munged >/dev/null; then
        return
    fi
    [ "$(id -u)" = 0 ] || die "run as root to install slurm-wlm and munge (apt-get)"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null
}

write_conf() {
    local cpus mem
    cpus=$(nproc)
    # memory SLURM may hand to jobs: 90 % of the machine, in MB
    mem=$(awk '/MemTotal/ {printf "%d", $2 / 1024 * 0.9}' /proc/meminfo)
    if [ -e "$CONF" ] && ! grep -q "written by simpick cluster/local-slurm.sh" "$CONF"; then
        die "$CONF exists and is not ours: this machine has a SLURM set-up; use it (profiles/slurm) instead"
    fi
    mkdir -p /etc/slurm "$STATE/ctld" "$STATE/d" /var/log/slurm
    cat > "$CONF" <<EOF
# written by simpick cluster/local-slurm.sh: a one-node test cluster, not for production
ClusterName=simpick-local
SlurmctldHost=$NODE
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$STATE/ctld
SlurmdSpoolDir=$STATE/d
SlurmctldPidFile=$STATE/slurmctld.pid
SlurmdPidFile=$STATE/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
# no cgroups in a container: track processes by parent id, no task containment
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
# no slurmdbd: sacct then asks slurmctld, which keeps finished jobs for MinJobAge seconds
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MinJobAge=600
SchedulerType=sched/backfill
# cores and memory are consumable, as on a real cluster: a job asking mem_mb gets it or waits
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MpiDefault=none
NodeName=$NODE CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
}

start() {
    install
    [ "$(id -u)" = 0 ] || die "run as root (it writes $CONF and starts slurmctld, slurmd and munged)"
    write_conf
    if [ ! -s /etc/munge/munge.key ]; then
        mkdir -p /etc/munge
        dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
    fi
    chown munge:munge /etc/munge/munge.key 2>/dev/null || true
    chmod 400 /etc/munge/munge.key
    mkdir -p /run/munge /var/log/munge /var/lib/munge
    chown munge:munge /run/munge /var/log/munge /var/lib/munge 2>/dev/null || true
    pgrep -x munged >/dev/null || runuser -u munge -- munged 2>/dev/null || munged --force
    pgrep -x slurmctld >/dev/null || slurmctld
    pgrep -x slurmd >/dev/null || slurmd
    for _ in $(seq 60); do
        if sinfo -h -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)'; then
            sinfo
            return
        fi
        sleep 1
    done
    tail -20 /var/log/slurm/slurmctld.log /var/log/slurm/slurmd.log >&2 || true
    die "the node did not come up in 60 s (logs above)"
}

stop() {
    pkill -x slurmd || true
    pkill -x slurmctld || true
    pkill -x munged || true
}

case "${1:-start}" in
    start) start ;;
    stop) stop ;;
    status) sinfo ;;
    *) die "usage: $0 start|stop|status" ;;
esac
