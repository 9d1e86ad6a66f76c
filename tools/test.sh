#!/usr/bin/env bash
# Runs every test on a fresh Debian machine: installs dependencies, builds with
# warnings as errors under AddressSanitizer + UndefinedBehaviorSanitizer, and runs
# the suites in parallel. Usage: tools/test.sh   (build dir: build-asan/)
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/setup.sh
python3 tools/check_layers.py  # an include against the layers fails before the long build
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFVV_SANITIZE=ON -DFVV_WERROR=ON \
  -DFVV_BUILD_BENCH=ON >/dev/null
cmake --build build-asan -j2
ctest --test-dir build-asan -j2 --output-on-failure
