#!/usr/bin/env bash
# Serves the web player and streams on 127.0.0.1 with Debian's lighttpd
# (tools/web/lighttpd.conf: byte ranges, the isolation headers, no caching),
# until Ctrl-C. The site is the WebAssembly build's (emcmake cmake -S player/web
# -B build-wasm && cmake --build build-wasm); each stream is served under
# streams/ and its page's address printed.
# Usage: tools/web/serve.sh STREAM.fvv [STREAM.fvv ...] [--port N] [--site DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
port=8080 site="$root/build-wasm/site" streams=()
while [ $# -gt 0 ]; do
  case $1 in
    --port) port=$2; shift 2 ;;
    --site) site=$2; shift 2 ;;
    -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) streams+=("$1"); shift ;;
  esac
done
[ ${#streams[@]} -gt 0 ] || { echo "serve.sh: give a .fvv stream to serve (--help)" >&2; exit 2; }
[ -f "$site/index.html" ] || {
  echo "serve.sh: no web player at $site: build it with" >&2
  echo "  emcmake cmake -S player/web -B build-wasm -G Ninja && cmake --build build-wasm" >&2
  exit 2
}
command -v lighttpd >/dev/null || { echo "serve.sh: lighttpd is missing (tools/setup.sh installs it)" >&2; exit 2; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for f in "$site"/*; do ln -s "$(cd "$(dirname "$f")" && pwd)/$(basename "$f")" "$dir/"; done
mkdir "$dir/streams"
for s in "${streams[@]}"; do
  [ -f "$s" ] || { echo "serve.sh: no such stream: $s" >&2; exit 2; }
  ln -s "$(cd "$(dirname "$s")" && pwd)/$(basename "$s")" "$dir/streams/"
  echo "http://127.0.0.1:$port/index.html?stream=streams/$(basename "$s")"
done
echo "(lighttpd on 127.0.0.1:$port; Ctrl-C stops it)"
FVV_WEB_ROOT="$dir" FVV_WEB_PORT=$port lighttpd -D -f "$root/tools/web/lighttpd.conf"
