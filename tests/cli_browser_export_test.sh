#!/usr/bin/env bash
# An exported glTF in a real browser: headless Chromium (tools/web/browser_harness.mjs)
# loads it with three.js, plays its animation, and shows a fixed frame from a
# fixed camera; fvv render --texture draws the same frame, camera and single
# texture with fvv's own OpenGL renderer. PSNR over the actor's pixels >= 30 dB;
# no browser process outlives the test.
set -u
fvv=$1
dir=$2
root=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
web=$root/tools/web
[ -d "$web/node_modules/three" ] && [ -d "$web/node_modules/puppeteer-core" ] ||
  fail "tools/web/node_modules incomplete: run tools/setup.sh"
command -v chromium >/dev/null || fail "chromium not installed: run tools/setup.sh"

"$fvv" sample -o "$dir/s.fvv" --frames 12 --cameras 4 --atlas 128 128 --gop 4 1 >/dev/null || fail "sample"
"$fvv" export "$dir/s.fvv" -o "$dir/actor.glb" -q || fail "export glb"
"$fvv" export "$dir/s.fvv" -o "$dir/actor.gltf" -q || fail "export gltf"
eye=0.8,1.3,3.4 target=0,0.9,0 frame=7
out=$(node "$web/screenshot_gltf.mjs" "$dir/actor.glb" "$dir/three.png" --frame $frame --size 320x240 \
      --eye $eye --target $target --fov 40 2>&1) || fail "three.js: $out"
grep -q "1 skinned mesh" <<<"$out" && grep -q "0.440 s animation" <<<"$out" || fail "three.js page: $out"
echo "{\"keyframes\": [{\"frame\": $frame, \"eye\": [$eye], \"target\": [$target], \"fov\": 40}]}" \
  >"$dir/path.json"
"$fvv" render "$dir/s.fvv" -o "$dir/fvv" --texture "$dir/actor.png" --path "$dir/path.json" \
  --first $frame --last $frame --size 320x240 >/dev/null 2>&1 || fail "fvv render --texture"
for f in three fvv/render_f0000$frame; do
  ffmpeg -v error -y -i "$dir/$f.png" -f rawvideo -pix_fmt rgb24 "$dir/$(basename $f).rgb" || fail "ffmpeg $f"
done
/usr/bin/python3 - "$dir/three.rgb" "$dir/render_f0000$frame.rgb" <<'PY' || fail "three.js against fvv render"
import sys
import numpy as np
a, b = (np.fromfile(p, np.uint8).reshape(240, 320, 3).astype(float) for p in sys.argv[1:3])
# The actor: pixels either renderer drew differently from its background.
actor = (np.abs(a - a[0, 0]).sum(2) > 0) | (np.abs(b - b[0, 0]).sum(2) > 0)
assert actor.sum() > 1500, f"only {actor.sum()} actor pixels: the actor is not in view"
mse = ((a - b)[actor] ** 2).mean()
psnr = 10 * np.log10(255 ** 2 / max(mse, 1e-9))
print(f"three.js against fvv render: {psnr:.2f} dB over {actor.sum()} actor pixels")
assert psnr >= 30, "below 30 dB"
PY
# Every browser process gone (zombies aside, which their parent reaps).
for _ in $(seq 50); do
  left=$(ps -eo stat=,comm= | awk '$2 ~ /chrom/ && $1 !~ /^Z/' | wc -l)
  [ "$left" = 0 ] && break
  sleep 0.1
done
[ "$left" = 0 ] || fail "chromium processes left: $(ps -eo pid,stat,cmd | grep [c]hrom)"
echo "browser export: ok"
