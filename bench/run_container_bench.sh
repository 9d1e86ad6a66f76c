#!/usr/bin/env bash
# Container benchmarks: motion-track kbps on the CMU BVH files of assimp-testmodels
# (against raw floats and zstd -19), and the mask coder against zstd -19.
# Usage: bench/run_container_bench.sh
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target motion_bench mask_bench
build/bench/motion_bench
echo
build/bench/mask_bench
