#!/usr/bin/env bash
# The documented way to serve fvv streams and the web player (docs/web.md):
# Debian's lighttpd with tools/web/lighttpd.conf on 127.0.0.1 answers byte
# ranges with the isolation headers and the module's type, and a page in
# headless chromium decodes a stream from it (tests/web_browser_decode_test.mjs).
# The server is stopped however the test ends.
# Usage: web_lighttpd_test.sh STREAM NATIVE_WHOLE_OUT_DIR BUILD_WASM_DIR WORK_DIR
set -euo pipefail
stream=$1 whole=$2 wasm=$3 dir=$4
root=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$dir" && mkdir -p "$dir/site/data"
dir=$(cd "$dir" && pwd)  # lighttpd takes an absolute document root
ln -s "$(cd "$wasm" && pwd)" "$dir/site/wasm"
ln -s "$root/player/web" "$dir/site/web"
ln -s "$root/tools/web/node_modules/fzstd/esm" "$dir/site/fzstd"
cp "$stream" "$dir/site/data/"
name=$(basename "$stream")
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
FVV_WEB_ROOT="$dir/site" FVV_WEB_PORT=$port lighttpd -D -f "$root/tools/web/lighttpd.conf" \
  >"$dir/lighttpd.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null; wait $server 2>/dev/null || true' EXIT
for _ in $(seq 50); do curl -s -o /dev/null "http://127.0.0.1:$port/data/$name" && break; sleep 0.1; done
fail() { echo "FAIL: $*" >&2; exit 1; }
headers=$(curl -s -D - -o /dev/null -H 'Range: bytes=100-199' "http://127.0.0.1:$port/data/$name")
grep -q '^HTTP/1.1 206' <<<"$headers" || fail "a range request: $headers"
grep -qi '^Content-Range: bytes 100-199/' <<<"$headers" || fail "Content-Range: $headers"
grep -qi '^Cross-Origin-Embedder-Policy: require-corp' <<<"$headers" || fail "COEP: $headers"
grep -qi '^Cache-Control: no-store' <<<"$headers" || fail "caching: $headers"
curl -s -D - -o /dev/null "http://127.0.0.1:$port/wasm/fvv_decoder.wasm" |
  grep -qi '^Content-Type: application/wasm' || fail "the module's type"
FVV_WEB_SERVER="http://127.0.0.1:$port" \
  node "$root/tests/web_browser_decode_test.mjs" "$wasm" "$dir/site/data/$name" "$whole"
