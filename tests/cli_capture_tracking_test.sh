#!/usr/bin/env bash
# The `fvv` commands that track a synthetic capture: `fvv track` (its report,
# poses.json, --smooth, --track-cameras on a dome), `fvv encode` tracking on a
# chosen few cameras, and `fvv capture calibrate-colour`. They run in the
# optimised build (tools/test.sh): the tracking and the colour calibration
# run under the sanitizers in their own suites, and tracking here cost three
# minutes there. The rest of `fvv capture` is tests/cli_capture_test.sh.
set -u
fvv=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

out=$("$fvv" synth -o "$dir/cap" --cameras 2 --width 96 --height 72 --frames 3 --held-out 1 2>&1) ||
  fail "synth: $out"

# fvv track: runs end to end on the capture, writes poses and reports errors against the truth
# (the generic proportions: fitting the build at 96x72 only costs time here).
out=$("$fvv" track "$dir/cap" -o "$dir/poses.json" --truth "$dir/cap" --fixed-shape -q 2>&1) || fail "track: $out"
grep -q "tracked frames 0..2" <<<"$out" && grep -q "joint error against" <<<"$out" || fail "track report: $out"
# ... and the error of each of the three frames, with the best and worst named.
grep -Eq "^ +cm:( +[0-9]+\.[0-9]){3}$" <<<"$out" && grep -q "per frame: best frame [0-2] " <<<"$out" ||
  fail "per-frame errors: $out"
grep -q '"dof_names"' "$dir/poses.json" && [ "$(grep -c '"xor_ratio"' "$dir/poses.json")" = 3 ] &&
  [ "$(grep -c '"calibration_disagrees": false' "$dir/poses.json")" = 2 ] || fail "poses.json"
# The synthetic calibration is exact: no camera is named as disagreeing.
grep -q "calibration disagrees" <<<"$out" && fail "a camera named on an exact calibration: $out"
# --smooth 0 reports each frame's own fit (the default smooths over time);
# a sigma out of range is refused before any work.
out=$("$fvv" track "$dir/cap" -o "$dir/raw.json" --smooth 0 --fixed-shape -q 2>&1) || fail "track --smooth 0: $out"
cmp -s "$dir/raw.json" "$dir/poses.json" && fail "--smooth 0 gave the smoothed poses"
out=$("$fvv" track "$dir/cap" -o "$dir/wild.json" --smooth 17 -q 2>&1) && fail "--smooth 17 accepted"
grep -q "smooth" <<<"$out" && [ ! -e "$dir/wild.json" ] || fail "--smooth 17 message: $out"

# A dome: its cameras as asked, and tracking on a chosen few of them, named in
# the report and in poses.json; a count of 0 is refused before any work.
out=$("$fvv" synth -o "$dir/dome" --dome 6 --width 96 --height 72 --frames 2 --held-out 0 2>&1) ||
  fail "synth --dome: $out"
grep -q "cameras:  6 at 96x72" <<<"$out" || fail "dome summary: $out"
out=$("$fvv" track "$dir/dome" -o "$dir/dome.json" --track-cameras 3 --fixed-shape -q 2>&1) ||
  fail "track --track-cameras 3: $out"
grep -q "track: fitting with 3 of 6 cameras (--track-cameras): cam" <<<"$out" || fail "fit cameras: $out"
python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["cameras"]; sys.exit(len(c) != 3)' \
  "$dir/dome.json" || fail "poses.json does not name the 3 cameras: $(head -c 400 "$dir/dome.json")"
out=$("$fvv" track "$dir/dome" -o "$dir/dome0.json" --track-cameras 0 -q 2>&1) && fail "--track-cameras 0 accepted"
grep -q "track-cameras" <<<"$out" && [ ! -e "$dir/dome0.json" ] || fail "--track-cameras 0 message: $out"
out=$("$fvv" synth -o "$dir/dome3" --dome 3 2>&1) && fail "--dome 3 accepted"
# fvv encode tracks on the same chosen few and textures every camera: the
# stream is the one encoded from fvv track's poses.
out=$("$fvv" encode "$dir/dome" -o "$dir/dome_tracked.fvv" --track-cameras 3 --fixed-shape \
  --atlas 128 2>&1) || fail "encode --track-cameras 3: $out"
grep -q "encode: tracking with 3 of 6 cameras (--track-cameras): cam" <<<"$out" ||
  fail "encode fit cameras: $out"
grep -q "2 frames (from 0) x 6 cameras" <<<"$out" || fail "encode did not texture all 6 cameras: $out"
out=$("$fvv" encode "$dir/dome" -o "$dir/dome_posed.fvv" --poses "$dir/dome.json" --atlas 128 2>&1) ||
  fail "encode --poses: $out"
[ "$(stat -c %s "$dir/dome_tracked.fvv")" -gt 0 ] && cmp -s "$dir/dome_tracked.fvv" "$dir/dome_posed.fvv" ||
  fail "tracking in fvv encode on 3 cameras differs from fvv track's poses encoded"
out=$("$fvv" encode "$dir/dome" -o "$dir/dome_bad.fvv" --track-cameras none 2>&1) &&
  fail "encode --track-cameras none accepted"
grep -q "track-cameras" <<<"$out" && [ ! -e "$dir/dome_bad.fvv" ] || fail "encode --track-cameras none: $out"

# Cameras of different colour responses: calibrate-colour finds gains that
# bring them to one colour (against the responses synth drew), writes them
# only with --write, and refuses what it cannot use.
out=$("$fvv" synth -o "$dir/colour" --cameras 6 --width 320 --height 240 --frames 4 --held-out 0 \
  --colour-mismatch 0.15 2>&1) || fail "synth --colour-mismatch: $out"
cp "$dir/colour/capture.json" "$dir/colour.before"
out=$("$fvv" capture calibrate-colour "$dir/colour" --frames 0:3 -q 2>&1) || fail "calibrate-colour: $out"
grep -q "colour gains of 6 cameras" <<<"$out" && grep -q "differ by" <<<"$out" ||
  fail "calibrate-colour report: $out"
cmp -s "$dir/colour/capture.json" "$dir/colour.before" || fail "calibrate-colour wrote without --write"
out=$("$fvv" capture calibrate-colour "$dir/colour" --frames 0:3 -q --write 2>&1) ||
  fail "calibrate-colour --write: $out"
python3 - "$dir/colour" <<'PY' || fail "calibrate-colour gains against the truth: $(cat "$dir/colour/capture.json")"
import json, sys
d = sys.argv[1]
cams = json.load(open(d + "/capture.json"))["cameras"]
truth = json.load(open(d + "/truth/truth.json"))["camera_responses"]
for k in range(3):
    common = [c["colour_gain"][k] * r[k] for c, r in zip(cams, truth)]
    assert max(common) / min(common) < 1.04, (k, common)
PY
out=$("$fvv" capture check "$dir/colour" 2>&1) || fail "a capture with colour gains does not check: $out"
grep -q "cam01 .* colour gain [0-9.]* [0-9.]* [0-9.]*" <<<"$out" || fail "check does not show the gains: $out"
out=$("$fvv" capture calibrate-colour "$dir/colour" --cameras cam00,nobody 2>&1) &&
  fail "calibrate-colour with an unknown camera succeeded"
grep -q 'no camera "nobody"' <<<"$out" || fail "unknown camera message: $out"
out=$("$fvv" capture calibrate-colour "$dir/colour" --frames 40:50 2>&1) &&
  fail "calibrate-colour beyond the take succeeded"
grep -q "the capture has 4 frames" <<<"$out" || fail "frame range message: $out"
echo "cli capture tracking: OK"
