#!/usr/bin/env bash
# The documented way to serve fvv streams and the web player (docs/web.md):
# Debian's lighttpd with tools/web/lighttpd.conf on 127.0.0.1 answers byte
# ranges with the isolation headers and the module's type, sends the page's
# code compressed and lets the browser keep it (asked again, a 304), never
# compresses or keeps a stream, and a page in headless chromium decodes a
# stream from it (tests/web_browser_decode_test.mjs).
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
headers=$(curl -s -D - -o /dev/null -H 'Accept-Encoding: gzip' -H 'Range: bytes=0-999' \
  "http://127.0.0.1:$port/data/$name")
grep -q '^HTTP/1.1 206' <<<"$headers" || fail "a range asked for with gzip accepted: $headers"
! grep -qi '^Content-Encoding' <<<"$headers" || fail "a stream's range compressed: $headers"
# The module: its type, compressed (and whole once inflated), kept and asked
# again by its ETag.
module="$wasm/fvv_decoder.wasm"
headers=$(curl -s -D - -o "$dir/module.gz" -H 'Accept-Encoding: gzip' "http://127.0.0.1:$port/wasm/fvv_decoder.wasm")
grep -qi '^Content-Type: application/wasm' <<<"$headers" || fail "the module's type: $headers"
grep -qi '^Content-Encoding: gzip' <<<"$headers" || fail "the module not compressed: $headers"
grep -qi '^Cache-Control: no-cache' <<<"$headers" || fail "the module's caching: $headers"
sent=$(stat -c %s "$dir/module.gz") size=$(stat -c %s "$module")
[ $((sent * 2)) -lt "$size" ] || fail "the module sent in $sent of its $size bytes"
gzip -dc "$dir/module.gz" | cmp -s - "$module" || fail "the compressed module inflates to another"
etag=$(sed -n 's/^ETag: *\(.*\)\r$/\1/Ip' <<<"$headers")
again=$(curl -s -D - -o /dev/null -H 'Accept-Encoding: gzip' -H "If-None-Match: $etag" \
  "http://127.0.0.1:$port/wasm/fvv_decoder.wasm")
grep -q '^HTTP/1.1 304' <<<"$again" || fail "the module asked again by its ETag $etag: $again"
echo "ok   the module in $sent of its $size bytes, a 304 when asked again; a stream's ranges as they are"
FVV_WEB_SERVER="http://127.0.0.1:$port" \
  node "$root/tests/web_browser_decode_test.mjs" "$wasm" "$dir/site/data/$name" "$whole"
