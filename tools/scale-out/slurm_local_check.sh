#!/usr/bin/env bash
# Runs slurm_array.sh under a real, single-node Slurm on this machine and
# checks the joined stream against one encode (docs/scale-out.md). Needs root
# and Debian's slurm-wlm and munge (apt-get install slurm-wlm munge); starts
# munged, slurmctld and slurmd on a private configuration and stops them again.
# Usage: tools/scale-out/slurm_local_check.sh FVV WORK_DIR
set -euo pipefail
fvv=$(readlink -f "${1:?usage: $0 FVV WORK_DIR}")
work=${2:?usage: $0 FVV WORK_DIR}
scripts=$(cd "$(dirname "$0")" && pwd)
for p in slurmctld slurmd sbatch munged; do
  command -v $p >/dev/null || { echo "$p not found: apt-get install slurm-wlm munge" >&2; exit 2; }
done
rm -rf "$work" && mkdir -p "$work"/{spool,ctld,log}
work=$(readlink -f "$work")
node=$(hostname -s)
export SLURM_CONF=$work/slurm.conf
cat >"$SLURM_CONF" <<CONF
ClusterName=fvvcheck
SlurmctldHost=$node
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmUser=root
SlurmctldPort=16817
SlurmdPort=16818
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
StateSaveLocation=$work/ctld
SlurmdSpoolDir=$work/spool
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
NodeName=$node CPUs=$(nproc) RealMemory=2000 State=UNKNOWN
PartitionName=check Nodes=$node Default=YES MaxTime=60 State=UP
CONF
stop() {
  local pids=()
  for f in "$work"/slurmd.pid "$work"/slurmctld.pid ${started_munge:+/run/munge/munged.pid}; do
    [ -f "$f" ] && pids+=("$(cat "$f")")
  done
  [ ${#pids[@]} -gt 0 ] || return 0
  kill "${pids[@]}" 2>/dev/null || true
  for _ in $(seq 20); do  # the daemons finish their shutdown before they exit
    kill -0 "${pids[@]}" 2>/dev/null || return 0
    sleep 0.5
  done
  kill -9 "${pids[@]}" 2>/dev/null || true
}
mkdir -p /run/munge
started_munge=
if ! pgrep -x munged >/dev/null; then
  munged --force
  started_munge=1
  for _ in $(seq 20); do
    munge -n >/dev/null 2>&1 && break
    sleep 0.5
  done
fi
trap stop EXIT
slurmctld
slurmd
for _ in $(seq 30); do
  sinfo -h -o %t 2>/dev/null | grep -q idle && break
  sleep 1
done
sinfo -h -o %t | grep -q idle || { echo "Slurm did not start (logs in $work/log)" >&2; exit 1; }

"$fvv" synth -o "$work/cap" --cameras 2 --width 160 --height 120 --frames 7 --held-out 0 \
  --unlit --noise 0 >/dev/null 2>&1
poses=$work/cap/truth/truth.json
"$fvv" encode "$work/cap" --poses "$poses" --atlas 128 --gop-frames 2 --prepare "$work/prep" -q \
  >/dev/null
"$fvv" encode "$work/cap" --poses "$poses" --prepared "$work/prep" -q -o "$work/single.fvv" >/dev/null
cd "$work"
array=$(FVV="$fvv" sbatch --parsable --export=ALL --array=0-3 --cpus-per-task=1 --mem=500M \
  "$scripts/slurm_array.sh" "$work/cap" "$poses" "$work/prep" "$work/parts")
join=$(sbatch --parsable --dependency=afterok:"$array" --mem=500M \
  --wrap "$fvv join $work/parts/part_*.fvv -o $work/take.fvv")
echo "array job $array (4 tasks), join job $join"
for _ in $(seq 120); do
  [ -z "$(squeue -h -j "$array,$join" 2>/dev/null)" ] && break
  sleep 1
done
cat "$work/slurm-$join.out"
cmp "$work/single.fvv" "$work/take.fvv"
echo "PASS: Slurm's array and dependent join wrote the single encode's bytes"
