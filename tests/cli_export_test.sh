#!/usr/bin/env bash
# End-to-end test of `fvv export`: glTF (.glb and .gltf with its side files)
# passing the Khronos glTF validator with no error and no warning, BVH, the
# round trip CMU BVH -> fvv synth -> fvv encode with the true poses -> fvv
# export -> fvv synth --motion (fvv's own BVH import) giving back the joint
# angles within the motion track's quantisation, and the errors a user sees.
set -u
fvv=$1
dir=$2
root=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$fvv" sample -o "$dir/s.fvv" --frames 10 --cameras 3 --atlas 32 32 --gop 4 1 >/dev/null || fail "sample"
out=$("$fvv" export "$dir/s.fvv" -o "$dir/a.glb" 2>&1) || fail "export glb: $out"
grep -q "wrote $dir/a.glb: 15 joints, 10 frames from 0 at 25 fps" <<<"$out" || fail "glb summary: $out"
out=$("$fvv" export "$dir/s.fvv" -o "$dir/b.gltf" --frames 2:7 --texture-frame 4 --texture-size 64 2>&1) ||
  fail "export gltf: $out"
grep -q "6 frames from 2" <<<"$out" && grep -q "texture 64x64 (frame 4)" <<<"$out" || fail "gltf summary: $out"
[ -s "$dir/b.bin" ] && [ -s "$dir/b.png" ] || fail ".gltf side files missing"
[ "$(ffprobe -v error -show_entries stream=width,height -of csv=p=0 "$dir/b.png")" = "64,64" ] ||
  fail "texture size"
ls "$dir" | grep -q "\.tmp" && fail "temporary files left: $(ls "$dir")"

# The Khronos validator (npm gltf-validator, installed by tools/setup.sh).
[ -d "$root/tools/web/node_modules/gltf-validator" ] ||
  fail "tools/web/node_modules/gltf-validator missing: run tools/setup.sh"
out=$(node "$root/tools/web/validate_gltf.mjs" "$dir/a.glb" "$dir/b.gltf" 2>&1) || fail "validator: $out"
[ "$(grep -c ": 0 errors, 0 warnings" <<<"$out")" = 2 ] || fail "validator: $out"

# A stream with the surface of every frame (format version 12): a morph
# target per frame, switched on by the animation one frame at a time.
"$fvv" sample -o "$dir/surface.fvv" --frames 6 --cameras 2 --atlas 32 32 --gop 4 1 --surface \
  >/dev/null || fail "sample --surface"
out=$("$fvv" export "$dir/surface.fvv" -o "$dir/surface.glb" 2>&1) || fail "export surface: $out"
out=$(node "$root/tools/web/validate_gltf.mjs" "$dir/surface.glb" 2>&1) || fail "validator: $out"
grep -q ": 0 errors, 0 warnings" <<<"$out" || fail "validator (surface): $out"
/usr/bin/python3 - "$dir/surface.glb" <<'PY' || fail "morph targets"
import json, struct, sys
b = open(sys.argv[1], 'rb').read()
n = struct.unpack('<I', b[12:16])[0]
doc = json.loads(b[20:20 + n])
prim = doc['meshes'][0]['primitives'][0]
assert len(prim['targets']) == 6, len(prim.get('targets', []))
assert doc['meshes'][0]['weights'] == [0] * 6
chan = [c for c in doc['animations'][0]['channels'] if c['target']['path'] == 'weights']
assert len(chan) == 1 and doc['animations'][0]['samplers'][chan[0]['sampler']]['interpolation'] == 'STEP'
# The targets move the surface: the sample's swings reach centimetres.
big = max(max(abs(x) for x in doc['accessors'][t['POSITION']]['max'] + doc['accessors'][t['POSITION']]['min']) for t in prim['targets'])
assert 0.01 < big < 0.4, big
PY

# Errors name the problem and write nothing.
out=$("$fvv" export "$dir/s.fvv" -o "$dir/x.obj" 2>&1) && fail ".obj accepted"
grep -q "writes .glb, .gltf or .bvh" <<<"$out" || fail ".obj message: $out"
out=$("$fvv" export "$dir/s.fvv" -o "$dir/x.bvh" --frames 8:20 2>&1) && fail "frames past the end accepted"
grep -q "frames 8..20: the stream has 10 frames" <<<"$out" || fail "frame range message: $out"
out=$("$fvv" export "$dir/s.fvv" -o "$dir/x.glb" --frames 0:3 --texture-frame 5 2>&1) &&
  fail "texture frame outside accepted"
grep -q "texture frame 5 is outside the frames exported" <<<"$out" || fail "texture frame: $out"
out=$("$fvv" export "$dir/s.fvv" -o "$dir/no/such/dir/x.glb" 2>&1) && fail "missing directory accepted"
grep -q "cannot create" <<<"$out" || fail "missing directory message: $out"
[ ! -e "$dir/x.bvh" ] && [ ! -e "$dir/x.glb" ] || fail "a failed export wrote a file"
echo "not a stream" >"$dir/bad.fvv"
out=$("$fvv" export "$dir/bad.fvv" -o "$dir/x.glb" 2>&1) && fail "bad stream accepted"
grep -q "fvv:" <<<"$out" || fail "bad stream message: $out"

# The round trip on the generic body with a CMU walk.
bvh=/usr/share/assimp/models/BVH/01_01.bvh
if [ ! -f "$bvh" ]; then
  echo "skip: BVH round trip ($bvh missing; tools/setup.sh installs assimp-testmodels)"
  exit 0
fi
"$fvv" synth -o "$dir/cap" --motion "$bvh" --frames 16 --cameras 4 --width 160 --height 120 \
  >/dev/null 2>&1 || fail "synth"
"$fvv" encode "$dir/cap" -o "$dir/cap.fvv" --poses "$dir/cap" --atlas 128 -q >/dev/null 2>&1 || fail "encode"
out=$("$fvv" export "$dir/cap.fvv" -o "$dir/m.bvh" 2>&1) || fail "export bvh: $out"
"$fvv" synth -o "$dir/back" --motion "$dir/m.bvh" --frames 16 --cameras 2 --width 160 --height 120 \
  >/dev/null 2>&1 || fail "fvv synth does not read the exported BVH"
/usr/bin/python3 - "$dir/cap/truth/truth.json" "$dir/back/truth/truth.json" <<'PY' || fail "round trip"
import json, math, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["dof_names"] == b["dof_names"], "DOF names differ"
rot_step, trans_step = math.radians(0.05), 0.0005  # the motion track's steps (fvv info)
worst_r = worst_t = 0.0
for fa, fb in zip(a["frames"], b["frames"]):
    for name, x, y in zip(a["dof_names"], fa["dofs"], fb["dofs"]):
        d = abs(x - y)
        if name.endswith((".tx", ".ty", ".tz")):
            worst_t = max(worst_t, d)
        else:
            worst_r = max(worst_r, d)
print(f"round trip: worst rotation {math.degrees(worst_r):.4f} deg, translation {worst_t * 1000:.3f} mm")
assert len(a["frames"]) == len(b["frames"]) == 16
assert worst_r <= rot_step and worst_t <= trans_step, "beyond the quantisation step"
PY
echo "cli export: ok"
