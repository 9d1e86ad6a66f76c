#!/usr/bin/env bash
# The WebAssembly decoder in Node (tests/web_decoder_test.mjs): a sample stream
# with the texture in chunks, the native reference decoder's conformance output
# at a prefix and whole, and the JavaScript API against them, in Node and in
# headless chromium (tests/web_browser_decode_test.mjs: the stream by HTTP
# Range requests; tests/web_stream_faults_test.mjs: player/web/fvv_stream.mjs
# cleanly and under a 404, a server that ignores Range, a connection closed
# mid-fragment, a damaged and a cut stream).
# The module's simplified body for the depth maps against the native one
# (tests/depth_map_triangles_print.cc).
# Usage: web_decoder_test.sh FVV CONFORMANCE_DECODE BUILD_WASM_DIR WORK_DIR DEPTH_MAP_TRIANGLES_PRINT
set -euo pipefail
fvv=$1 native=$2 wasm=$3 dir=$4 triangles=$5
here=$(cd "$(dirname "$0")" && pwd)
body="$here/../conformance/cases/encoder_body/stream.fvv"  # the generic body model
rm -rf "$dir" && mkdir -p "$dir/prefix" "$dir/whole"
"$fvv" sample -o "$dir/s.fvv" --frames 10 --cameras 3 --atlas 48 40 --gop 4 1 --coder arith4 \
  --bpp 3 --texture-chunks >/dev/null
"$fvv" sample -o "$dir/surface.fvv" --frames 8 --cameras 3 --atlas 48 40 --gop 4 1 --coder arith4 \
  --bpp 3 --surface >/dev/null
"$native" "$dir/s.fvv" "$dir/prefix" 900
"$native" "$dir/s.fvv" "$dir/whole" 0
node --no-experimental-fetch "$here/web_decoder_test.mjs" "$wasm" "$dir/s.fvv" "$dir/prefix" 900 "$dir/whole" \
  "$dir/surface.fvv" "$body" "$("$triangles" "$body")"
node "$here/web_browser_decode_test.mjs" "$wasm" "$dir/s.fvv" "$dir/whole"
mkdir -p "$dir/faults"
node "$here/web_stream_faults_test.mjs" "$wasm" "$dir/s.fvv" "$dir/whole" "$dir/faults"
