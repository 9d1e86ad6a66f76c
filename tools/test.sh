#!/usr/bin/env bash
# Runs every test on a fresh Debian machine: installs dependencies, builds with
# clang and warnings as errors under AddressSanitizer + UndefinedBehaviorSanitizer
# with libFuzzer's coverage (one build serves the suites and the fuzz targets),
# and runs the suites in parallel (three slow tracking tests in an optimised
# build, below); then the threaded modules' tests under ThreadSanitizer, then
# every fuzz target for a fixed time.
# Usage: tools/test.sh   (build dirs: build-asan/, build/ for those three,
# build-tsan/)
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/setup.sh
python3 tools/check_layers.py  # an include against the layers fails before the long build
# A directory configured with another compiler cannot be switched in place.
for d in build-asan build-tsan; do
  if [ -f $d/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang' $d/CMakeCache.txt; then
    rm -rf $d
  fi
done
export CC=clang CXX=clang++
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFVV_SANITIZE=ON -DFVV_WERROR=ON \
  -DFVV_BUILD_FUZZERS=ON -DFVV_BUILD_BENCH=ON >/dev/null
cmake --build build-asan -j2
# CesiumMan's tracking tests fit a cartoon body's proportions (a model rebuilt
# per trial): 18 times slower under the sanitizers, nearly half the suite's time
# there. They run in an optimised build; the same tracker code runs under the
# sanitizers in every other tracking test.
slow='^CesiumManTest\.'
CC=cc CXX=c++ cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DFVV_WERROR=ON >/dev/null
cmake --build build -j2 --target track_test
ctest --test-dir build-asan -j2 --output-on-failure -E "$slow"
ctest --test-dir build -j2 --output-on-failure -R "$slow"

# ThreadSanitizer on what runs threads: the codec's pool and parallel coding,
# the decoder's workers and its C API under threads, the encoder session (its
# encode beside tracking). Only these targets are built; within the codec's
# suite, the tests that run the pool (its rate comparisons run single-threaded
# code for minutes under TSan and are left to the ASan run).
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFVV_TSAN=ON -DFVV_WERROR=ON \
  -DFVV_BUILD_BENCH=OFF >/dev/null
cmake --build build-tsan -j2 --target codec_test player_decoder_api_test \
  player_decoder_threads_test encode_ordered_queue_test encode_session_test
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1"
tsan() { echo "== ThreadSanitizer: $*"; timeout 900 "$@"; }
tsan build-tsan/tests/codec_test \
  --gtest_filter='ThreadPool.*:Decoder.*:Embedded.*:Prune.GainsWhereLoneCoefficientsCostMost:*LosslessRoundTrip.*'
tsan build-tsan/tests/player_decoder_threads_test
tsan build-tsan/tests/player_decoder_api_test
tsan build-tsan/tests/encode_ordered_queue_test
tsan build-tsan/tests/encode_session_test \
  --gtest_filter='EncodeTest.RoundTripReachesTheReportedPsnr:EncodeTest.CApiEncodesAndReportsAndRefusesMisuse'

# Fuzzing: every libFuzzer target for a fixed time (FVV_FUZZ_SECONDS, default
# 30), two at a time, on a copy of its seed corpus and regressions, under
# ASan+UBSan (the build above). A crash fails the run and leaves its input in
# build-asan/fuzz-crashes/ (fuzz/README.md).
fuzz_targets=(fuzz_stream_reader fuzz_motion fuzz_mask fuzz_block fuzz_decode fuzz_decoder_api
  fuzz_bvh fuzz_gltf fuzz_capture_json fuzz_calibration fuzz_block_round_trip fuzz_poses fuzz_features)
rm -rf build-asan/fuzz-runs && mkdir -p build-asan/fuzz-crashes
fuzz_one() {
  local t=$1 dir=build-asan/fuzz-runs/$1
  mkdir -p "$dir"
  cp fuzz/corpus/"$t"/* "$dir"/
  if [ -d fuzz/regressions/"$t" ]; then cp fuzz/regressions/"$t"/* "$dir"/; fi
  if ! build-asan/fuzz/"$t" "$dir" -max_total_time="${FVV_FUZZ_SECONDS:-30}" -rss_limit_mb=4096 \
    -artifact_prefix=build-asan/fuzz-crashes/"$t"- >build-asan/fuzz-runs/"$t".log 2>&1; then
    tail -40 build-asan/fuzz-runs/"$t".log
    echo "FUZZ FAILED: $t (input in build-asan/fuzz-crashes/)"
    return 1
  fi
  echo "== fuzzed $t: $(grep -o 'Done [0-9]* runs in [0-9]* second(s)' build-asan/fuzz-runs/"$t".log)," \
    "$(grep -o 'cov: [0-9]*' build-asan/fuzz-runs/"$t".log | tail -1)"
}
fuzz_failed=0
for ((i = 0; i < ${#fuzz_targets[@]}; i += 2)); do
  pids=()
  for t in "${fuzz_targets[@]:i:2}"; do
    fuzz_one "$t" &
    pids+=($!)
  done
  for p in "${pids[@]}"; do wait "$p" || fuzz_failed=1; done
done
[ $fuzz_failed = 0 ] || exit 1
