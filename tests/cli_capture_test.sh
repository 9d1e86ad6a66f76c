#!/usr/bin/env bash
# End-to-end test of `fvv synth` and `fvv capture`: a synthetic capture is made,
# checked, shown as a contact sheet and re-described from an imported
# calibration; bad inputs give non-zero exits with messages naming the problem.
# The commands that track it are tests/cli_capture_tracking_test.sh.
set -u
fvv=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

out=$("$fvv" synth -o "$dir/cap" --cameras 2 --width 96 --height 72 --frames 3 --held-out 1 2>&1) ||
  fail "synth: $out"
grep -q "cameras:  2 at 96x72, 1 held out" <<<"$out" || fail "synth summary: $out"
grep -q "ETA" <<<"$out" || fail "synth progress: $out"
# Real conditions set 4 portrait cameras at 360x640 unless the size or count is given.
out=$("$fvv" synth -o "$dir/real" --real-conditions --width 72 --height 96 --frames 1 2>&1) ||
  fail "synth --real-conditions: $out"
grep -q "cameras:  4 at 72x96" <<<"$out" || fail "real conditions kept the size given: $out"
out=$("$fvv" synth -o "$dir/real" --real-conditions --cameras 3 --frames 1 2>&1) ||
  fail "synth --real-conditions --cameras 3: $out"
grep -q "cameras:  3 at 360x640" <<<"$out" || fail "real conditions kept the count given: $out"
rm -rf "$dir/real"
# A capture's own cameras film the synthetic actor (--rig), 1 degree off what is recorded.
out=$("$fvv" synth -o "$dir/rig" --rig "$dir/cap" --frames 1 --calibration-error 1 2>&1) ||
  fail "synth --rig: $out"
grep -q "cameras:  2 of $dir/cap, each at its own size (the first 96x72)" <<<"$out" ||
  fail "rig summary: $out"
grep -q '"calibration_error"' "$dir/rig/truth/truth.json" || fail "the turns are not in the truth"
cmp -s <(grep -v directory "$dir/cap/capture.json" | grep -A12 '"K"' | head -12) \
  <(grep -v directory "$dir/rig/capture.json" | grep -A12 '"K"' | head -12) ||
  fail "the rig's intrinsics changed"
out=$("$fvv" synth -o "$dir/rig" --rig "$dir/cap" --cameras 3 --frames 1 2>&1) &&
  fail "--rig with --cameras accepted"
grep -q "leave out --cameras" <<<"$out" || fail "rig with cameras: $out"
out=$("$fvv" synth -o "$dir/rig" --rig-poses "$dir/none.json" --frames 1 2>&1) &&
  fail "--rig-poses without --rig accepted"
grep -q "give the rig too" <<<"$out" || fail "rig poses without a rig: $out"
rm -rf "$dir/rig"

# refine-calib --from tangents: cameras filmed half a degree off what capture.json
# records (about 3 pixels here) are turned back to within a pixel, from their
# true silhouettes alone; run again, it finds nothing left to write.
"$fvv" synth -o "$dir/turned" --cameras 4 --width 320 --height 240 --frames 10 --held-out 0 \
  --calibration-error 0.5 --with-silhouettes --no-plates >/dev/null 2>&1 || fail "synth turned"
cp "$dir/turned/capture.json" "$dir/turned/given.json"
out=$("$fvv" capture refine-calib "$dir/turned" --from tangents --frames 0:9 --write 2>&1) ||
  fail "refine-calib --from tangents: $out"
grep -q "refined from the tangents" <<<"$out" || fail "tangents summary: $out"
python3 - "$dir/turned" <<'PY' || fail "refine-calib --from tangents did not find the turns"
import json, math, sys
d = sys.argv[1]
given = json.load(open(d + "/given.json"))["cameras"]
refined = json.load(open(d + "/capture.json"))["cameras"]
turns = {t["camera"]: t["shift_px"] for t in json.load(open(d + "/truth/truth.json"))["calibration_error"]["turns"]}
def mul(a, b): return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
def tr(a): return [list(r) for r in zip(*a)]
def angle(a, b):
    m = mul(a, tr(b))
    return math.acos(max(-1.0, min(1.0, (m[0][0] + m[1][1] + m[2][2] - 1) / 2)))
for g, r in zip(given, refined):
    fx, fy = g["K"][0][0], g["K"][1][1]
    sx, sy = turns[g["name"]]
    w = [-sy / fy, sx / fx, 0.0]
    t = math.sqrt(sum(v * v for v in w))
    k = [v / t for v in w]
    K = [[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]]
    K2 = mul(K, K)
    turn = [[(i == j) + math.sin(t) * K[i][j] + (1 - math.cos(t)) * K2[i][j] for j in range(3)] for i in range(3)]
    filmed = mul(turn, g["R"])
    before, after = angle(g["R"], filmed) * fx, angle(r["R"], filmed) * fx
    print(g["name"], "%.2f -> %.2f px" % (before, after))
    assert before > 2 and after < 1, g["name"]
PY
out=$("$fvv" capture refine-calib "$dir/turned" --from tangents --frames 0:9 --write 2>&1) ||
  fail "refine-calib --from tangents again: $out"
grep -q "left unchanged" <<<"$out" || fail "a refined calibration was refined again: $out"
rm -rf "$dir/turned"
[ -f "$dir/cap/capture.json" ] && [ -f "$dir/cap/cam01/000002.png" ] && [ -f "$dir/cap/background/cam00.png" ] ||
  fail "synth outputs missing"
[ -f "$dir/cap/truth/truth.json" ] && [ -f "$dir/cap/truth/silhouettes/cam00/000000.png" ] &&
  [ -f "$dir/cap/truth/heldout/capture.json" ] || fail "ground truth missing"

out=$("$fvv" capture check "$dir/cap" 2>&1) || fail "check: $out"
grep -q "2 cameras, 3 frames at 25 fps, up axis y, background plates: OK" <<<"$out" || fail "check report: $out"
out=$("$fvv" capture sheet "$dir/cap" --frame 2 -o "$dir/sheet.png" 2>&1) || fail "sheet: $out"
[ -f "$dir/sheet.png" ] || fail "no contact sheet"
"$fvv" capture sheet "$dir/cap/truth/heldout" --silhouettes -o "$dir/sil.png" >/dev/null || fail "silhouette sheet"
# The visual hull of a frame, as a PLY point cloud; bad frame numbers are refused.
out=$("$fvv" capture hull "$dir/cap" --frame 1 -o "$dir/hull.ply" --voxel 0.02 2>&1) || fail "hull: $out"
grep -q "visual hull of frame 1 (2 cameras" <<<"$out" || fail "hull report: $out"
head -1 "$dir/hull.ply" | grep -q "^ply" && [ "$(grep -c . "$dir/hull.ply")" -gt 100 ] || fail "hull.ply"
# Poses from feature points (synth writes its joints' as truth/features.json),
# good enough to encode with; a feature file naming an unknown camera fails.
out=$("$fvv" capture register "$dir/cap" --features "$dir/cap/truth/features.json" -o "$dir/reg.json" \
  --truth "$dir/cap" 2>&1) || fail "register: $out"
grep -q "registered frames 0..2" <<<"$out" && grep -q "joint error against" <<<"$out" ||
  fail "register report: $out"
"$fvv" encode "$dir/cap" -o "$dir/reg.fvv" --poses "$dir/reg.json" --atlas 128 -q >/dev/null 2>&1 ||
  fail "encode with registered poses"
echo '{"features": [{"frame": 0, "camera": "cam09", "points": {"l_knee": [1, 2]}}]}' >"$dir/bad.json"
out=$("$fvv" capture register "$dir/cap" --features "$dir/bad.json" -o "$dir/bad_reg.json" 2>&1) &&
  fail "a feature file with an unknown camera accepted"
grep -q 'no camera "cam09"' <<<"$out" && [ ! -e "$dir/bad_reg.json" ] || fail "register error: $out"
out=$("$fvv" capture hull "$dir/cap" --frame 3 -o "$dir/hull3.ply" 2>&1) && fail "hull of frame 3 accepted"
grep -q "the capture has 3 frames" <<<"$out" && [ ! -e "$dir/hull3.ply" ] || fail "hull frame message: $out"

# Bad inputs.
out=$("$fvv" capture check "$dir/nowhere" 2>&1) && fail "missing capture accepted"
grep -q "cannot read" <<<"$out" || fail "missing capture message: $out"
mkdir -p "$dir/broken" && head -c 200 "$dir/cap/capture.json" >"$dir/broken/capture.json"
out=$("$fvv" capture check "$dir/broken" 2>&1) && fail "truncated capture.json accepted"
grep -q "not valid JSON" <<<"$out" || fail "truncated capture.json message: $out"
cp -r "$dir/cap" "$dir/gone" && rm "$dir/gone/cam01/000001.png"
out=$("$fvv" capture check "$dir/gone" 2>&1) && fail "missing frame accepted"
grep -q 'camera "cam01", frame 1: missing file' <<<"$out" || fail "missing frame message: $out"
out=$("$fvv" track "$dir/gone" -o "$dir/gone.json" -q 2>&1) && fail "track with a missing frame accepted"
grep -q 'camera "cam01", frame 1' <<<"$out" || fail "track missing frame message: $out"
[ ! -e "$dir/gone.json" ] || fail "a failed track left a poses file"
out=$("$fvv" synth -o "$dir/x" --motion "$dir/none.bvh" 2>&1) && fail "missing BVH accepted"
grep -q "none.bvh" <<<"$out" || fail "missing BVH message: $out"

# import-calib: a TOML rig for the same two cameras describes the same capture.
cp -r "$dir/cap" "$dir/imported" && rm "$dir/imported/capture.json"
cat >"$dir/rig.toml" <<TOML
[cam00]
image_size = [96, 72]
K = [[108, 0, 47.5], [0, 108, 35.5], [0, 0, 1]]
dist = [0, 0, 0, 0, 0]
rvec = [0, 3.14159265358979, 0]
t = [0, -1300, 3600]
[cam01]
image_size = [96, 72]
K = [[108, 0, 47.5], [0, 108, 35.5], [0, 0, 1]]
dist = [0, 0, 0, 0, 0]
rvec = [0, 0, 0]
t = [0, -1300, 3600]
TOML
out=$("$fvv" capture import-calib "$dir/rig.toml" -o "$dir/imported" --translation-unit mm --fps 25 2>&1) ||
  fail "import-calib: $out"
grep -q "imported 2 cameras (TOML) from 1 file(s)" <<<"$out" && grep -q "(3 frames at 25 fps)" <<<"$out" ||
  fail "import report: $out"
"$fvv" capture check "$dir/imported" >/dev/null || fail "imported capture does not check"
# Without --up, a rig whose cameras stand upright along z is taken as z up, and
# the import says why; told y, it warns that the cameras say otherwise.
mkdir -p "$dir/zup"
sed 's/^rvec = .*/rvec = [1.5707963267949, 0, 0]/' "$dir/rig.toml" >"$dir/zup.toml"
out=$("$fvv" capture import-calib "$dir/zup.toml" -o "$dir/zup" --images "$dir/cap/{camera}/%06d.png" \
  --translation-unit mm 2>&1) || fail "import-calib z up: $out"
grep -q "up axis z: from the cameras (+z: 2 camera(s)' image up within 45 degrees of it)" <<<"$out" ||
  fail "up axis from the cameras: $out"
grep -q '"up_axis": "z"' "$dir/zup/capture.json" || fail "capture.json up axis: $(cat "$dir/zup/capture.json")"
out=$("$fvv" capture check "$dir/zup" 2>&1) || fail "z-up capture does not check: $out"
grep -q "warning" <<<"$out" && fail "an upright rig warned: $out"
out=$("$fvv" capture import-calib "$dir/zup.toml" -o "$dir/zup" --images "$dir/cap/{camera}/%06d.png" \
  --translation-unit mm --up y 2>&1) || fail "import-calib --up y: $out"
grep -q "up axis y: as --up says" <<<"$out" && grep -q "warning: up axis: the cameras' image up points along +z" <<<"$out" ||
  fail "no warning against the cameras: $out"
out=$("$fvv" capture check "$dir/zup" 2>&1) || fail "y-up capture does not check: $out"
grep -q "warning: the cameras do not stand upright in this capture's world" <<<"$out" ||
  fail "check does not warn of a lying rig: $out"
# A capture directory that does not exist yet is made, once the import succeeds;
# one that fails leaves none behind.
out=$("$fvv" capture import-calib "$dir/zup.toml" -o "$dir/new/capture" \
  --images "$dir/cap/{camera}/%06d.png" --translation-unit mm 2>&1) ||
  fail "import-calib into a new directory: $out"
"$fvv" capture check "$dir/new/capture" >/dev/null || fail "the new directory's capture does not check"
out=$("$fvv" capture import-calib "$dir/zup.toml" -o "$dir/never" --images "$dir/none/{camera}/%06d.png" \
  --translation-unit mm 2>&1) && fail "import-calib without frames accepted"
grep -q "no frames found" <<<"$out" || fail "no frames message: $out"
[ ! -e "$dir/never" ] || fail "a failed import left its directory"
touch "$dir/plain"
out=$("$fvv" capture import-calib "$dir/zup.toml" -o "$dir/plain" \
  --images "$dir/cap/{camera}/%06d.png" --translation-unit mm 2>&1) && fail "a file as --output accepted"
grep -q "plain: cannot make the directory" <<<"$out" || fail "file as --output message: $out"
printf '[cam00]\nwidth = 96\n' >"$dir/partial.toml"
out=$("$fvv" capture import-calib "$dir/partial.toml" -o "$dir/imported" 2>&1) && fail "partial calibration accepted"
grep -q "partial.toml: cam00: no camera matrix\|no camera found" <<<"$out" || fail "partial message: $out"

echo "cli capture: OK"
