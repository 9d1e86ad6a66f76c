#!/usr/bin/env bash
# End-to-end test of `fvv encode` as a user runs it: a small synthetic capture is
# tracked and encoded (progress, summary table, textures saved), the stream
# inspects, decodes and renders; encoding again from the saved textures gives a
# stream of the same texture size; bad inputs fail with messages naming them
# and leave no output behind.
set -u
fvv=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$fvv" synth -o "$dir/cap" --cameras 4 --width 320 --height 240 --frames 3 --held-out 1 \
  >/dev/null 2>&1 || fail "synth"

out=$("$fvv" encode "$dir/cap" -o "$dir/a.fvv" --atlas 128 --gop-frames 2 --fixed-shape --save-textures "$dir/tex" \
  --summary-json "$dir/summary.json" --meta title=cli 2>&1) || fail "encode: $out"
for word in "encode: frame 2 (3/3)" "ETA" "pose source: tracked" "compression" "PSNR (visible)" \
  "seconds per frame" "mean IoU"; do
  grep -q "$word" <<<"$out" || fail "encode output lacks '$word': $out"
done
[ -s "$dir/a.fvv" ] && [ -f "$dir/tex/textures.json" ] && [ -f "$dir/tex/cam03/texture_000002.png" ] &&
  [ -f "$dir/tex/cam00/mask_000000.png" ] || fail "encode outputs missing"
grep -q '"psnr"' "$dir/summary.json" || fail "summary json"

out=$("$fvv" info "$dir/a.fvv" 2>&1) || fail "info: $out"
grep -q "title" <<<"$out" || fail "metadata not in the stream: $out"
"$fvv" decode "$dir/a.fvv" -o "$dir/dec" >/dev/null 2>&1 || fail "decode"
[ -f "$dir/dec/poses.json" ] || fail "decoded poses missing"
"$fvv" render "$dir/a.fvv" -o "$dir/render" --size 160x120 --camera 1 --last 0 >/dev/null 2>&1 ||
  fail "render"
# A novel view from the capture's held-out camera, at that camera's image size.
out=$("$fvv" render "$dir/a.fvv" -o "$dir/render_held" --cameras-from "$dir/cap/truth/heldout" --camera 0 \
  --last 0 2>&1) || fail "render --cameras-from: $out"
grep -q "at 320x240 (camera \"held00\"" <<<"$out" || fail "held-out render report: $out"
# Renderer I on the capture itself, given poses (the truth; tracked when none
# are given: cli_render_tracked); a stream is not a capture.
out=$("$fvv" render "$dir/cap" --renderer projective --poses "$dir/cap" -o "$dir/r1" \
  --cameras-from "$dir/cap/truth/heldout" --camera 0 2>&1) || fail "render --renderer projective: $out"
grep -q "rendered frames 0..2 at 320x240 (camera \"held00\".*Renderer I (projective)" <<<"$out" ||
  fail "Renderer I report: $out"
[ "$(ls "$dir"/r1/render_*.png | wc -l)" = 3 ] || fail "Renderer I wrote $(ls "$dir"/r1 | wc -l) files"
# With the surface of every frame tracked from the capture's silhouettes: the
# same frames, drawn on another surface.
out=$("$fvv" render "$dir/cap" --renderer projective --poses "$dir/cap" -o "$dir/r1s" --surface \
  --cameras-from "$dir/cap/truth/heldout" --camera 0 2>&1) || fail "render --surface: $out"
grep -q "surface tracked" <<<"$out" || fail "Renderer I --surface report: $out"
cmp -s "$dir/r1/render_f00002.png" "$dir/r1s/render_f00002.png" &&
  fail "Renderer I drew the same with --surface"
out=$("$fvv" render "$dir/a.fvv" --surface -o "$dir/r1bad" 2>&1) && fail "--surface with Renderer II"
grep -q "carries its own surface" <<<"$out" || fail "--surface with Renderer II: $out"
out=$("$fvv" render "$dir/a.fvv" --renderer projective --poses "$dir/cap" -o "$dir/r1bad" 2>&1) &&
  fail "a stream accepted as a capture"
grep -q "capture.json" <<<"$out" || fail "Renderer I on a stream: $out"
out=$("$fvv" render "$dir/a.fvv" --poses "$dir/cap" -o "$dir/r1bad" 2>&1) && fail "--poses with Renderer II"
grep -q "projective" <<<"$out" || fail "--poses with Renderer II: $out"
out=$("$fvv" render "$dir/cap" --renderer projective --poses "$dir/cap" --first 5 -o "$dir/r1bad" 2>&1) &&
  fail "frames beyond the capture accepted"
grep -q "beyond" <<<"$out" || fail "Renderer I frame range: $out"

# Again from the saved textures (no tracking, no resampling): the same textures give the same bytes.
out=$("$fvv" encode "$dir/cap" -o "$dir/b.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" -q 2>&1) ||
  fail "encode --textures: $out"
grep -q "pose source: textures" <<<"$out" || fail "textures source not reported: $out"
tex_a=$(grep -o '"texture": [0-9]*' "$dir/summary.json" | head -1 | grep -o '[0-9]*')
tex_b=$(grep "textures  " <<<"$out" | awk '{print $2}')
[ "$tex_a" = "$tex_b" ] || fail "texture bytes differ: $tex_a vs $tex_b"

# Format versions: the defaults write version 11 (the texture in chunks, the
# model on a grid); --whole-texture version 10 with the same samples; with
# --whole-texture --model-floats version 7 (3 fractional sample bits, own-band weights, SPIHT
# coder arith3, 9/7 precision 5, mask mode 2); then --sample-bits 0 writes version 6, --weights axis version 5, with --coder
# arith2 version 4, --coder arith version 3; --coder arith --precision 2
# --mask-coder context what version 1 decoders read.
"$fvv" info "$dir/b.fvv" | grep -q "format version 11" || fail "default format version: $("$fvv" info "$dir/b.fvv" | head -1)"
"$fvv" info "$dir/b.fvv" | grep -q "texture-chunks" || fail "default tools: $("$fvv" info "$dir/b.fvv" | grep tools)"
out=$("$fvv" encode "$dir/cap" -o "$dir/v10.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --whole-texture -q 2>&1) || fail "encode --whole-texture: $out"
"$fvv" info "$dir/v10.fvv" | grep -q "format version 10" || fail "whole-texture format version: $("$fvv" info "$dir/v10.fvv" | head -1)"
"$fvv" decode "$dir/b.fvv" -o "$dir/b_dec" >/dev/null 2>&1 || fail "decode of the chunked stream"
"$fvv" decode "$dir/v10.fvv" -o "$dir/v10_dec" >/dev/null 2>&1 || fail "decode of the whole-texture stream"
diff -r "$dir/b_dec" "$dir/v10_dec" >/dev/null || fail "chunks and texr decode differently"
"$fvv" info "$dir/b.fvv" | grep -q "quantised-model" || fail "default tools: $("$fvv" info "$dir/b.fvv" | grep tools)"
"$fvv" info "$dir/b.fvv" | grep -q "model: .*on a grid: positions 0.1221 mm" || fail "default model: $("$fvv" info "$dir/b.fvv" | grep model:)"
out=$("$fvv" encode "$dir/cap" -o "$dir/v7.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --whole-texture --model-floats -q 2>&1) || fail "encode --model-floats: $out"
"$fvv" info "$dir/v7.fvv" | grep -q "format version 7" || fail "model-floats format version: $("$fvv" info "$dir/v7.fvv" | head -1)"
"$fvv" info "$dir/v7.fvv" | grep -q "on a grid" && fail "model-floats model: $("$fvv" info "$dir/v7.fvv" | grep model:)"
[ "$(stat -c %s "$dir/v7.fvv")" -gt "$(stat -c %s "$dir/b.fvv")" ] || fail "the float model is not the larger stream"
# 4:2:0: bilinear chroma (format version 9) unless the older rule is asked for.
out=$("$fvv" encode "$dir/cap" -o "$dir/c420.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --chroma 420 -q 2>&1) || fail "encode --chroma 420: $out"
"$fvv" info "$dir/c420.fvv" | grep -q "format version 11" || fail "chroma 420 format version: $("$fvv" info "$dir/c420.fvv" | head -1)"
"$fvv" info "$dir/c420.fvv" | grep -q "chroma-420.*chroma-bilinear" || fail "chroma 420 tools: $("$fvv" info "$dir/c420.fvv" | grep tools)"
out=$("$fvv" encode "$dir/cap" -o "$dir/c420n.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --whole-texture --model-floats --chroma 420-nearest -q 2>&1) || fail "encode --chroma 420-nearest: $out"
"$fvv" info "$dir/c420n.fvv" | grep -q "format version 7" || fail "chroma 420-nearest format version: $("$fvv" info "$dir/c420n.fvv" | head -1)"
"$fvv" info "$dir/c420n.fvv" | grep -q "chroma-bilinear" && fail "chroma 420-nearest tools: $("$fvv" info "$dir/c420n.fvv" | grep tools)"
"$fvv" info "$dir/b.fvv" | grep -q "sample-precision" || fail "default tools: $("$fvv" info "$dir/b.fvv" | grep tools)"
out=$("$fvv" encode "$dir/cap" -o "$dir/v6.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --whole-texture --model-floats --sample-bits 0 -q 2>&1) || fail "encode --sample-bits 0: $out"
"$fvv" info "$dir/v6.fvv" | grep -q "format version 6" || fail "sample-bits 0 format version: $("$fvv" info "$dir/v6.fvv" | head -1)"
"$fvv" info "$dir/v6.fvv" | grep -q "sample-precision" && fail "sample-bits 0 tools: $("$fvv" info "$dir/v6.fvv" | grep tools)"
out=$("$fvv" encode "$dir/cap" -o "$dir/bad.fvv" --atlas 128 --textures "$dir/tex" --sample-bits 5 2>&1) &&
  fail "--sample-bits 5 accepted"
grep -q "sample-bits" <<<"$out" || fail "--sample-bits 5 message: $out"
"$fvv" info "$dir/b.fvv" | grep -q "spiht-arith3" || fail "default tools: $("$fvv" info "$dir/b.fvv" | grep tools)"
"$fvv" info "$dir/b.fvv" | grep -q "own-band-weights" || fail "default tools: $("$fvv" info "$dir/b.fvv" | grep tools)"
out=$("$fvv" encode "$dir/cap" -o "$dir/v5.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --whole-texture --model-floats --weights axis -q 2>&1) || fail "encode --weights axis: $out"
"$fvv" info "$dir/v5.fvv" | grep -q "format version 5" || fail "weights axis format version: $("$fvv" info "$dir/v5.fvv" | head -1)"
"$fvv" info "$dir/v5.fvv" | grep -q "own-band-weights" && fail "weights axis tools: $("$fvv" info "$dir/v5.fvv" | grep tools)"
out=$("$fvv" encode "$dir/cap" -o "$dir/v4.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --whole-texture --model-floats --weights axis --coder arith2 -q 2>&1) || fail "encode --coder arith2: $out"
"$fvv" info "$dir/v4.fvv" | grep -q "format version 4" || fail "coder arith2 format version: $("$fvv" info "$dir/v4.fvv" | head -1)"
"$fvv" info "$dir/v4.fvv" | grep -q "spiht-arith2" || fail "coder arith2 tools: $("$fvv" info "$dir/v4.fvv" | grep tools)"
out=$("$fvv" encode "$dir/cap" -o "$dir/v3.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --whole-texture --model-floats --weights axis --coder arith -q 2>&1) || fail "encode --coder arith: $out"
"$fvv" info "$dir/v3.fvv" | grep -q "format version 3" || fail "coder arith format version: $("$fvv" info "$dir/v3.fvv" | head -1)"
out=$("$fvv" encode "$dir/cap" -o "$dir/v1.fvv" --atlas 128 --gop-frames 2 --textures "$dir/tex" \
  --whole-texture --model-floats --weights axis --coder arith --precision 2 --mask-coder context -q 2>&1) || fail "encode --precision 2: $out"
"$fvv" info "$dir/v1.fvv" | grep -q "format version 1" || fail "precision 2 format version: $("$fvv" info "$dir/v1.fvv" | head -1)"
"$fvv" decode "$dir/v1.fvv" -o "$dir/v1dec" >/dev/null 2>&1 || fail "decode of the version 1 stream"

# The surface of every frame, and its pull to the previous frame reaching the
# surface tracker: the first frame has none to hold to, the later ones differ.
for t in 1 0; do
  out=$("$fvv" encode "$dir/cap" -o "$dir/s$t.fvv" --atlas 128 --gop-frames 2 --fixed-shape --poses "$dir/cap" \
    --surface --surface-temporal $t -q 2>&1) || fail "encode --surface --surface-temporal $t: $out"
  "$fvv" info "$dir/s$t.fvv" | grep -q "tools:.* surface" || fail "surface tool: $("$fvv" info "$dir/s$t.fvv" | grep tools)"
  "$fvv" decode "$dir/s$t.fvv" -o "$dir/s${t}_dec" --format conformance >/dev/null 2>&1 || fail "decode of the surface stream"
done
[ -s "$dir/s1_dec/surface_000002.bin" ] || fail "no surface in the conformance output: $(ls "$dir/s1_dec")"
cmp -s "$dir/s1_dec/surface_000002.bin" "$dir/s0_dec/surface_000002.bin" &&
  fail "--surface-temporal changed nothing"
out=$("$fvv" encode "$dir/cap" -o "$dir/x.fvv" --surface --surface-temporal -1 2>&1) &&
  fail "a negative --surface-temporal accepted"
grep -q "surface-temporal" <<<"$out" || fail "--surface-temporal -1 message: $out"

# Stereo on the surface: on a ring of 8 cameras (45 degrees apart, two
# neighbours near enough) it matches vertices, says how many, and moves the
# surface; refused out of range.
"$fvv" synth -o "$dir/cap8" --cameras 8 --width 320 --height 240 --frames 2 --held-out 0 \
  >/dev/null 2>&1 || fail "synth of 8 cameras"
for w in 3 0; do
  out=$("$fvv" encode "$dir/cap8" -o "$dir/st$w.fvv" --atlas 128 --gop-frames 2 --fixed-shape \
    --poses "$dir/cap8" --surface --surface-stereo $w --summary-json "$dir/st$w.json" 2>&1) ||
    fail "encode --surface --surface-stereo $w: $out"
  grep -q "stereo $w\( (matches\|,\)" <<<"$out" || fail "no stereo weight or share in the summary: $out"
  "$fvv" decode "$dir/st$w.fvv" -o "$dir/st${w}_dec" --format conformance >/dev/null 2>&1 ||
    fail "decode of the stereo surface stream"
done
share() { grep -o '"stereo_share": *[0-9.e+-]*' "$1" | grep -o '[0-9.e+-]*$'; }
awk -v s="$(share "$dir/st3.json")" 'BEGIN { exit !(s > 0.05) }' ||
  fail "stereo matched a share of $(share "$dir/st3.json")"
awk -v s="$(share "$dir/st0.json")" 'BEGIN { exit !(s == 0) }' ||
  fail "stereo without --surface-stereo: $(share "$dir/st0.json")"
cmp -s "$dir/st3_dec/surface_000001.bin" "$dir/st0_dec/surface_000001.bin" &&
  fail "--surface-stereo changed nothing"
out=$("$fvv" encode "$dir/cap8" -o "$dir/x.fvv" --surface --surface-stereo -1 2>&1) &&
  fail "a negative --surface-stereo accepted"
grep -q "surface-stereo" <<<"$out" || fail "--surface-stereo -1 message: $out"

# Bad input: clear errors, non-zero exits, nothing written.
out=$("$fvv" encode "$dir/nothing" -o "$dir/x.fvv" 2>&1) && fail "missing capture accepted"
grep -q "nothing" <<<"$out" || fail "missing capture error: $out"
out=$("$fvv" encode "$dir/cap" -o "$dir/x.fvv" --bpp 0.1 --psnr 30 2>&1) && fail "two rates accepted"
grep -q "at most one" <<<"$out" || fail "rate error: $out"
out=$("$fvv" encode "$dir/cap" -o "$dir/x.fvv" --poses "$dir/tex/cam00/mask_000000.png" 2>&1) &&
  fail "a PNG accepted as poses"
grep -q "not a JSON object" <<<"$out" || fail "poses error: $out"
out=$("$fvv" encode "$dir/cap" -o "$dir/x.fvv" --frames 7:9 2>&1) && fail "frames beyond the capture"
grep -q "no frames to encode" <<<"$out" || fail "frames error: $out"
[ ! -e "$dir/x.fvv" ] || fail "a failed encode left output"
ls "$dir"/x.fvv.part-* >/dev/null 2>&1 && fail "a failed encode left a temporary file"
"$fvv" encode --help | grep -q "save-textures" || fail "help"
echo "cli_encode: OK"
