#!/usr/bin/env bash
# One shard of a take per Slurm array task (docs/scale-out.md).
#   jid=$(sbatch --parsable --array=0-15 tools/scale-out/slurm_array.sh CAPTURE POSES PREPARED PARTS \
#         [ENCODE OPTIONS, e.g. --psnr 38])
#   sbatch --dependency=afterok:$jid --wrap "fvv join PARTS/part_*.fvv -o take.fvv"
# (shards that tracked, POSES "-": --wrap "join_parts.sh CAPTURE PREPARED PARTS take.fvv")
# The shard count is the array's size; the task's place in it is its shard
# (SLURM_ARRAY_TASK_ID, counted from the array's first index). POSES "-": the
# take was prepared without poses, and each shard tracks its own frames.
#SBATCH --job-name=fvv-shard
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --output=fvv-shard-%A_%a.log
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: sbatch --array=0-(N-1) $0 CAPTURE POSES PREPARED PARTS_DIR [ENCODE OPTIONS]" >&2
  exit 2
fi
capture=$1 poses=$2 prepared=$3 parts=$4
shift 4
: "${SLURM_ARRAY_TASK_ID:?not a Slurm array task (sbatch --array=0-(N-1))}"
n=${SLURM_ARRAY_TASK_COUNT:?}
k=$((SLURM_ARRAY_TASK_ID - ${SLURM_ARRAY_TASK_MIN:-0}))
pose_options=(--poses "$poses")
[ "$poses" != - ] || pose_options=()
mkdir -p "$parts"
exec "${FVV:-fvv}" encode "$capture" "${pose_options[@]}" --prepared "$prepared" --shard "$k/$n" \
  --threads "${SLURM_CPUS_PER_TASK:-1}" -q -o "$parts/part_$k.fvv" "$@"
