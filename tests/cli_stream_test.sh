#!/usr/bin/env bash
# End-to-end test of `fvv sample` and `fvv info`: outputs, exit codes and the
# messages a user sees for damaged, truncated and foreign files.
set -u
fvv=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$fvv" sample -o "$dir/s.fvv" --frames 10 --cameras 3 --atlas 32 16 --gop 4 2 >/dev/null || fail "sample"
out=$("$fvv" info "$dir/s.fvv" 2>&1) || fail "info on a good file: $out"
grep -q "10 frames at 25.000 fps" <<<"$out" || fail "info header line: $out"
grep -q "index: front" <<<"$out" || fail "fast-start index not reported: $out"
[ "$(grep -c ' ok$' <<<"$out")" = 6 ] || fail "expected 6 good fragments: $out"
json=$("$fvv" info "$dir/s.fvv" --json) || fail "info --json"
grep -q '"damaged_fragments": 0' <<<"$json" || fail "json: $json"

"$fvv" sample -o "$dir/e.fvv" --frames 5 --cameras 1 --atlas 16 16 --end-index >/dev/null || fail "sample --end-index"
out=$("$fvv" info "$dir/e.fvv" 2>&1) || fail "info on end-index file: $out"
grep -q "index: end" <<<"$out" || fail "end index not reported: $out"

# fvv decode: every frame and camera as PNG, masks, poses, a one-line report.
out=$("$fvv" decode "$dir/s.fvv" -o "$dir/dec" 2>&1) || fail "decode: $out"
grep -q "decoded frames 0..9 (3 GOPs, 3 cameras, 32x16)" <<<"$out" || fail "decode report: $out"
grep -q "complete" <<<"$out" || fail "full decode not complete: $out"
[ "$(ls "$dir"/dec/tex_*.png | wc -l)" = 30 ] || fail "decode wrote $(ls "$dir"/dec | wc -l) files"
[ "$(ls "$dir"/dec/mask_*.png | wc -l)" = 30 ] || fail "masks missing"
grep -q '"bone_world"' "$dir/dec/poses.json" || fail "poses.json"
out=$("$fvv" decode "$dir/s.fvv" -o "$dir/cut" --bytes 100 --frames 4:5 2>&1) || fail "cut decode: $out"
grep -q "decoded frames 4..5 (1 GOPs" <<<"$out" && grep -q "truncated" <<<"$out" || fail "cut report: $out"
out=$("$fvv" decode "$dir/s.fvv" -o "$dir/bad" --frames 7:99 2>&1) && fail "frames beyond the end accepted"
grep -q "not a range" <<<"$out" || fail "range message: $out"

# fvv render: headless Renderer II, an orbit and a capture camera's view.
out=$("$fvv" render "$dir/s.fvv" -o "$dir/render" --size 96x64 --last 3 2>&1) || fail "render: $out"
grep -q "rendered frames 0..3 at 96x64 (orbit)" <<<"$out" || fail "render report: $out"
[ "$(ls "$dir"/render/render_*.png | wc -l)" = 4 ] || fail "render wrote $(ls "$dir"/render | wc -l) files"
out=$("$fvv" render "$dir/s.fvv" -o "$dir/render_cam" --size 96x64 --camera 1 --first 2 --last 2 2>&1) ||
  fail "render --camera: $out"
out=$("$fvv" render "$dir/s.fvv" -o "$dir/sheet" --size 40x30 --first 3 --contact-sheet 5 2>&1) ||
  fail "contact sheet: $out"
[ -s "$dir/sheet/contact_sheet.png" ] || fail "no contact sheet"
out=$("$fvv" render "$dir/s.fvv" -o "$dir/render_bad" --camera 9 2>&1) && fail "render: camera 9 accepted"
grep -q "the stream has 3 cameras" <<<"$out" || fail "camera message: $out"
# A JSON camera path, rendered to PNGs and an MP4 (ffmpeg).
cat >"$dir/path.json" <<'JSON'
{"keyframes": [{"frame": 0, "eye": [3, 1.6, 3], "target": "actor", "fov": 40},
               {"frame": 3, "eye": [-1, 1.0, 2.5], "target": [0, 1, 0], "fov": 25}]}
JSON
out=$("$fvv" render "$dir/s.fvv" -o "$dir/render_path" --video "$dir/path.mp4" --size 96x64 --last 3 \
  --path "$dir/path.json" 2>&1) || fail "render --path --video: $out"
grep -q "(path .*path.json)" <<<"$out" || fail "path report: $out"
[ "$(ls "$dir"/render_path/render_*.png | wc -l)" = 4 ] || fail "path render wrote the wrong files"
[ "$(ffprobe -v error -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$dir/path.mp4")" = 4 ] ||
  fail "path.mp4 does not hold 4 frames"
cmp -s "$dir/render_path/render_f00000.png" "$dir/render_path/render_f00003.png" &&
  fail "the path's first and last views are the same image"
echo '{"keyframes": [{"frame": 2, "eye": [1, 2]}]}' >"$dir/bad_path.json"
out=$("$fvv" render "$dir/s.fvv" -o "$dir/render_bad" --path "$dir/bad_path.json" 2>&1) &&
  fail "bad path accepted"
grep -q "keyframes\[0\].eye" <<<"$out" || fail "bad path message: $out"
out=$("$fvv" render "$dir/s.fvv" --video "$dir/odd.mp4" --size 95x64 2>&1) && fail "odd video size accepted"
grep -q "even width" <<<"$out" && [ ! -e "$dir/odd.mp4" ] || fail "odd video size: $out"

# fvv play: the GLFW player, in a virtual X display when one can be had.
if command -v xvfb-run >/dev/null; then
  # The GLX driver GLFW dlopens keeps allocations LeakSanitizer cannot attribute
  # (its module is gone at exit); leak checking of our GL code runs in renderer_test.
  out=$(ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
        xvfb-run -a -s "-screen 0 640x480x24" "$fvv" play "$dir/s.fvv" --width 320 --height 240 \
        --seconds 1.5 --screenshot "$dir/play.png" 2>&1) || fail "play: $out"
  grep -q "played 1.[5-9] s" <<<"$out" || fail "play summary: $out"
  grep -q " 0 frames without texture" <<<"$out" || fail "play showed untextured frames: $out"
  [ "$(ffprobe -v error -show_entries stream=width,height -of csv=p=0 "$dir/play.png")" = "320,240" ] ||
    fail "play --screenshot did not save the 320x240 window"
else
  echo "skip: fvv play (xvfb-run not installed; tools/setup.sh installs it)"
fi
out=$(DISPLAY= WAYLAND_DISPLAY= "$fvv" play "$dir/s.fvv" 2>&1) && fail "play without a display succeeded"
grep -q "needs a display" <<<"$out" || fail "play without display: $out"
out=$("$fvv" play "$dir/s.fvv" --floor 1.5 2>&1) && fail "play --floor 1.5 accepted"
grep -q -- "--floor" <<<"$out" || fail "play --floor 1.5: $out"

# A damaged byte inside the last fragment: an error naming the fragment (decode exits 6).
cp "$dir/s.fvv" "$dir/bad.fvv"
size=$(stat -c %s "$dir/bad.fvv")
printf '\x55' | dd of="$dir/bad.fvv" bs=1 seek=$((size - 40)) conv=notrunc status=none
out=$("$fvv" info "$dir/bad.fvv" 2>&1) && fail "damaged file accepted: $out"
grep -q "checksum mismatch" <<<"$out" || fail "no checksum message: $out"
out=$("$fvv" decode "$dir/bad.fvv" -o "$dir/bad_dec" 2>&1)
[ $? = 6 ] || fail "decode of a damaged file: exit status is not 6 (checksum mismatch): $out"
grep -q "checksum mismatch" <<<"$out" || fail "decode: no checksum message: $out"

# Truncated: the header's index points past the end.
head -c $((size / 2)) "$dir/s.fvv" >"$dir/cut.fvv"
out=$("$fvv" info "$dir/cut.fvv" 2>&1) && fail "truncated file accepted: $out"
grep -qE "truncated|corrupt" <<<"$out" || fail "truncation message: $out"

# Not an fvv file at all, and a missing file.
echo "hello, this is not a stream" >"$dir/text.fvv"
out=$("$fvv" info "$dir/text.fvv" 2>&1) && fail "text file accepted"
grep -q "not an fvv" <<<"$out" || fail "foreign file message: $out"
"$fvv" info "$dir/missing.fvv" >/dev/null 2>&1 && fail "missing file accepted"

# Out-of-level request: a clear error, and no file left behind.
out=$("$fvv" sample -o "$dir/big.fvv" --cameras 20 2>&1) && fail "level 1 with 20 cameras accepted"
grep -q "level 1 allows 8" <<<"$out" || fail "level message: $out"
[ ! -e "$dir/big.fvv" ] || fail "a file was left behind"
ls "$dir" | grep -q part && fail "temporary file left behind"
echo "cli stream test passed"
