#!/usr/bin/env bash
# Where the held-out view's decibels go (issue 43): a synthetic capture with 2
# held-out cameras and true poses, drawn from the held-out cameras by
# Renderer I (straight from the camera images) and by Renderer II from streams
# that differ in one step at a time: the atlas (512 or 1024 texels) and the
# coding (near-lossless at 60 dB, the default 36 dB target, 20:1 and 120:1).
# PSNR (RGB) over the truth's actor silhouette against the held-out truth
# images, every frame of the range, both held-out cameras.
# Usage: bench/run_heldout_gap_bench.sh [frames, default 8] [camera size WxH, default 640x480]
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-8}
size=${2:-640x480}
if ! [[ $size =~ ^([0-9]+)x([0-9]+)$ ]]; then
  echo "camera size: WxH (e.g. 320x240), not '$size'" >&2
  exit 2
fi
width=${BASH_REMATCH[1]} height=${BASH_REMATCH[2]}
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target fvv >/dev/null
fvv=$PWD/build/tools/fvv/fvv
work=${FVV_BENCH_DIR:-out/heldout_gap_bench}
rm -rf "$work" && mkdir -p "$work"
last=$((frames - 1))
"$fvv" synth -o "$work/cap" --frames "$frames" --cameras 8 --held-out 2 --width "$width" --height "$height" \
  --motion /usr/share/assimp/models/BVH/01_01.bvh >/dev/null 2>&1
held=$work/cap/truth/heldout

# PSNR of DIR/render_fNNNNN.png against the held-out truth of camera K.
score() { bench/heldout_score.py "$1" "$held" "$2" "$last" | cut -d' ' -f1; }

row() {  # name, then a render command's arguments before --cameras-from
  local name=$1
  shift
  local line=""
  for k in 0 1; do
    "$fvv" render "$@" --cameras-from "$held" --camera $k --first 0 --last $last \
      -o "$work/r_$k" >/dev/null 2>&1
    line="$line $(score "$work/r_$k" $k)"
    rm -rf "$work/r_$k"
  done
  printf "%-44s %s\n" "$name" "$line"
}

echo "held-out views of a synthetic capture ($frames frames, 8 cameras at $size, true poses):"
echo "RGB PSNR (dB) over the actor, held-out camera 0 and 1"
row "Renderer I (the camera images)" "$work/cap" --renderer projective --poses "$work/cap"
for atlas in 512 1024; do
  for rate in "--psnr 60" "--psnr 36" "--bpp 1.2" "--bpp 0.2"; do
    s="$work/s_${atlas}_${rate// /}.fvv"
    "$fvv" encode "$work/cap" --poses "$work/cap" --atlas $atlas $rate -q -o "$s" >/dev/null 2>&1
    bytes=$(stat -c %s "$s")
    row "Renderer II, atlas $atlas, $rate ($((bytes / 1024)) KiB)" "$s"
  done
done
