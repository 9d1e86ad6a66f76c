#!/usr/bin/env bash
# The decoder in WebAssembly (Node) beside the native decoder: the same
# program (tools/web/conformance_decode.cc: the reference decode of every
# frame and camera, Annex B's YUV and RGB formed, no files written), one thread
# each, on the same stream and budgets, alternately over ROUNDS rounds; the
# median ms per decode of each and their ratio.
# Usage: bench/run_wasm_bench.sh [STREAM] [ROUNDS] [BUDGET ...]
#   STREAM: default out/demo/capture.fvv (./tools/demo.sh); BUDGETS: bytes per
#   fragment (a prefix with the texture in chunks), default 0 (whole) and 8000.
set -euo pipefail
cd "$(dirname "$0")/.."
stream=${1:-out/demo/capture.fvv}
rounds=${2:-3}
shift $(( $# > 2 ? 2 : $# )) || true
budgets=("$@")
[ ${#budgets[@]} -gt 0 ] || budgets=(0 8000)
[ -f "$stream" ] || { echo "no stream $stream (run ./tools/demo.sh, or name one)" >&2; exit 1; }
cmake --build build -j2 --target conformance_decode >/dev/null
[ -f build-wasm/CMakeCache.txt ] || emcmake cmake -S player/web -B build-wasm -G Ninja >/dev/null
cmake --build build-wasm -j2 >/dev/null
ms() { "$@" | awk '{print $1}'; }
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR + 1) / 2)]}'; }
printf "%-10s %12s %12s %8s\n" "budget" "native ms" "wasm ms" "ratio"
for b in "${budgets[@]}"; do
  native=() wasm=()
  for ((r = 0; r < rounds; ++r)); do
    native+=("$(ms build/tools/conformance_decode "$stream" - "$b" --repeat 1)")
    wasm+=("$(ms node --no-experimental-fetch build-wasm/conformance_decode.js "$stream" - "$b" --repeat 1)")
  done
  n=$(printf "%s\n" "${native[@]}" | median)
  w=$(printf "%s\n" "${wasm[@]}" | median)
  printf "%-10s %12.1f %12.1f %8.2f\n" "$b" "$n" "$w" "$(echo "$w / $n" | bc -l)"
done
