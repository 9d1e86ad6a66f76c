#!/usr/bin/env bash
# A take's shards over SSH hosts with GNU parallel, then the join
# (docs/scale-out.md). Every host sees the capture, poses, prepared take and
# parts directory at the same paths (a shared file system). POSES "-": the take
# was prepared without poses, and each shard tracks its own frames.
# Usage: tools/scale-out/parallel_shards.sh SHARDS HOSTS CAPTURE POSES PREPARED PARTS_DIR OUTPUT
#          [ENCODE OPTIONS, e.g. --psnr 38]
#   HOSTS: GNU parallel's --sshlogin list, e.g. "2/node1,2/node2" (":" is this machine)
# The shard of a job is its job number {#} less one.
set -euo pipefail
if [ $# -lt 7 ]; then
  echo "usage: $0 SHARDS HOSTS CAPTURE POSES PREPARED PARTS_DIR OUTPUT [ENCODE OPTIONS]" >&2
  exit 2
fi
shards=$1 hosts=$2 capture=$3 poses=$4 prepared=$5 parts=$6 output=$7
shift 7
fvv=${FVV:-fvv}
pose_options=(--poses "$poses")
[ "$poses" != - ] || pose_options=()
mkdir -p "$parts"
rm -f "$parts"/part_*.fvv  # parts of an earlier split would not join with these
# --halt now,fail=1: the first failed shard stops the others; rerun that shard alone.
parallel --sshlogin "$hosts" --halt now,fail=1 \
  "$fvv" encode "$capture" "${pose_options[@]}" --prepared "$prepared" \
  --shard '$(( {#} - 1 ))'/"$shards" --threads "${FVV_SHARD_THREADS:-1}" -q \
  -o "$parts"/'part_$(( {#} - 1 )).fvv' "$@" ::: $(seq "$shards")
if [ "$poses" = - ]; then
  # Shards that tracked: a part that lost the actor is encoded again after its neighbour.
  FVV=$fvv "$(dirname "$0")/join_parts.sh" "$capture" "$prepared" "$parts" "$output" \
    --threads "${FVV_SHARD_THREADS:-1}" "$@"
else
  "$fvv" join "$parts"/part_*.fvv -o "$output"
fi
