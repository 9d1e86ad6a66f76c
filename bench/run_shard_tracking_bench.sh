#!/usr/bin/env bash
# Tracking inside each shard (docs/scale-out.md, "Tracking in shards"): on a
# synthetic take with ground truth, the joint error at shard borders against a
# tracking run over the whole take, for each warm-up; then, with the default
# warm-up, one process that tracks and encodes the whole take against N shards
# that each track and encode their own frames, side by side under GNU parallel,
# one thread each, and the join.
# Usage: bench/run_shard_tracking_bench.sh [frames, default 48] [shards, default 3]
#        [cameras, default 8] [warm-ups, default "0 4 8 16"] [shards timed, default 2]
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-48}
shards=${2:-3}
cameras=${3:-8}
warmups=${4-0 4 8 16}  # "": the timing alone
timed=${5:-2}  # one per core of this machine
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target fvv >/dev/null
fvv=$PWD/build/tools/fvv/fvv
work=${FVV_BENCH_DIR:-out/shard_tracking_bench}
rm -rf "$work" && mkdir -p "$work"
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
# fvv track --truth's per-frame joint errors (cm), one per line.
per_frame() { grep -E '^ +cm:' "$1" | sed 's/cm://' | tr -s ' ' '\n' | grep -v '^$'; }

echo "== a synthetic take: $frames frames, $cameras cameras at 640x480, $shards shards"
"$fvv" synth -o "$work/cap" --frames "$frames" --cameras "$cameras" --held-out 0 >/dev/null
if [ -n "$warmups" ]; then
"$fvv" track "$work/cap" -o "$work/whole.json" --truth "$work/cap" -q >"$work/whole.txt"
per_frame "$work/whole.txt" >"$work/whole.cm"
echo "whole take tracked in one run: $(grep 'joint error' "$work/whole.txt" | sed 's/ (.*//')"

# The border frames: the 8 frames on each side of every border between shards.
borders=$(python3 -c 'import sys
frames, gop, shards = map(int, sys.argv[1:])
spans = (frames + gop - 1) // gop
print(" ".join(str(spans * k // shards * gop) for k in range(1, shards)))' "$frames" 8 "$shards")
echo "borders before frames: $borders"
echo
echo "| warm-up | prepare (s) | mean error, all frames | within 8 frames of a border | whole-take run there | worst frame's excess |"
echo "|---|---|---|---|---|---|"
for w in $warmups; do
  prep=$work/prep_w$w
  t0=$(now)
  "$fvv" encode "$work/cap" --prepare "$prep" --warm-up "$w" -q >/dev/null
  t1=$(now)
  : >"$work/shards_w$w.cm"
  for ((k = 0; k < shards; ++k)); do
    "$fvv" track "$work/cap" --prepared "$prep" --shard "$k/$shards" -q -o "$work/part_w${w}_$k.json" \
      --truth "$work/cap" >"$work/part_w${w}_$k.txt"
    per_frame "$work/part_w${w}_$k.txt" >>"$work/shards_w$w.cm"
  done
  paste "$work/shards_w$w.cm" "$work/whole.cm" | python3 -c 'import sys
borders = [int(b) for b in sys.argv[1].split()]
rows = [tuple(map(float, l.split())) for l in sys.stdin]
near = [i for i in range(len(rows)) if any(b - 8 <= i < b + 8 for b in borders)]
mean = lambda v: sum(v) / len(v)
print("| %s | %s | %.2f cm (whole-take run %.2f) | %.2f cm | %.2f cm | %+.1f cm |" % (
    sys.argv[2], sys.argv[3], mean([r[0] for r in rows]), mean([r[1] for r in rows]),
    mean([rows[i][0] for i in near]), mean([rows[i][1] for i in near]),
    max(rows[i][0] - rows[i][1] for i in near)))' "$borders" "$w" "$(secs "$t0" "$t1")"
done
fi
echo
# Each process on a core of its own (taskset), as on machines of their own: one
# encode that tracks runs its coding on a thread beside the tracking, which
# would otherwise take the second core.
echo "== tracking and encoding: one process against $timed shards, one core each"
prep=$work/prep_timed
t0=$(now)
taskset -c 0 "$fvv" encode "$work/cap" --threads 1 -q -o "$work/single.fvv" \
  --summary-json "$work/single.json" >/dev/null
t1=$(now)
single=$(secs "$t0" "$t1")
echo "one process on one core, tracking and encoding the whole take: $single s"
t2=$(now)
"$fvv" encode "$work/cap" --prepare "$prep" --warm-up 8 --threads 1 -q >/dev/null
t3=$(now)
parallel --sshlogin "$timed/:" --halt now,fail=1 \
  taskset -c '$(( ({%} - 1) % '"$(nproc)"' ))' "$fvv" encode "$work/cap" --threads 1 -q --prepared "$prep" \
  --shard '$(( {#} - 1 ))'/"$timed" -o "$work"/'tracked_part_$(( {#} - 1 )).fvv' \
  --summary-json "$work"/'tracked_part_$(( {#} - 1 )).json' ::: $(seq "$timed") >/dev/null
t4=$(now)
mkdir -p "$work/tracked_parts"
for f in "$work"/tracked_part_*.fvv; do mv "$f" "$work/tracked_parts/part_${f##*_}"; done
# A part that lost the actor is encoded again after its neighbour (join_parts.sh says so).
FVV=$fvv tools/scale-out/join_parts.sh "$work/cap" "$prep" "$work/tracked_parts" "$work/joined.fvv" \
  --threads 1 >/dev/null
t5=$(now)
sharded=$(secs "$t3" "$t4")
echo "prepare (shape from the first 16 frames, 8 texture frames fitted): $(secs "$t2" "$t3") s"
echo "$timed shards side by side (GNU parallel), one core each: $sharded s"
echo "join: $(secs "$t4" "$t5") s"
echo "speed-up: $(ratio "$single" "$sharded")x shards alone, $(ratio "$single" "$(secs "$t2" "$t5")")x" \
  "with the prepare and join"
"$fvv" info "$work/joined.fvv" >/dev/null
python3 -c 'import json, sys
j = json.load(open(sys.argv[1]))
print("single run: %d bytes, %.2f dB RGB over visible texels" % (j["bytes"]["file"], j["psnr"]["rgb"]))
parts = [json.load(open(p)) for p in sys.argv[3:]]
frames = sum(p["frames"] for p in parts)
print("joined: %d bytes, %.2f dB (the parts own, frame-weighted)" % (int(sys.argv[2]),
      sum(p["psnr"]["rgb"] * p["frames"] for p in parts) / frames))' "$work/single.json" \
  "$(stat -c %s "$work/joined.fvv")" "$work"/tracked_part_*.json
