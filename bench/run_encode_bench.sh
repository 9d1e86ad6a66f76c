#!/usr/bin/env bash
# Encoding speed with the capture front end included (target: >= 1
# frame/s for 8 cameras at 640x480 on a 2-core machine): `fvv encode` tracks
# the sample capture (8 cameras, 640x480, 50 frames of CMU 01_01), resamples,
# codes and writes it; frames per second of wall time, as the encoder reports.
# With a git ref, that revision's encoder is built in a worktree and run on the
# same capture, alternating with this one, for a ratio measured side by side
# (and the two streams are compared byte for byte).
#   bench/run_encode_bench.sh [PEER_GIT_REF] [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
peer_ref=${1:-}
rounds=${2:-2}
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target fvv >/dev/null
fvv=build/tools/fvv/fvv
work=${FVV_BENCH_DIR:-/tmp/fvv_encode_bench}
mkdir -p "$work"
if [ ! -f "$work/capture/capture.json" ]; then
  motion=()
  bvh=/usr/share/assimp/models/BVH/01_01.bvh
  [ -f "$bvh" ] && motion=(--motion "$bvh")
  $fvv synth -o "$work/capture" --frames 50 "${motion[@]}" >/dev/null
fi
encoders=("this:$fvv")
if [ -n "$peer_ref" ]; then
  peer_dir="$work/peer"
  git worktree remove --force "$peer_dir" 2>/dev/null || rm -rf "$peer_dir"
  git worktree add --force --detach "$peer_dir" "$peer_ref" >/dev/null
  echo "building the peer encoder ($peer_ref) in $peer_dir ..."
  cmake -S "$peer_dir" -B "$peer_dir/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DFVV_BUILD_TESTS=OFF -DFVV_BUILD_BENCH=OFF >/dev/null
  cmake --build "$peer_dir/build" -j2 --target fvv >/dev/null
  encoders+=("$peer_ref:$peer_dir/build/tools/fvv/fvv")
fi
printf '%-14s %5s %9s %9s %9s\n' encoder round "wall s" "frames/s" "cpu s"
declare -A sum
TIMEFORMAT='%R %U %S'
for r in $(seq "$rounds"); do
  for e in "${encoders[@]}"; do
    name=${e%%:*} bin=${e#*:}
    t=$( { time "$bin" encode "$work/capture" -o "$work/$name.fvv" -q >/dev/null 2>&1; } 2>&1)
    read -r wall user sys <<<"$t"
    sum[$name]=$(awk -v a="${sum[$name]:-0}" -v b="$wall" 'BEGIN { print a + b }')
    awk -v n="$name" -v r="$r" -v w="$wall" -v u="$user" -v s="$sys" \
      'BEGIN { printf "%-14s %5d %9.1f %9.2f %9.1f\n", n, r, w, 50 / w, u + s }'
  done
done
if [ -n "$peer_ref" ]; then
  awk -v p="${sum[$peer_ref]}" -v t="${sum[this]}" -v n="$peer_ref" \
    'BEGIN { printf "speed-up of this encoder over %s: %.2fx (total wall time)\n", n, p / t }'
  if cmp -s "$work/this.fvv" "$work/$peer_ref.fvv"; then
    echo "streams: byte-identical"
  else
    echo "streams: differ"
  fi
fi
