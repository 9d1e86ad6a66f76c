#!/usr/bin/env bash
# Streams with and without shape masks at equal total bytes (issue 43): a
# synthetic capture with 2 held-out cameras and true poses is encoded with
# masks at 4 rates (24 / R bits per atlas texel for R = 20, 50, 120, 280:1)
# and at the default target (36 dB over the texels seen), then without masks with the masks' bytes given to the textures instead (the
# same total); both are drawn by Renderer II from the held-out cameras. Per
# rate: each stream's bytes, the textures' RGB PSNR over the texels the
# cameras saw (the encoder's figure), and the held-out views' RGB PSNR and
# SSIM over the truth's actor silhouette, every frame of both cameras, beside
# Renderer I's from the camera images. Then
# Renderer II's cost of the depth maps at 1280x720 (render_bench).
# Usage: bench/run_mask_free_bench.sh [frames, default 8] [atlas, default 512]
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-8}
atlas=${2:-512}
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DFVV_BUILD_BENCH=ON >/dev/null
cmake --build build -j2 --target fvv render_bench >/dev/null
fvv=$PWD/build/tools/fvv/fvv
work=${FVV_BENCH_DIR:-out/mask_free_bench}
rm -rf "$work" && mkdir -p "$work"
last=$((frames - 1))
echo "synthesising $frames frames, 8 cameras at 640x480 and 2 held out ..." >&2
"$fvv" synth -o "$work/cap" --frames "$frames" --cameras 8 --held-out 2 \
  --motion /usr/share/assimp/models/BVH/01_01.bvh >/dev/null 2>&1
held=$work/cap/truth/heldout

# "PSNR SSIM" of DIR/render_fNNNNN.png against held-out camera K's truth.
score() { bench/heldout_score.py "$1" "$held" "$2" "$last"; }

# Held-out PSNR and SSIM of a render of ARGS...: "psnr0 ssim0 psnr1 ssim1".
views() {
  local line=""
  for k in 0 1; do
    "$fvv" render "$@" --cameras-from "$held" --camera $k --first 0 --last $last \
      -o "$work/r_$k" >/dev/null 2>&1
    line="$line $(score "$work/r_$k" $k)"
    rm -rf "$work/r_$k"
  done
  echo "$line"
}

field() {  # JSON file, python expression on `j`
  /usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"
}

echo "Streams with and without masks at equal total bytes: $frames frames, 8 cameras at 640x480,"
echo "atlas $atlas, true poses; held-out views by Renderer II (PSNR dB / SSIM over the actor)"
printf "%-7s %-8s %10s %8s %9s %17s %17s\n" rate masks bytes "mask %" "tex PSNR" \
  "held-out 0" "held-out 1"
read -r r0 s0 r1 s1 <<<"$(views "$work/cap" --renderer projective --poses "$work/cap")"
printf "%-7s %-8s %10s %8s %9s %8s / %6s %8s / %6s\n" "-" "Renderer I (the camera images)" "" "" "" \
  "$r0" "$s0" "$r1" "$s1"
for ratio in 20 50 120 280 default; do
  rate=(--psnr 36)  # the encoder's default target
  [ "$ratio" = default ] ||
    rate=(--bpp "$(/usr/bin/python3 -c "print(f'{24 / $ratio:.5f}')")")
  m=$work/masked_$ratio
  "$fvv" encode "$work/cap" --poses "$work/cap" --atlas "$atlas" "${rate[@]}" --masks -q \
    --summary-json "$m.json" -o "$m.fvv" >/dev/null 2>&1
  per_gop=$(field "$m.json" "(j['bytes']['texture'] + j['bytes']['masks']) // j['gops']")
  u=$work/unmasked_$ratio
  "$fvv" encode "$work/cap" --poses "$work/cap" --atlas "$atlas" --bytes "$per_gop" --no-masks \
    -q --summary-json "$u.json" -o "$u.fvv" >/dev/null 2>&1
  for s in "$m" "$u"; do
    read -r p0 s0 p1 s1 <<<"$(views "$s.fvv")"
    printf "%-7s %-8s %10s %7.1f%% %9.2f %8s / %6s %8s / %6s\n" \
      "$([ "$ratio" = default ] && echo "36 dB" || echo "$ratio:1")" \
      "$([ "$s" = "$m" ] && echo with || echo without)" "$(stat -c %s "$s.fvv")" \
      "$(field "$s.json" "100 * j['bytes']['masks'] / j['bytes']['file']")" \
      "$(field "$s.json" "j['psnr']['rgb']")" "$p0" "$s0" "$p1" "$s1"
  done
done
echo
echo "Renderer II's cost, the stream without masks at 50:1 against the one with:"
build/bench/render_bench "$work/masked_50.fvv" --size 1280x720 --views 24
build/bench/render_bench "$work/unmasked_50.fvv" --size 1280x720 --views 24
