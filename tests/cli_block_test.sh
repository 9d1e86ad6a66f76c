#!/usr/bin/env bash
# End-to-end test of `fvv block`: exit codes, outputs and error messages.
set -u
fvv=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$fvv" block sample -o "$dir/in" --frames 2 --cameras 3 --width 40 --height 24 >/dev/null || fail "sample"
[ "$(ls "$dir"/in/view_*.png | wc -l)" = 6 ] || fail "sample wrote $(ls "$dir"/in | wc -l) files"

out=$("$fvv" block encode "$dir"/in/view_*.png --cameras 3 --mask "$dir"/in/mask_*.png -o "$dir/b.fvb" --bpp 1 2>&1) ||
  fail "encode: $out"
grep -q "PSNR over used texels" <<<"$out" || fail "encode report: $out"
out=$("$fvv" block decode "$dir/b.fvb" -o "$dir/dec" 2>&1) || fail "decode: $out"
grep -q "complete" <<<"$out" || fail "decode report: $out"
[ "$(ls "$dir"/dec/view_*.png | wc -l)" = 6 ] || fail "decode wrote the wrong number of views"
out=$("$fvv" block decode "$dir/b.fvb" -o "$dir/dec2" --bytes 100 2>&1) || fail "truncated decode: $out"
grep -q "truncated" <<<"$out" || fail "truncated decode report: $out"

# The defaults (3 fractional sample bits, own-band weights, coder arith3, 9/7
# precision 5) write block file version 6; --sample-bits 0 writes version 5,
# --weights axis version 4, with --coder arith2 version 3,
# --coder arith version 2 and --precision 2 with it version 1 (what older
# decoders read); --coder arith4 writes version 7; all decode, and 7 is
# refused by name.
version_of() { od -An -tu1 -j4 -N1 "$1" | tr -d ' '; }
[ "$(version_of "$dir/b.fvb")" = 6 ] || fail "defaults wrote version $(version_of "$dir/b.fvb")"
"$fvv" block encode "$dir"/in/view_*.png --cameras 3 --sample-bits 0 -o "$dir/s0.fvb" --bpp 1 >/dev/null 2>&1 ||
  fail "sample-bits 0 encode"
[ "$(version_of "$dir/s0.fvb")" = 5 ] || fail "sample-bits 0 wrote version $(version_of "$dir/s0.fvb")"
out=$("$fvv" block decode "$dir/s0.fvb" -o "$dir/s0dec" 2>&1) || fail "sample-bits 0 decode: $out"
"$fvv" block encode "$dir"/in/view_*.png --cameras 3 --weights axis -o "$dir/a3.fvb" --bpp 1 >/dev/null 2>&1 ||
  fail "weights axis encode"
[ "$(version_of "$dir/a3.fvb")" = 4 ] || fail "weights axis wrote version $(version_of "$dir/a3.fvb")"
out=$("$fvv" block decode "$dir/a3.fvb" -o "$dir/a3dec" 2>&1) || fail "weights axis decode: $out"
"$fvv" block encode "$dir"/in/view_*.png --cameras 3 --weights axis --coder arith2 -o "$dir/a2.fvb" --bpp 1 >/dev/null 2>&1 ||
  fail "coder arith2 encode"
[ "$(version_of "$dir/a2.fvb")" = 3 ] || fail "coder arith2 wrote version $(version_of "$dir/a2.fvb")"
out=$("$fvv" block decode "$dir/a2.fvb" -o "$dir/a2dec" 2>&1) || fail "coder arith2 decode: $out"
"$fvv" block encode "$dir"/in/view_*.png --cameras 3 --weights axis --coder arith -o "$dir/a1.fvb" --bpp 1 >/dev/null 2>&1 ||
  fail "coder arith encode"
[ "$(version_of "$dir/a1.fvb")" = 2 ] || fail "coder arith wrote version $(version_of "$dir/a1.fvb")"
out=$("$fvv" block decode "$dir/a1.fvb" -o "$dir/a1dec" 2>&1) || fail "coder arith decode: $out"
"$fvv" block encode "$dir"/in/view_*.png --cameras 3 --weights axis --coder arith --precision 2 -o "$dir/p2.fvb" --bpp 1 >/dev/null 2>&1 ||
  fail "precision 2 encode"
[ "$(version_of "$dir/p2.fvb")" = 1 ] || fail "precision 2 wrote version $(version_of "$dir/p2.fvb")"
out=$("$fvv" block decode "$dir/p2.fvb" -o "$dir/p2dec" 2>&1) || fail "precision 2 decode: $out"
"$fvv" block encode "$dir"/in/view_*.png --cameras 3 --coder arith4 -o "$dir/a4.fvb" --bpp 1 >/dev/null 2>&1 ||
  fail "coder arith4 encode"
[ "$(version_of "$dir/a4.fvb")" = 7 ] || fail "coder arith4 wrote version $(version_of "$dir/a4.fvb")"
out=$("$fvv" block decode "$dir/a4.fvb" -o "$dir/a4dec" 2>&1) || fail "coder arith4 decode: $out"
grep -q "RGB" <<<"$out" || ls "$dir"/a4dec/*.png >/dev/null || fail "coder arith4 wrote no images"
out=$("$fvv" block encode "$dir"/in/view_*.png --cameras 3 --weights level -o "$dir/wl.fvb" 2>&1) &&
  fail "weights level accepted"
grep -q -- "--weights" <<<"$out" || fail "weights level message: $out"
out=$("$fvv" block encode "$dir"/in/view_*.png --cameras 3 --precision 7 -o "$dir/p7.fvb" 2>&1) &&
  fail "precision 7 accepted"
grep -q -- "--precision" <<<"$out" || fail "precision 7 message: $out"
[ ! -e "$dir/p7.fvb" ] || fail "refused precision left a file"

# Lossless really is.
"$fvv" block encode "$dir"/in/view_*.png --cameras 3 --lossless -o "$dir/l.fvb" >/dev/null 2>&1 || fail "lossless encode"
"$fvv" block decode "$dir/l.fvb" -o "$dir/ldec" >/dev/null || fail "lossless decode"
out=$("$fvv" block encode "$dir"/ldec/view_*.png --cameras 3 --lossless -o "$dir/l2.fvb" 2>&1) || fail "re-encode"
grep -q "RGB 99.00 dB" <<<"$out" || fail "lossless re-encode not exact: $out"

# Errors: clear message, non-zero exit, nothing written.
out=$("$fvv" block encode "$dir"/in/view_*.png --cameras 4 -o "$dir/x.fvb" 2>&1) && fail "bad shape accepted"
grep -q "cannot form" <<<"$out" || fail "bad shape message: $out"
printf 'garbage' >"$dir/bad.fvb"
out=$("$fvv" block decode "$dir/bad.fvb" -o "$dir/xdec" 2>&1) && fail "garbage accepted"
grep -q "not an fvv block file" <<<"$out" || fail "garbage message: $out"
head -c 60 "$dir/b.fvb" >"$dir/cut.fvb"
out=$("$fvv" block decode "$dir/cut.fvb" -o "$dir/xdec" 2>&1) && fail "truncated file accepted"
grep -q "truncated" <<<"$out" || fail "truncated file message: $out"
# The header's shape decides the memory: a block above --max-samples is refused
# before anything is allocated for it (the default takes 2^27 samples).
out=$("$fvv" block decode "$dir/b.fvb" -o "$dir/ydec" --max-samples 5000 2>&1) && fail "a block above --max-samples decoded"
grep -q "2x3x24x40 (frames x cameras x height x width), 5760 samples, is above --max-samples 5000" <<<"$out" || fail "max-samples message: $out"
[ ! -e "$dir/ydec" ] || fail "a refused decode made its output directory"
[ ! -e "$dir/x.fvb" ] || fail "failed encode left a file"
echo "cli_block: all checks passed"
