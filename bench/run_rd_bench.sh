#!/usr/bin/env bash
# Rate-distortion of the encoder against per-frame JPEG 2000 (OpenJPEG) and
# H.264 / H.265 (ffmpeg libx264 / libx265) on the demo capture's multi-view
# atlas textures, at 20:1, 50:1, 120:1 and 280:1; one table from one run.
# Usage: bench/run_rd_bench.sh [frames, default 16]   (makes out/rd_bench/ if absent)
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target fvv rd_bench
fvv=build/tools/fvv/fvv
out=out/rd_bench
frames=${1:-16}
if [ ! -f "$out/textures/textures.json" ]; then
  rm -rf "$out" && mkdir -p "$out"
  # The demo capture (CMU 01_01 on the built-in actor, 8 cameras at 640x480),
  # tracked and resampled as `fvv encode` does it.
  $fvv synth -o "$out/capture" --frames "$frames" --motion /usr/share/assimp/models/BVH/01_01.bvh
  $fvv encode "$out/capture" -o "$out/capture.fvv" --masks --save-textures "$out/textures" -q
fi
build/bench/rd_bench "$out/textures" "$out/capture" "$out/work" --frames "$frames"
