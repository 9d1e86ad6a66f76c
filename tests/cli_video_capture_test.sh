#!/usr/bin/env bash
# Every fvv command that reads a capture, on a capture whose cameras are video
# files: with a frame range that stops before the videos end, with errors (a
# video shorter than the capture says, a missing one) and under SIGTERM. Each
# run is under a timeout; the test checks the exit status, the outputs (written
# whole, or not at all), and that no ffmpeg child outlives its fvv.
set -u
fvv=$1
dir=$2
data=${3:-}  # third-party test data (../shared/data); the real-capture part skips without it
rm -rf "$dir" && mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v ffmpeg >/dev/null || { echo "SKIP: ffmpeg not installed (tools/setup.sh installs it)"; exit 0; }

# Children of any fvv of this test: ffmpeg processes that carry this test's
# mark in their environment (fvv passes its environment on). The mark, not the
# videos' paths, tells them apart from another program's decoders of the same
# videos (the real capture's, in a bench running beside the tests).
export FVV_TEST_MARK="$dir"
leftover() {
  local p
  for p in $(pgrep -x ffmpeg); do
    tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qxF "FVV_TEST_MARK=$dir" && echo "$p"
  done
  return 0
}
no_children() {
  local left
  left=$(leftover)
  [ -z "$left" ] || { ps -o pid,args -p "$(echo $left | tr " " ,)" >&2; fail "$1: ffmpeg children left behind"; }
}
# Runs fvv under a timeout; a hang is a failure of its own.
run() {
  timeout 120 "$fvv" "$@"
  local rc=$?
  [ $rc -ne 124 ] || fail "fvv $* hung (killed after 120 s)"
  return $rc
}

"$fvv" synth -o "$dir/cap" --cameras 3 --width 160 --height 120 --frames 12 --held-out 0 \
  >/dev/null 2>&1 || fail "synth"
for c in cam00 cam01 cam02; do
  ffmpeg -v error -y -framerate 25 -i "$dir/cap/$c/%06d.png" -c:v libx264 -qp 0 \
    -pix_fmt yuv444p "$dir/cap/$c.mp4" || fail "ffmpeg encode $c"
done
python3 - "$dir/cap/capture.json" <<'EOF' || fail "capture.json for videos"
import json, sys
path = sys.argv[1]
c = json.load(open(path))
for cam in c["cameras"]:
    cam["frames"] = {"video": cam["name"] + ".mp4"}
json.dump(c, open(path, "w"), indent=1)
EOF

# Early stops: each command reads a few frames of 12 and must exit, with its output.
out=$(run capture check "$dir/cap" 2>&1) || fail "check: $out"
no_children "capture check"
out=$(run capture sheet "$dir/cap" --frame 2 -o "$dir/sheet.png" 2>&1) || fail "sheet: $out"
[ -s "$dir/sheet.png" ] || fail "sheet: no contact sheet"
no_children "capture sheet"
out=$(run capture hull "$dir/cap" --frame 3 -o "$dir/hull.ply" --voxel 0.03 2>&1) || fail "hull: $out"
head -1 "$dir/hull.ply" | grep -q "^ply" || fail "hull: no point cloud"
no_children "capture hull"
out=$(run track "$dir/cap" --frames 0:1 -o "$dir/poses.json" --fixed-shape -q 2>&1) || fail "track: $out"
grep -q '"frames"' "$dir/poses.json" || fail "track: no poses.json"
no_children "track"
out=$(run encode "$dir/cap" --frames 0:1 --poses "$dir/poses.json" --atlas 128 -o "$dir/part.fvv" \
  -q 2>&1) || fail "encode: $out"
"$fvv" info "$dir/part.fvv" >/dev/null || fail "encode: unreadable stream"
no_children "encode"
out=$(run render "$dir/cap" --renderer projective --poses "$dir/poses.json" --first 0 --last 1 \
  --size 160x120 -o "$dir/render" --video "$dir/render.mp4" 2>&1) || fail "render: $out"
[ -s "$dir/render.mp4" ] && [ -f "$dir/render/render_f00001.png" ] || fail "render: outputs missing"
no_children "render"

# The commands that read the person network's keypoints over a span stop
# early too. Without the models, or on frames this small, they may find too
# little to go on: then a clear error. Either way capture.json stays as it was:
# the synthetic calibration is true, so refine-calib finds nothing to write.
cp "$dir/cap/capture.json" "$dir/capture.json.before"
for cmd in "sync --max-offset 2" "refine-calib --write" "refine-calib --from tangents --write"; do
  out=$(run capture $cmd "$dir/cap" --frames 0:5 2>&1)
  rc=$?
  if [ $rc -ne 0 ]; then
    grep -Eq "person network|needs 20|too few" <<<"$out" || fail "capture $cmd: unclear error: $out"
  elif [ "${cmd#refine-calib}" != "$cmd" ]; then
    grep -q "left unchanged" <<<"$out" || fail "$cmd rewrote a true calibration: $out"
  fi
  cmp -s "$dir/cap/capture.json" "$dir/capture.json.before" ||
    fail "capture $cmd: capture.json changed"
  no_children "capture $cmd"
done

# The tangents' sync needs frames either side of its span: a span with too few
# is a clear error; one at the capture's start is narrowed, and cameras in step
# stay so.
out=$(run capture sync "$dir/cap" --from tangents --frames 0:3 --max-offset 5 --write 2>&1) &&
  fail "sync --from tangents with no room for its offsets succeeded"
grep -q "5 frames either side" <<<"$out" || fail "sync --from tangents, too few frames: $out"
out=$(run capture sync "$dir/cap" --from tangents --frames 0:9 --write 2>&1)
if [ $? -ne 0 ]; then
  grep -Eq "person network|too few" <<<"$out" || fail "sync --from tangents: unclear error: $out"
else
  grep -q "run in step" <<<"$out" || fail "sync --from tangents moved cameras in step: $out"
  grep -q "frames 2..9 compared" <<<"$out" || fail "sync --from tangents: span not narrowed: $out"
fi
cmp -s "$dir/cap/capture.json" "$dir/capture.json.before" ||
  fail "sync --from tangents: capture.json changed"
no_children "capture sync --from tangents"

# A video shorter than the capture says: a clear error naming the video and the
# frame, a non-zero exit, no output, no child.
cp -r "$dir/cap" "$dir/short"
ffmpeg -v error -y -i "$dir/cap/cam01.mp4" -frames:v 6 -c:v libx264 -qp 0 -pix_fmt yuv444p \
  "$dir/short/cam01.mp4" || fail "ffmpeg cut"
out=$(run track "$dir/short" -o "$dir/short_poses.json" -q 2>&1) && fail "track of a short video succeeded"
grep -q "cam01.mp4: no frame 6" <<<"$out" || fail "short video error: $out"
[ ! -e "$dir/short_poses.json" ] || fail "track wrote poses after an error"
no_children "track (short video)"
out=$(run encode "$dir/short" --poses "$dir/cap/truth/truth.json" --frames 6:9 --atlas 128 \
  -o "$dir/short.fvv" -q 2>&1) && fail "encode of a short video succeeded"
grep -q "cam01.mp4" <<<"$out" || fail "encode short video error: $out"
[ ! -e "$dir/short.fvv" ] || fail "encode left a stream after an error"
no_children "encode (short video)"

# A missing video.
cp -r "$dir/cap" "$dir/missing" && rm "$dir/missing/cam02.mp4"
out=$(run capture sheet "$dir/missing" --frame 1 -o "$dir/missing.png" 2>&1) &&
  fail "sheet with a missing video succeeded"
grep -q "cam02.mp4" <<<"$out" || fail "missing video error: $out"
no_children "capture sheet (missing video)"

# SIGTERM while tracking: fvv ends with the signal, its decoders with it, and
# no poses.json appears.
timeout 120 "$fvv" track "$dir/cap" -o "$dir/killed.json" -q >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 100); do
  [ -n "$(leftover)" ] && break
  sleep 0.1
done
[ -n "$(leftover)" ] || fail "track started no video decoder"
sleep 0.5
kill -TERM $pid
wait $pid
rc=$?
[ $rc -eq 143 ] || fail "track under SIGTERM exited $rc, not 143"
sleep 0.2
no_children "track (SIGTERM)"
[ ! -e "$dir/killed.json" ] || fail "a poses.json after SIGTERM"

# The real capture: its Qualisys calibration and videos of two widths, imported
# with the frames' size taken and said; a contact sheet stops early there too.
real="$data/real/pose2sim_single"
if [ -n "$data" ] && [ -f "$real/calibration/Calib.qca.txt" ]; then
  mkdir -p "$dir/real"
  # No --up: the Qualisys lab frame is z up, which the cameras confirm.
  out=$(run capture import-calib "$real/calibration/Calib.qca.txt" -o "$dir/real" \
    --video "$(cd "$real/videos" && pwd)/{camera}.mp4" 2>&1) || fail "import real: $out"
  grep -q "imported 4 cameras (Qualisys) from 1 file(s)" <<<"$out" || fail "import report: $out"
  grep -q "up axis z: the Qualisys format's world is z up" <<<"$out" || fail "real up axis: $out"
  grep -q "warning: up axis" <<<"$out" && fail "the real cameras contradicted z up: $out"
  grep -q "cam01: the calibration's image is 1088x1920, its frames are 1080x1920 (-8 x +0" \
    <<<"$out" || fail "no warning about cam01's width: $out"
  grep -q "(100 frames at 60 fps)" <<<"$out" || fail "frames and rate from the videos: $out"
  out=$(run capture sheet "$dir/real" --frame 10 -o "$dir/real.png" 2>&1) || fail "real sheet: $out"
  [ -s "$dir/real.png" ] || fail "real sheet missing"
  no_children "real capture sheet"
else
  echo "SKIP (real capture part): no $real (FVV_TEST_DATA_DIR)"
fi

echo "video captures: 10 commands stop early and exit; short and missing videos fail cleanly; SIGTERM leaves no child"
