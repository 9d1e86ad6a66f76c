#!/usr/bin/env bash
# Makes the conformance case "encoder_body": a stream from the full encoder
# (fvv synth -> fvv encode with the true poses) with the generic body model of
# 23,040 triangles, 17 bones and 35 DOFs, so the suite holds one stream shaped
# exactly like what studios produce. Released cases never change: an existing
# case is kept unless --force.
# Usage: conformance/generator/make_encoder_case.sh FVV_BINARY CONFORMANCE_DIR [--force]
set -euo pipefail
fvv=$1
suite=$2
case_dir="$suite/encoder_body"
if [ -f "$case_dir/test.json" ] && [ "${3:-}" != "--force" ]; then
  echo "kept     encoder_body (released; --force to remake)"
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$fvv" synth -o "$work/capture" --cameras 3 --width 160 --height 120 --frames 4 --held-out 0 \
  --with-silhouettes >/dev/null
mkdir -p "$case_dir"
"$fvv" encode "$work/capture" -o "$case_dir/stream.fvv" --poses "$work/capture/truth/truth.json" \
  --atlas 128 --gop-frames 2 --psnr 30 --mask-coder context \
  --meta title="fvv conformance: encoder_body" -q >/dev/null
cat >"$case_dir/test.json" <<JSON
{
 "name": "encoder_body",
 "description": "made by fvv encode from a synthetic capture: the generic body model (17 bones, 15,670 vertices, 23,040 triangles), 3 cameras, 128x128 atlas, GOP 2 frames x 1 camera, PSNR rate control",
 "format_version": 1,
 "profile": 1,
 "level": 1,
 "tools": ["97", "spiht-arith", "masks"],
 "spec_sections": ["2", "3.1", "3.2", "3.3", "3.4", "3.5", "3.6", "3.7", "5", "6.1", "6.2", "6.3", "6.4", "7", "9.1", "9.2", "9.3", "9.4", "9.5", "9.6", "9.7"],
 "stream": "stream.fvv",
 "expect": "decode"
}
JSON
"$fvv" conform "$case_dir" --bless --budgets 300,1200 --force
