#!/usr/bin/env bash
# Rate-distortion of the encoder against per-frame JPEG 2000 (OpenJPEG) and
# H.264 / H.265 (ffmpeg libx264 / libx265) on the demo capture's multi-view
# atlas textures, at 20:1, 50:1, 120:1 and 280:1; one table from one run.
# Usage: bench/run_rd_bench.sh [frames, default 16] [masks: on (default) | off]
#   (makes out/rd_bench/ if absent). With masks off fvv's streams carry none:
#   the textures of a mask-free encode of the same capture and poses, and fvv's
#   total bytes are its texture bytes. Further arguments go to rd_bench.
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target fvv rd_bench
fvv=build/tools/fvv/fvv
out=out/rd_bench
frames=${1:-16}
masks=${2:-on}
shift $(($# < 2 ? $# : 2))
if [ ! -f "$out/textures/textures.json" ]; then
  rm -rf "$out" && mkdir -p "$out"
  # The demo capture (CMU 01_01 on the built-in actor, 8 cameras at 640x480),
  # tracked and resampled as `fvv encode` does it.
  $fvv synth -o "$out/capture" --frames "$frames" --motion /usr/share/assimp/models/BVH/01_01.bvh
  $fvv track "$out/capture" -o "$out/poses.json" -q
  $fvv encode "$out/capture" -o "$out/capture.fvv" --poses "$out/poses.json" --masks \
    --save-textures "$out/textures" -q
fi
textures=$out/textures
if [ "$masks" = off ]; then
  textures=$out/textures_no_masks
  # The same poses, so both tables code the same surface.
  [ -f "$textures/textures.json" ] || $fvv encode "$out/capture" -o "$out/capture_no_masks.fvv" \
    --poses "$out/poses.json" --save-textures "$textures" -q
fi
build/bench/rd_bench "$textures" "$out/capture" "$out/work" --frames "$frames" --masks "$masks" "$@"
