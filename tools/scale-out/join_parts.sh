#!/usr/bin/env bash
# The join step of every engine (docs/scale-out.md): fvv join over a parts
# directory. Where shards tracked their own frames and the join finds two
# parts disagreeing at their border (a shard's first-frame search lost the
# actor), the shard it names is encoded again going on from the part before
# it (--after), on this machine, and the join tried again, at most once per
# border.
# Usage: tools/scale-out/join_parts.sh CAPTURE PREPARED PARTS_DIR OUTPUT [ENCODE OPTIONS]
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 CAPTURE PREPARED PARTS_DIR OUTPUT [ENCODE OPTIONS]" >&2
  exit 2
fi
capture=$1 prepared=$2 parts=$3 output=$4
shift 4
fvv=${FVV:-fvv}
shards=$(ls "$parts"/part_*.fvv | wc -l)
for ((attempt = 0; attempt < shards; ++attempt)); do
  if out=$("$fvv" join "$parts"/part_*.fvv -o "$output" 2>&1); then
    echo "$out"
    exit 0
  fi
  if ! grep -q "disagree at their border" <<<"$out"; then
    echo "$out" >&2
    exit 1
  fi
  k=$(grep -o 'encode shard [0-9]* again' <<<"$out" | grep -o '[0-9]*')
  before=$(grep -o 'again with --after [^,]*' <<<"$out" | sed 's/again with --after //')
  echo "$out" >&2
  echo "join_parts: shard $k disagrees with the part before it; encoding it again after $before" >&2
  "$fvv" encode "$capture" --prepared "$prepared" --shard "$k/$shards" --after "$before" -q \
    -o "$parts/part_$k.fvv" "$@" >/dev/null
done
"$fvv" join "$parts"/part_*.fvv -o "$output"
