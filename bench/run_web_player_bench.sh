#!/usr/bin/env bash
# The web player's frame rate beside fvv play's, on the same stream, at the
# same size, on this machine (a benchmark, not a test): fvv play in a virtual
# display (GLFW on Mesa's llvmpipe), the page in chromium with its two
# software WebGL back ends: SwiftShader (headless, what the tests use) and
# llvmpipe (ANGLE on OpenGL in the same virtual display: the native player's
# rasteriser). Prints frames drawn per second, each side's share of the
# native rate, the share of the page's time spent in WebGL, and the page's
# renderer alone (playback paused, the decoder worker idle: decoded frames set
# and drawn with a read-back after each), whose rate beside the playing one
# tells what the decoder's share of the two cores costs the drawing.
# Usage: bench/run_web_player_bench.sh STREAM [WxH, default 800x556] [SECONDS, default 10]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
stream=$(realpath "$1") size=${2:-800x556} seconds=${3:-10}
w=${size%x*} h=${size#*x}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
native=$(xvfb-run -a -s "-screen 0 $((w + 64))x$((h + 64))x24" "$root/build/tools/fvv/fvv" play "$stream" \
  --width "$w" --height "$h" --seconds "$seconds" | tail -1)
echo "fvv play: $native"
native_fps=$(sed -n 's/.*: \([0-9.]*\) fps drawn.*/\1/p' <<<"$native")
cd "$root/tools/web"
node screenshot_player.mjs "$root/build-wasm/site" "$stream" "$out/swiftshader.png" "$seconds" \
  --size "$size" --json "$out/swiftshader.json" --time-frames --renderer-alone 30 | grep -v '^page: '
FVV_CHROMIUM_GL="--use-angle=gl --ignore-gpu-blocklist --enable-gpu" xvfb-run -a \
  -s "-screen 0 $((w + 64))x$((h + 108))x24" node screenshot_player.mjs "$root/build-wasm/site" "$stream" \
  "$out/llvmpipe.png" "$seconds" --size "$size" --json "$out/llvmpipe.json" --time-frames --renderer-alone 30 | grep -v '^page: '
for backend in swiftshader llvmpipe; do
  node -e "
    const s = require('$out/$backend.json');
    console.log('$backend: ' + s.drawn_fps.toFixed(1) + ' fps drawn, ' +
      (100 * s.drawn_fps / $native_fps).toFixed(0) + ' % of fvv play; ' +
      s.speed.toFixed(2) + 'x real time; WebGL ' + (100 * s.webgl_share).toFixed(0) +
      ' % of the time (' + s.webglMs.toFixed(1) + ' ms a frame)' +
      (s.renderer_alone ? '; the renderer alone ' + (1000 / s.renderer_alone.ms).toFixed(1) + ' fps, ' +
        (100 * 1000 / s.renderer_alone.ms / $native_fps).toFixed(0) + ' % of fvv play' : ''));"
done
