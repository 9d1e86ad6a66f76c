#!/usr/bin/env bash
# The main job on the built-in default: installs dependencies, builds, renders the
# built-in sample capture (the generic body model driven by CMU motion, 8 studio
# cameras, ground truth), shows it as a contact sheet, tracks the actor's motion
# from silhouettes and reports the joint errors; makes the built-in
# multi-view test volume (8 frames x 8 cameras, 256x256), codes it as one 4D
# block at several rates, decodes, then writes a complete .fvv stream (model,
# cameras, motion, masks, textures) and inspects it; prints figures and outputs.
# Usage: tools/demo.sh [output dir, default out/demo]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/demo}
./tools/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target fvv
fvv=build/encoder/cli/fvv
rm -rf "$out" && mkdir -p "$out"
echo "== the sample capture: 8 cameras at 640x480, 50 frames, with ground truth"
motion=()
bvh=/usr/share/assimp/models/BVH/01_01.bvh  # CMU subject 1, trial 1 (assimp-testmodels)
[ -f "$bvh" ] && motion=(--motion "$bvh")
$fvv synth -o "$out/capture" --frames 50 "${motion[@]}"
$fvv capture check "$out/capture"
$fvv capture sheet "$out/capture" --frame 30 -o "$out/capture_sheet.png"
echo "== marker-free motion capture: silhouettes, initialisation, tracking; errors against the truth"
mkdir -p "$out/track_overlays"
$fvv track "$out/capture" -o "$out/poses.json" --truth "$out/capture" --overlays "$out/track_overlays" -q
echo "== sample capture volume"
$fvv block sample -o "$out/views" --frames 8 --cameras 8 --width 256 --height 256
for bpp in 0.05 0.1 0.25 0.5; do
  echo "== 4D-SPIHT at $bpp bpp (9/7, arithmetic coding, masks)"
  $fvv block encode "$out"/views/view_*.png --cameras 8 --mask "$out"/views/mask_*.png \
    --bpp $bpp -o "$out/block_$bpp.fvb" 2>/dev/null
done
echo "== decode 0.25 bpp in full and cut to 20% of its bytes"
$fvv block decode "$out/block_0.25.fvb" -o "$out/decoded_full"
bytes=$(( $(stat -c %s "$out/block_0.25.fvb") / 5 ))
$fvv block decode "$out/block_0.25.fvb" -o "$out/decoded_cut" --bytes $bytes
echo "== lossless (5/3, reversible colour)"
$fvv block encode "$out"/views/view_*.png --cameras 8 --lossless -o "$out/block_lossless.fvb" 2>/dev/null
echo "== a complete .fvv stream: 40 frames x 8 cameras, 256x256 atlas, 8x8 GOPs"
$fvv sample -o "$out/sample.fvv" --frames 40 --cameras 8 --atlas 256 256 --bpp 0.1
$fvv info "$out/sample.fvv"
echo "== decode it with the decoder library, in full and at 4000 bytes per GOP"
$fvv decode "$out/sample.fvv" -o "$out/sample_decoded" --frames 0:7
$fvv decode "$out/sample.fvv" -o "$out/sample_cut" --frames 0:7 --bytes 4000
echo "== render it headless with Renderer II: an orbit, and capture camera 2's view"
$fvv render "$out/sample.fvv" -o "$out/render_orbit" --size 640x480
$fvv render "$out/sample.fvv" -o "$out/render_camera2" --size 640x480 --camera 2 --last 7
$fvv render "$out/sample.fvv" -o "$out/render_orbit" --size 320x240 --first 10 --contact-sheet 12
echo
echo "outputs: $out/capture (capture.json, camNN/ frames, background/ plates, truth/ poses,"
echo "         joints, silhouettes, texture, held-out views), $out/capture_sheet.png,"
echo "         $out/poses.json (tracked poses, fit quality), $out/track_overlays (fit drawn over frames),"
echo "         $out/views (input views + masks), $out/block_*.fvb (coded blocks),"
echo "         $out/decoded_full and $out/decoded_cut (decoded views, view_tTTT_cCC.png),"
echo "         $out/sample.fvv (a stream; fvv info $out/sample.fvv --json),"
echo "         $out/sample_decoded and $out/sample_cut (tex_/mask_fFFFFF_cCC.png, poses.json),"
echo "         $out/render_orbit and $out/render_camera2 (render_fFFFFF.png),"
echo "         $out/render_orbit/contact_sheet.png (12 novel views of frame 10)"
