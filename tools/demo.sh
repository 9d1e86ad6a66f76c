#!/usr/bin/env bash
# The main job on the built-in default: installs dependencies, builds, renders the
# built-in sample capture (the generic body model driven by CMU motion, 8 studio
# cameras, ground truth), shows it as a contact sheet, tracks the actor's motion
# from silhouettes and reports the joint errors; encodes the capture into a
# .fvv stream (texture atlas, multi-view resampling, 4D-SPIHT textures, masks,
# motion) and prints the encoder's summary; encodes it again in two shards side
# by side and joins them into the same bytes; inspects, decodes and renders the
# stream with Renderer II and the capture itself with Renderer I (projective
# texturing); plays it for 4 s with both cores busy, and in the web player in
# headless chromium; exports the actor as glTF
# and BVH and shows it with three.js in headless Chromium; on the real capture in ../shared/data (where present) imports the
# studio calibration, brings the cameras in step, and tracks, encodes and renders
# one camera held out; prints figures and outputs.
# Usage: tools/demo.sh [output dir, default out/demo]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/demo}
./tools/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target fvv shape_bench real_bench
fvv=build/tools/fvv/fvv
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
$fvv track "$out/capture" -o "$out/poses.json" --truth "$out/capture" --overlays "$out/track_overlays" -q |
  tee "$out/track.txt"
echo "== encode: atlas, resampling of every camera into it, 4D-SPIHT textures (8-frame GOPs per camera), motion (no masks: players take visibility from the geometry)"
$fvv encode "$out/capture" -o "$out/capture.fvv" --poses "$out/poses.json" \
  --save-textures "$out/textures" --summary-json "$out/encode_summary.json" -q
$fvv info "$out/capture.fvv"
echo "== the same take in shards (docs/scale-out.md): prepare once, 2 shards side by side (GNU parallel), join"
$fvv encode "$out/capture" --poses "$out/poses.json" --prepare "$out/prepared" -q
FVV=$fvv tools/scale-out/parallel_shards.sh 2 2/: "$out/capture" "$out/poses.json" "$out/prepared" \
  "$out/shards" "$out/capture_joined.fvv" >/dev/null
$fvv encode "$out/capture" --poses "$out/poses.json" --prepared "$out/prepared" -q \
  -o "$out/capture_prepared.fvv" >/dev/null
if cmp -s "$out/capture_joined.fvv" "$out/capture_prepared.fvv"; then
  echo "  joined shards == one encode with the same prepared take: $(stat -c %s "$out/capture_joined.fvv") bytes, identical"
else
  echo "  joined shards differ from one encode" >&2
  exit 1
fi
echo "== shards that track their own frames: the actor's shape once, then 2 shards each tracking its frames and 8 more on each side"
$fvv encode "$out/capture" --prepare "$out/prepared_tracking" -q >/dev/null
# A shard whose first-frame search loses the actor disagrees with the part
# before it at their border: the join names it, and the script's join step
# encodes it again going on from that part's poses (--after).
FVV=$fvv tools/scale-out/parallel_shards.sh 2 2/: "$out/capture" - "$out/prepared_tracking" \
  "$out/tracked_shards" "$out/capture_tracked_shards.fvv" >/dev/null 2>"$out/tracked_join.txt"
after=()
if grep -q "join_parts: shard 1" "$out/tracked_join.txt"; then
  echo "  fvv join refused the parts: $(grep -o 'the [a-z_]* joint is [0-9.]* cm apart' "$out/tracked_join.txt" | head -1) at their border"
  echo "  shard 1 encoded again, going on from part 0's poses (--after), and joined"
  after=(--after "$out/tracked_shards/part_0.fvv")
fi
shard=$($fvv track "$out/capture" --prepared "$out/prepared_tracking" --shard 1/2 "${after[@]}" \
  --truth "$out/capture" -q -o "$out/poses_shard_1.json" | grep -E "tracked frames|warm-up|joint error" |
  sed 's/ (17 joints.*//')
echo "$shard"
range=$(grep -o 'tracked frames [0-9]*\.\.[0-9]*' <<<"$shard" | grep -o '[0-9]*\.\.[0-9]*')
echo "  one tracking pass over the take, the same frames: mean $(grep -E '^ +cm:' "$out/track.txt" |
  sed 's/cm://' | tr -s ' ' '\n' | grep -v '^$' |
  awk -v a="${range%..*}" -v b="${range#*..}" 'NR - 1 >= a && NR - 1 <= b { s += $1; n++ }
    END { printf "%.2f", s / n }') cm"
echo "== decode it with the decoder library, in full and at 20000 bytes per GOP"
$fvv decode "$out/capture.fvv" -o "$out/decoded" --frames 0:7
$fvv decode "$out/capture.fvv" -o "$out/decoded_cut" --frames 0:7 --bytes 20000
echo "== one atlas frame as a still image (fvv block encode) at 0.5 bpp: SPIHT coder 3, then coder 4 (quadtrees per subband)"
for coder in arith3 arith4; do
  line=$($fvv block encode "$out/textures/cam02/texture_000000.png" \
    --mask "$out/textures/cam02/mask_000000.png" --coder $coder --bpp 0.5 \
    -o "$out/still_$coder.fvb" 2>/dev/null | tail -1)
  echo "  $coder: $line"
done
echo "== the second texture codec: 8 frames of the same textures, predictive (T00, R0, R with shape-adaptive BISK)"
$fvv encode "$out/capture" -o "$out/capture_predictive.fvv" --textures "$out/textures" --frames 0:7 \
  --texture-codec predictive -q
$fvv render "$out/capture_predictive.fvv" -o "$out/render_predictive" --size 640x480 --camera 2 \
  --first 7 --last 7
echo "== render it headless with Renderer II: an orbit, capture camera 2's view, 12 novel views"
$fvv render "$out/capture.fvv" -o "$out/render_orbit" --size 640x480
$fvv render "$out/capture.fvv" -o "$out/render_camera2" --size 640x480 --camera 2 --last 7
$fvv render "$out/capture.fvv" -o "$out/render_orbit" --size 320x240 --first 30 --contact-sheet 12
echo "== interchange: the actor as glTF 2.0 and BVH (fvv export), checked by the Khronos validator, drawn by three.js in headless Chromium"
mkdir -p "$out/export"
$fvv export "$out/capture.fvv" -o "$out/export/actor.glb"
$fvv export "$out/capture.fvv" -o "$out/export/motion.bvh"
node tools/web/validate_gltf.mjs "$out/export/actor.glb"
node tools/web/screenshot_gltf.mjs "$out/export/actor.glb" "$out/export/three.png" --frame 20 \
  --size 640x480 --eye 0.5,1.2,3.2 --target 0,0.95,0 | grep -v "^page: "
echo "== the real-time player, 4 s in a virtual display while stress-ng keeps both cores busy (docs/player.md)"
stress-ng --cpu 2 --timeout 8s --quiet &
load=$!
xvfb-run -a -s "-screen 0 1280x720x24" $fvv play "$out/capture.fvv" --seconds 4 \
  --screenshot "$out/play_loaded.png" | tail -1 || { kill "$load"; exit 1; }
kill "$load" 2>/dev/null || true
wait "$load" 2>/dev/null || true
echo "== the web player: the decoder in WebAssembly, Renderer II in WebGL 2, the stream by HTTP ranges (docs/web.md)"
emcmake cmake -S player/web -B build-wasm -G Ninja >/dev/null
cmake --build build-wasm -j2 | tail -1
node tools/web/screenshot_player.mjs build-wasm/site "$out/capture.fvv" "$out/web_player.png" 6
echo "== Renderer I: the capture itself, projectively textured from its camera images with the tracked poses"
$fvv render "$out/capture" --renderer projective --poses "$out/poses.json" -o "$out/render_projective" \
  --size 320x240 --first 30 --contact-sheet 12
$fvv render "$out/capture" --renderer projective --poses "$out/poses.json" -o "$out/render_projective" \
  --cameras-from "$out/capture/truth/heldout" --camera 0 --first 30 --last 33
$fvv render "$out/capture.fvv" -o "$out/render_heldout" --cameras-from "$out/capture/truth/heldout" \
  --camera 0 --first 30 --last 33
echo "== a studio dome: 24 cameras around the actor, close-ups and a bystander, no plates (fvv synth --dome),"
echo "   tracked on person masks from the 10 cameras the fit chooses (fvv track --track-cameras), against the truth"
$fvv synth -o "$out/dome" --dome 24 --width 640 --height 360 --frames 4 --held-out 0 --bystander \
  --no-plates
$fvv track "$out/dome" -o "$out/dome_poses.json" --truth "$out/dome" -q
echo "   encoded from all 24 cameras with those poses, and drawn from 6 viewpoints around the actor"
echo "   (the player blends and decodes at most the 8 cameras closest to a view)"
$fvv encode "$out/dome" -o "$out/dome.fvv" --poses "$out/dome_poses.json" -q
$fvv render "$out/dome.fvv" --size 320x240 --contact-sheet 6 -o "$out/dome_views"
echo "== shape refinement: generic model, visual hull and refined model against a bumpy actor's true surface"
build/bench/shape_bench --out "$out/shape"
echo "== the surface of every frame: an actor in loose shorts (fvv synth --garment), 8 cameras 45 degrees"
echo "   apart at 640x480, a rig that suits stereo; encoded with --surface from the true poses (the"
echo "   summary says what the rig chose), the held-out camera's view drawn with Renderer II"
$fvv synth -o "$out/garment" --garment 0.08 --cameras 8 --width 640 --height 480 --frames 4 --held-out 1 \
  >/dev/null
$fvv encode "$out/garment" -o "$out/garment.fvv" --poses "$out/garment" --surface | grep -E "^  surface "
$fvv render "$out/garment.fvv" -o "$out/garment_heldout" --cameras-from "$out/garment/truth/heldout" \
  --camera 0 | tail -1
real=../shared/data/real/pose2sim_single
if [ -d "$real" ]; then
  echo "== a real capture (Pose2Sim's demo: Qualisys calibration, 4 portrait videos at 60 fps): import and look"
  mkdir -p "$out/real"
  $fvv capture import-calib "$real/calibration/Calib.qca.txt" -o "$out/real" \
    --video "$(cd "$real/videos" && pwd)/{camera}.mp4"
  $fvv capture check "$out/real"
  $fvv capture sheet "$out/real" --frame 50 -o "$out/real_sheet.png"
  # The person the pretrained network sees in each camera (masks and keypoints),
  # where this build has OpenCV's dnn module and tools/setup.sh fetched the models.
  if $fvv capture sheet "$out/real" --frame 50 --persons -o "$out/real_persons.png"; then
    echo "== the real capture's frame offsets from the keypoints (fvv capture sync), checked again by the"
    echo "   tangents of the actor's masks, frames 32-93 (sync --from tangents: they run in step)"
    $fvv capture sync "$out/real" --write
    $fvv capture sync "$out/real" --from tangents --frames 32:93 --write
    echo "== tracked with all four cameras, frames 30-59: a camera whose network named left and right"
    echo "   the other way round is put right, and a camera whose calibration disagrees is named"
    $fvv track "$out/real" --frames 30:59 -o "$out/real_poses.json" -q
    echo "== its calibration disagrees by a constant shift per camera (docs/capture-format.md): the"
    echo "   cameras turned until the tangents of the actor's masks agree, frames 30-94 (refine-calib"
    echo "   --from tangents)"
    $fvv capture refine-calib "$out/real" --from tangents --frames 30:94 --write
    echo "== its cameras disagree on colour too (exposure, white balance): each camera's gain from the"
    echo "   actor's surface as two cameras see it, frames 30-59 (calibrate-colour)"
    $fvv capture calibrate-colour "$out/real" --frames 30:59 --write -q
    echo "== camera cam02 held out: tracked from the other three on person masks and keypoints, encoded,"
    echo "   and its view rendered with Renderer II (the stream with the surface of every frame)"
    echo "   and Renderer I against the real frames"
    build/bench/real_bench "$out/real" --frames 0:11 --render-frames 4 --held-out cam02 \
      --out "$out/real_heldout" --surface
  else
    echo "  (no person models: fvv falls back to background subtraction; tracking the real take is skipped)"
  fi
else
  echo "== (no real capture at $real: skipping its step)"
fi
echo "== conformance: the suite's streams through the reference decoder (conformance/README.md)"
$fvv conform conformance/cases -q
echo
echo "outputs: $out/capture (capture.json, camNN/ frames, background/ plates, truth/ poses,"
echo "         joints, silhouettes, texture, held-out views), $out/capture_sheet.png,"
echo "         $out/poses.json (tracked poses, fit quality), $out/track_overlays (fit drawn over frames),"
echo "         $out/capture.fvv (the stream; fvv info $out/capture.fvv --json),"
echo "         $out/textures (atlas textures and masks before coding, per camera),"
echo "         $out/prepared, $out/shards and $out/capture_joined.fvv (the take in two shards, joined),"
echo "         $out/encode_summary.json, $out/decoded and $out/decoded_cut (tex_/mask_fFFFFF_cCC.png,"
echo "         poses.json), $out/render_orbit and $out/render_camera2 (render_fFFFFF.png),"
echo "         $out/render_orbit/contact_sheet.png (12 novel views of frame 30),"
echo "         $out/export (actor.glb for Blender, three.js, Unity; motion.bvh; three.png: three.js's view),"
echo "         $out/play_loaded.png (fvv play's last frame and HUD with both cores busy),"
echo "         $out/web_player.png (the web player's page in headless chromium, HUD included),"
echo "         $out/render_projective (Renderer I: contact sheet, held-out camera 0's view of frames 30-33;"
echo "         $out/render_heldout is Renderer II's, $out/capture/truth/heldout/held00 the truth),"
echo "         $out/shape/capture (the bumpy actor's synthetic capture the shape table measured),"
echo "         $out/dome, $out/dome_poses.json and $out/dome.fvv (a 24-camera dome, tracked on 10 of its"
echo "         cameras, encoded from all 24; $out/dome_views: 6 views of its first frame),"
echo "         $out/capture_predictive.fvv and $out/render_predictive (the predictive texture codec),"
echo "         $out/real (the real capture's capture.json, in step and its cameras turned by the tangents"
echo "         and their colour gains),"
echo "         $out/real_sheet.png and"
echo "         $out/real_persons.png (the network's person masks and keypoints),"
echo "         $out/real_poses.json (all four cameras tracked, frames 30-59: camera_shifts, side_exchanges),"
echo "         $out/real_heldout (camera cam02 held out: poses, stream, renders, contact_sheet.png,"
echo "         real_bench.json),"
echo "         $out/still_arith3.fvb and $out/still_arith4.fvb (one atlas frame, coders 3 and 4)"
echo
echo "the web player on this stream, in your browser: tools/web/serve.sh $out/capture.fvv"
echo "  then open http://127.0.0.1:8080/index.html?stream=streams/capture.fvv (docs/web.md)"
