#!/usr/bin/env bash
# Fuzzes every libFuzzer target for a fixed time, two at a time, each on a copy
# of its seed corpus and regressions. A crash fails the run and leaves its
# input in BUILD/fuzz-crashes/; each run's log is in BUILD/fuzz-runs/.
# Usage: fuzz/run_all.sh BUILD SECONDS   (tools/test.sh: build-asan 30; the
# longer run before an issue closes: build-asan 276, an hour in all)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: fuzz/run_all.sh BUILD SECONDS}
seconds=${2:?usage: fuzz/run_all.sh BUILD SECONDS}
targets=(fuzz_stream_reader fuzz_motion fuzz_mask fuzz_block fuzz_decode fuzz_decoder_api
  fuzz_decoder_ranges fuzz_bvh fuzz_gltf fuzz_capture_json fuzz_calibration fuzz_block_round_trip
  fuzz_poses fuzz_features
  fuzz_prepared fuzz_image)
runs=$build/fuzz-runs crashes=$build/fuzz-crashes
rm -rf "$runs" && mkdir -p "$runs" "$crashes"
fuzz_one() {
  local t=$1 dir=$runs/$1
  mkdir -p "$dir"
  cp fuzz/corpus/"$t"/* "$dir"/
  if [ -d fuzz/regressions/"$t" ]; then cp fuzz/regressions/"$t"/* "$dir"/; fi
  if ! "$build"/fuzz/"$t" "$dir" -max_total_time="$seconds" -rss_limit_mb=4096 \
    -print_final_stats=1 -artifact_prefix="$crashes/$t-" >"$runs/$t.log" 2>&1; then
    tail -40 "$runs/$t.log"
    echo "FUZZ FAILED: $t (input in $crashes/)"
    return 1
  fi
  echo "== fuzzed $t: $(grep -o 'Done [0-9]* runs in [0-9]* second(s)' "$runs/$t.log")," \
    "$(grep -o 'cov: [0-9]* ft: [0-9]*' "$runs/$t.log" | tail -1), corpus $(ls "$dir" | wc -l)"
}
failed=0
for ((i = 0; i < ${#targets[@]}; i += 2)); do
  pids=()
  for t in "${targets[@]:i:2}"; do
    fuzz_one "$t" &
    pids+=($!)
  done
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
done
exit $failed
