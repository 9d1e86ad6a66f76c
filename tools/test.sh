#!/usr/bin/env bash
# Runs every test on a fresh Debian machine: installs dependencies, builds with
# clang and warnings as errors under AddressSanitizer + UndefinedBehaviorSanitizer
# with libFuzzer's coverage (one build serves the suites and the fuzz targets),
# and runs the suites in parallel (the slowest tracking tests in an optimised
# build, below); then the decoder in WebAssembly in Node, then the threaded
# modules' tests under ThreadSanitizer, then every fuzz target for a fixed time.
# Usage: tools/test.sh   (build dirs: build-asan/, build/ for those three,
# build-wasm/, build-tsan/)
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage's end and the time so far, to see where a slow run spent it.
stage() { echo "== $1 done at $((SECONDS / 60)) min $((SECONDS % 60)) s"; }
./tools/setup.sh
stage "set-up"
python3 tools/check_layers.py  # an include against the layers fails before the long build
# A directory configured with another compiler cannot be switched in place.
for d in build-asan build-tsan; do
  if [ -f $d/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang' $d/CMakeCache.txt; then
    rm -rf $d
  fi
done
export CC=clang CXX=clang++
# Line tables are all a sanitizer's report needs (file and line of every
# frame); full debug info made the sanitizer builds a quarter slower.
lines="-O2 -gline-tables-only -DNDEBUG"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFVV_SANITIZE=ON -DFVV_WERROR=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$lines" -DCMAKE_C_FLAGS_RELWITHDEBINFO="$lines" \
  -DFVV_BUILD_FUZZERS=ON -DFVV_BUILD_BENCH=ON >/dev/null
cmake --build build-asan -j2
stage "sanitizer build"
# CesiumMan's tracking tests fit a cartoon body's proportions (a model rebuilt
# per trial): 18 times slower under the sanitizers, nearly half the suite's time
# there. The tracked shards' test tracks a take four times over. They run in an
# optimised build; the same tracker code runs under the sanitizers in every
# other tracking test. The person
# silhouettes' test tracks a take on two kinds of silhouettes (541 s under the
# sanitizers, 35 s optimised); the person observer's other tests run there.
# Five more fit many frames over and over (507, 225, 197 and 167 s under the
# sanitizers, 8-20 s optimised; the calibration check tracks a take twice,
# 8 s optimised; the silhouette refinement tracks it three times, 5 s
# optimised; the sides of a 12-camera rig are decided the slow way beside the
# fast, 20 s optimised); their suites' other tests run there. The
# command line's shard test tracks a take and its shards (past its 600 s
# timeout under the sanitizers on a busy machine, 27 s optimised; the shards'
# other paths run there in the encoder's shard tests), and so do its commands
# that track a synthetic capture (fvv track, fvv encode tracking a dome's few
# cameras, fvv capture calibrate-colour: 230 s under the sanitizers, 15 s
# optimised; the tracker and the colour calibration run there in their own
# suites, the rest of fvv capture in cli_capture). Renderer I tracking a
# capture itself (105 s under the sanitizers, 10 s optimised) runs the tracker
# that the command-line encode test runs there. The loose-shorts actor's
# surface tests encode and score 8 frames twice (23 s optimised), and refine
# the first frame's shape on tracked poses (167 s under the sanitizers, 8 s
# optimised); the same surface tracking runs under the sanitizers in the
# surface-detail test, and the encoder's shape refinement in the refined
# model's test.
slow='^(CesiumManTest\.|TrackedShardTest\.|PersonSilhouettes\.|'
slow+='TrackTest\.(SmoothedFramesReachTheCallbackInOrderWithTheirPoses|'
slow+='SightingsHoldTheFitWithOneCameraConfused|RecoversKnownMotionWithinBounds|'
slow+='NamesTheCameraWhoseCalibrationDisagrees|SilhouetteRefinementTurnsBumpedCamerasBack)$|'
slow+='ShapeRefinementTest\.FeaturePointsCorrectAPoseError$|^cli_shards$|^cli_render_tracked$|'
slow+='^cli_capture_tracking$|'
slow+='SightingSides\.InARigOfTwelveTryingTheCamerasThatStandOutDecidesAsTryingAll$|'
slow+='(Tracked)?GarmentTest\.)'
CC=cc CXX=c++ cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DFVV_WERROR=ON >/dev/null
cmake --build build -j2 --target track_test encode_shards_test track_person_observer_test track_sighting_sides_test \
  shape_refinement_test fvv conformance_decode depth_map_triangles_print
stage "optimised build"
ctest --test-dir build-asan -j2 --output-on-failure -E "$slow"
stage "sanitizer suites"
ctest --test-dir build -j2 --output-on-failure -R "$slow"
stage "optimised suites"

# The decoder library in WebAssembly (player/web/CMakeLists.txt, Debian's
# emscripten, no threads): the conformance suite in Node against the released
# expectations, bit for bit, and its JavaScript API against the native decoder;
# the web player's page (player/web/index.html) against fvv render and faults.
emcmake cmake -S player/web -B build-wasm -G Ninja >/dev/null
cmake --build build-wasm -j2
stage "WebAssembly build"
build/tools/fvv/fvv conform conformance/cases -q \
  --decoder 'node --no-experimental-fetch build-wasm/conformance_decode.js {stream} {out} {bytes}'
tests/web_decoder_test.sh build/tools/fvv/fvv build/tools/conformance_decode build-wasm \
  build-wasm/web_decoder_test build/tests/depth_map_triangles_print
tests/web_lighttpd_test.sh build-wasm/web_decoder_test/s.fvv build-wasm/web_decoder_test/whole \
  build-wasm build-wasm/web_lighttpd_test
tests/web_player_test.sh build/tools/fvv/fvv build-wasm/site build-wasm/web_player_test
stage "WebAssembly decoder in Node, the web player in chromium"

# ThreadSanitizer on what runs threads: the codec's pool and parallel coding,
# the decoder's workers and its C API under threads, the encoder session (its
# encode beside tracking). Only these targets are built; within the codec's
# suite, the tests that run the pool (its rate comparisons run single-threaded
# code for minutes under TSan and are left to the ASan run).
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFVV_TSAN=ON -DFVV_WERROR=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$lines" -DCMAKE_C_FLAGS_RELWITHDEBINFO="$lines" \
  -DFVV_BUILD_BENCH=OFF >/dev/null
cmake --build build-tsan -j2 --target codec_test player_decoder_api_test \
  player_decoder_threads_test player_decoder_realtime_test encode_ordered_queue_test \
  encode_session_test
stage "ThreadSanitizer build"
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1"
tsan() { echo "== ThreadSanitizer: $*"; timeout 900 "$@"; }
tsan build-tsan/tests/codec_test \
  --gtest_filter='ThreadPool.*:Decoder.*:Embedded.*:Prune.GainsWhereLoneCoefficientsCostMost:*LosslessRoundTrip.*'
tsan build-tsan/tests/player_decoder_threads_test
tsan build-tsan/tests/player_decoder_api_test
tsan build-tsan/tests/player_decoder_realtime_test
tsan build-tsan/tests/encode_ordered_queue_test
tsan build-tsan/tests/encode_session_test \
  --gtest_filter='EncodeTest.RoundTripReachesTheReportedPsnr:EncodeTest.CApiEncodesAndReportsAndRefusesMisuse'

# Fuzzing: every libFuzzer target for a fixed time (FVV_FUZZ_SECONDS, default
# 30), two at a time, under ASan+UBSan (the build above). A crash fails the run
# and leaves its input in build-asan/fuzz-crashes/ (fuzz/README.md).
stage "ThreadSanitizer runs"
fuzz/run_all.sh build-asan "${FVV_FUZZ_SECONDS:-30}"
stage "fuzzing"
