#!/usr/bin/env bash
# Codec benchmark: Kodak 2D against OpenJPEG, then the 8x8x512x512 4D GOP.
# Usage: bench/run_codec_bench.sh [images, default 24]   (data: FVV_TEST_DATA_DIR or ../shared/data)
set -euo pipefail
cd "$(dirname "$0")/.."
data=${FVV_TEST_DATA_DIR:-../shared/data}
[ -d "$data/kodak" ] || { echo "skip: $data/kodak not found"; exit 0; }
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target codec_bench
build/bench/codec_bench kodak "$data" --images "${1:-24}"
build/bench/codec_bench gop4d "$data"
