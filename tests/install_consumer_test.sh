#!/usr/bin/env bash
# Installs fvv into a temporary prefix and builds two applications against it
# with find_package(fvv COMPONENTS encoder export): one linking fvv::dec
# decodes a stream, one linking fvv::export writes its actor as glTF, one
# linking fvv::encoder encodes a small synthetic capture, which the first then
# decodes.
# Usage: install_consumer_test.sh BUILD_DIR SOURCE_DIR FVV_BINARY WORK_DIR [EXTRA_LINK_FLAGS]
set -u
build=$1 src=$2 fvv=$3 work=$4 flags=${5:-}
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log" 2>&1 || fail "install: $(tail -5 "$work/install.log")"
cmake -S "$src/tests/install_consumer" -B "$work/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_EXE_LINKER_FLAGS="$flags" >"$work/configure.log" 2>&1 || fail "find_package(fvv): $(tail -8 "$work/configure.log")"
cmake --build "$work/consumer" >"$work/build.log" 2>&1 || fail "consumer build: $(tail -8 "$work/build.log")"
"$fvv" sample -o "$work/s.fvv" --frames 3 --cameras 2 --atlas 16 16 >/dev/null || fail "sample"
out=$("$work/consumer/consumer" "$work/s.fvv" 2>&1) || fail "consumer run: $out"
[ "$out" = "frames 3" ] || fail "consumer output: $out"
out=$("$work/consumer/export_consumer" "$work/s.fvv" "$work/s.glb" 2>&1) || fail "export consumer run: $out"
[ "$out" = "exported" ] && [ -s "$work/s.glb" ] || fail "export consumer output: $out"
"$fvv" synth -o "$work/cap" --cameras 2 --width 96 --height 72 --frames 3 --held-out 0 >/dev/null 2>&1 ||
  fail "synth"
out=$("$work/consumer/encode_consumer" "$work/cap" "$work/cap" "$work/e.fvv" 2>&1) ||
  fail "encode consumer run: $out"
[ "$out" = "encoded 3 frames, psnr ok" ] || fail "encode consumer output: $out"
out=$("$work/consumer/consumer" "$work/e.fvv" 2>&1) || fail "decoding the encoded stream: $out"
[ "$out" = "frames 3" ] || fail "consumer output on the encoded stream: $out"
echo "install consumer test passed"
