#!/usr/bin/env bash
# A one-node SLURM on this machine, for running the workflow through profiles/slurm for real (and for
# tests/test_slurm.py). Run as root; no systemd needed: every daemon is started by hand.
#
#   workflow/cluster/setup_slurm.sh          # install (Debian slurm-wlm, munge), configure, start
#   workflow/cluster/setup_slurm.sh stop     # stop the daemons it started
#
# Tested with Debian 12's slurm-wlm 22.05 and snakemake-executor-plugin-slurm 2.8. No accounting
# database: job status comes from squeue (the profile's slurm-status-command), so finished jobs stay
# visible to squeue for MinJobAge = 300 s. EnforcePartLimits=ALL makes sbatch refuse at once a job
# asking for more CPUs or memory than the node has, instead of leaving it PENDING forever.
set -euo pipefail

RUN=/run/vibroimpact-slurm          # pid files of the daemons started here
CONF=/etc/slurm/slurm.conf
PARTITION=${VIBROIMPACT_SLURM_PARTITION:-local}

stop() {
    for d in slurmd slurmctld munged; do
        if [ -f "$RUN/$d.pid" ]; then
            kill "$(cat "$RUN/$d.pid")" 2>/dev/null || true
            rm -f "$RUN/$d.pid"
        fi
    done
}

if [ "${1:-}" = stop ]; then
    stop
    exit 0
fi

if [ "$(id -u)" != 0 ]; then
    echo "setup_slurm.sh: run as root (it installs packages and starts daemons)" >&2
    exit 2
fi

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge >/dev/null
fi

stop
mkdir -p "$RUN" /var/spool/slurmctld /var/spool/slurmd /var/log/slurm /run/munge /etc/munge
chown munge:munge /run/munge /etc/munge
[ -s /etc/munge/munge.key ] || mungekey --create --keyfile=/etc/munge/munge.key
chown munge:munge /etc/munge/munge.key
chmod 400 /etc/munge/munge.key
mkdir -p /var/log/munge /var/lib/munge
chown munge:munge /var/log/munge /var/lib/munge
runuser -u munge -- munged
sleep 1
cp /run/munge/munged.pid "$RUN/munged.pid"

host=$(hostname -s)
cpus=$(nproc)
mem=$(( $(free -m | awk '/^Mem:/{print $2}') * 9 / 10 ))
cat >"$CONF" <<EOF
# written by vibroimpact's workflow/cluster/setup_slurm.sh: a one-node cluster
ClusterName=vibroimpact
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=$RUN/slurmctld.pid
SlurmdPidFile=$RUN/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge=300
EnforcePartLimits=ALL
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=$PARTITION Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld
slurmd
for _ in $(seq 60); do
    if sinfo -h -o %T 2>/dev/null | grep -qx idle; then
        srun -N1 -n1 true
        echo "one-node SLURM ready: partition '$PARTITION', node $host, $cpus CPUs, $mem MB"
        exit 0
    fi
    sleep 1
done
echo "setup_slurm.sh: the node did not become idle; see /var/log/slurm/" >&2
sinfo >&2 || true
exit 1
