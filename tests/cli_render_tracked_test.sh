#!/usr/bin/env bash
# `fvv render CAPTURE --renderer projective` without --poses tracks the capture
# first and renders the frames it asked for from the tracked poses.
set -u
fvv=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$fvv" synth -o "$dir/cap" --cameras 4 --width 320 --height 240 --frames 3 >/dev/null 2>&1 ||
  fail "synth"
out=$("$fvv" render "$dir/cap" --renderer projective -o "$dir/r1t" --size 96x64 --last 1 2>&1) ||
  fail "render --renderer projective (tracked): $out"
grep -q "tracking the capture first" <<<"$out" && grep -q "rendered frames 0..1" <<<"$out" ||
  fail "tracked Renderer I report: $out"
[ "$(ls "$dir"/r1t/render_f*.png | wc -l)" = 2 ] || fail "tracked Renderer I wrote $(ls "$dir"/r1t)"
[ "$(ffprobe -v error -show_entries stream=width,height -of csv=p=0 "$dir/r1t/render_f00001.png")" = "96,64" ] ||
  fail "render size"
echo "cli render tracked: ok"
