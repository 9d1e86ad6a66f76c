#!/usr/bin/env bash
# Encoding in shards on this machine: one process on the whole take against N
# shards run side by side by GNU parallel (--sshlogin : stands in for remote
# hosts), each with one thread; then the join, checked byte for byte against
# the single run, and the time of each stage. docs/scale-out.md has the figures
# and the scaling table built from them.
# Usage: bench/run_shard_bench.sh [frames, default 48] [shards, default 2] [cameras, default 8]
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-48}
shards=${2:-2}
cameras=${3:-8}
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target fvv >/dev/null
fvv=$PWD/build/tools/fvv/fvv
work=${FVV_BENCH_DIR:-out/shard_bench}
rm -rf "$work" && mkdir -p "$work"
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a / b }'; }

echo "== a synthetic take: $frames frames, $cameras cameras at 640x480"
"$fvv" synth -o "$work/cap" --frames "$frames" --cameras "$cameras" --held-out 0 >/dev/null
poses=$work/cap  # the take's poses: one tracking pass shared by every shard (here the truth)
common=(--poses "$poses" --threads 1 -q)

t0=$(now)
"$fvv" encode "$work/cap" "${common[@]}" --prepare "$work/prep" >/dev/null
t1=$(now)
echo "prepare: $(secs "$t0" "$t1") s"

"$fvv" encode "$work/cap" "${common[@]}" --prepared "$work/prep" -o "$work/single.fvv" \
  --summary-json "$work/single.json" >/dev/null
t2=$(now)
single=$(secs "$t1" "$t2")
echo "single process, 1 thread: $single s"

# {#} is GNU parallel's job number, from 1.
parallel --sshlogin "$shards/:" --halt now,fail=1 \
  "$fvv" encode "$work/cap" "${common[@]}" --prepared "$work/prep" \
  --shard '$(( {#} - 1 ))'/"$shards" -o "$work"/'part_$(( {#} - 1 )).fvv' ::: $(seq "$shards") \
  >/dev/null
t3=$(now)
sharded=$(secs "$t2" "$t3")
echo "$shards shards side by side (GNU parallel), 1 thread each: $sharded s"

"$fvv" join "$work"/part_*.fvv -o "$work/joined.fvv" -q
t4=$(now)
echo "join: $(secs "$t3" "$t4") s"
if cmp -s "$work/single.fvv" "$work/joined.fvv"; then
  echo "joined == single run: identical, $(stat -c %s "$work/joined.fvv") bytes"
else
  echo "joined != single run"
  exit 1
fi
# What the prepared take's fixed fallback texture costs or gains against the
# running one of an encode without it (bytes and PSNR over visible texels).
"$fvv" encode "$work/cap" "${common[@]}" -o "$work/unprepared.fvv" \
  --summary-json "$work/unprepared.json" >/dev/null
figures() {
  python3 -c 'import json, sys
j = json.load(open(sys.argv[1]))
print("%d bytes, %.2f dB" % (j["bytes"]["file"], j["psnr"]["rgb"]))' "$1"
}
echo "file, RGB PSNR over visible texels: prepared $(figures "$work/single.json"); without" \
  "--prepared $(figures "$work/unprepared.json")"
echo "speed-up: $(ratio "$single" "$sharded")x (encode only; prepare and join are the serial part)"
echo "per frame, one thread: $(ratio "$single" "$frames") s ($cameras cameras, 512^2 atlas)"
