#!/usr/bin/env bash
# Studio scale (bench/README.md): synthetic domes of 8, 16, 32 and 64 cameras
# (fvv synth --dome N, a second person walking through, no plates: silhouettes
# from the person network), each tracked with every camera and with the few
# the fit chooses (fvv track --track-cameras), both against the truth; then
# encoded from every camera with the chosen cameras' poses, and played
# (build/bench/playback_load_bench --only idle: fvv play's loop headless at
# 1280x720, the view swinging round the actor). Reports seconds per frame, the
# joint error, the encoder's peak memory and the player's frames per second
# and cameras decoded per dome, writes out/dome_bench/dome_bench_WxH.tsv and a
# plot to docs/figures/dome_bench_WxH.png.
# Usage: bench/run_dome_bench.sh [WIDTHxHEIGHT] [FRAMES] [COUNTS...]
#   default 640x360, 8 frames, domes of 8 16 32 64 cameras
# Needs a Release build in build/ and the person models (tools/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-640x360}
frames=${2:-8}
shift $(($# < 2 ? $# : 2))
counts=("$@")
[ ${#counts[@]} -gt 0 ] || counts=(8 16 32 64)
w=${size%x*} h=${size#*x}
fvv=build/tools/fvv/fvv
out=out/dome_bench
mkdir -p "$out"
tsv="$out/dome_bench_${size}.tsv"
printf 'cameras\tfit_cameras\ttrack_all_s\terror_all_cm\ttrack_chosen_s\terror_chosen_cm\tsilhouettes_chosen_s\tnetwork_chosen_s\tencode_s\tencode_peak_mb\tencode_cores\tplay_fps\n' >"$tsv"
# Seconds per frame after the first (the first frame's fit is a one-off) and
# the mean joint error, from fvv track's report.
per_frame() { grep -o 'every later frame [0-9.]* s' "$1" | grep -o '[0-9.]*' | head -1; }
joint_error() { grep -o 'joint error against [^:]*: mean [0-9.]* cm' "$1" | grep -o 'mean [0-9.]*' | grep -o '[0-9.]*'; }
for n in "${counts[@]}"; do
  cap="$out/dome${n}_${size}"
  if [ ! -f "$cap/capture.json" ]; then
    $fvv synth -o "$cap" --dome "$n" --width "$w" --height "$h" --frames "$frames" --held-out 0 \
      --no-plates --bystander >/dev/null
  fi
  $fvv track "$cap" -o "$cap/poses_all.json" --truth "$cap" --track-cameras all --persons on -q \
    >"$cap/track_all.txt" 2>&1
  $fvv track "$cap" -o "$cap/poses.json" --truth "$cap" --track-cameras auto --persons on -q \
    >"$cap/track_chosen.txt" 2>&1
  fit=$(grep -o 'fitting with [0-9]* of' "$cap/track_chosen.txt" | grep -o '[0-9]*' || echo "$n")
  sil=$(grep -o '(silhouettes [0-9.]*' "$cap/track_chosen.txt" | head -1 | grep -o '[0-9.]*$')
  net=$(grep -o 'person network [0-9.]*' "$cap/track_chosen.txt" | head -1 | grep -o '[0-9.]*$' || echo "")
  /usr/bin/time -v $fvv encode "$cap" -o "$cap/dome.fvv" --poses "$cap/poses.json" \
    >"$cap/encode.txt" 2>"$cap/encode_time.txt"
  enc_s=$(grep -o 'Elapsed (wall clock) time.*' "$cap/encode_time.txt" | awk '{print $NF}' |
    awk -F: '{ if (NF == 3) print $1 * 3600 + $2 * 60 + $3; else print $1 * 60 + $2 }')
  peak=$(grep -o 'Maximum resident set size (kbytes): [0-9]*' "$cap/encode_time.txt" | grep -o '[0-9]*$')
  cores=$(grep -o 'Percent of CPU this job got: [0-9]*' "$cap/encode_time.txt" | grep -o '[0-9]*$')
  build/bench/playback_load_bench "$cap/dome.fvv" --only idle --seconds 10 >"$cap/play.txt" 2>&1
  fps=$(awk '$1 == "idle" { print $2 }' "$cap/play.txt")
  row=$(printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%.3f\t%.0f\t%.2f\t%s' "$n" "$fit" \
    "$(per_frame "$cap/track_all.txt")" "$(joint_error "$cap/track_all.txt")" \
    "$(per_frame "$cap/track_chosen.txt")" "$(joint_error "$cap/track_chosen.txt")" \
    "${sil:-}" "${net:-}" "$(echo "$enc_s / $frames" | bc -l)" "$(echo "$peak / 1024" | bc -l)" \
    "$(echo "$cores / 100" | bc -l)" "${fps:-}")
  echo "$row" | tee -a "$tsv"
done
column -t "$tsv"
if command -v gnuplot >/dev/null; then
  mkdir -p docs/figures
  gnuplot <<EOF
set terminal pngcairo size 900,520
set output 'docs/figures/dome_bench_${size}.png'
set title 'fvv on a synthetic dome, ${size}, ${frames} frames: seconds per frame (2 cores)'
set xlabel 'cameras'
set ylabel 'seconds per frame'
set logscale x 2
set key top left
plot '$tsv' using 1:3 with linespoints title 'track, every camera', \
     '$tsv' using 1:5 with linespoints title 'track, the cameras chosen', \
     '$tsv' using 1:9 with linespoints title 'encode, every camera'
EOF
  echo "plot: docs/figures/dome_bench_${size}.png"
fi
