#!/usr/bin/env bash
# The web player in headless chromium (tests/web_player_test.mjs): sample
# streams with the texture in chunks (with masks; without, so that visibility
# comes from depth maps; with masks and the surface of every frame), a
# synthetic actor's stream of the generic body without masks (whose depth maps
# both players draw from the simplified body), fvv render's stills of them
# from a fixed view, and
# the faulty streams the page must report: damaged (a byte flipped inside a
# texture chunk), cut (the last fragment half gone).
# Usage: web_player_test.sh FVV SITE_DIR WORK_DIR
set -euo pipefail
fvv=$1 site=$2 dir=$3
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$dir" && mkdir -p "$dir"
common=(--frames 24 --cameras 4 --atlas 128 128 --gop 8 1 --bpp 2 --texture-chunks)
"$fvv" sample -o "$dir/masks.fvv" "${common[@]}" >/dev/null
"$fvv" sample -o "$dir/depth.fvv" "${common[@]}" --no-masks >/dev/null
"$fvv" sample -o "$dir/surface.fvv" "${common[@]}" --surface >/dev/null
"$fvv" synth -o "$dir/body" --cameras 3 --width 160 --height 120 --frames 6 >/dev/null
"$fvv" encode "$dir/body" -o "$dir/body.fvv" --poses "$dir/body" --atlas 128 -q >/dev/null
cat >"$dir/path.json" <<'JSON'
{"keyframes": [{"frame": 0, "eye": [1.6, 1.3, 2.6], "target": [0, 0.9, 0], "fov": 40}]}
JSON
for kind in masks depth surface body; do
  "$fvv" render "$dir/$kind.fvv" --path "$dir/path.json" --first 5 --last 5 --size 640x480 \
    -o "$dir/native_$kind" >/dev/null
  cp "$dir/native_$kind/render_f00005.png" "$dir/native_$kind.png"
done
"$fvv" render "$dir/depth.fvv" --path "$dir/path.json" --first 5 --last 5 --size 640x480 \
  --bytes 600 -o "$dir/native_depth_600" >/dev/null
cp "$dir/native_depth_600/render_f00005.png" "$dir/native_depth_600.png"
cp "$here/../conformance/cases/live/stream.fvv" "$dir/live.fvv"  # no index
cp "$dir/depth.fvv" "$dir/dropped.fvv"
cp "$dir/depth.fvv" "$dir/whole.fvv"
# Damaged: a byte well inside the first fragment's chunks; cut: the last 40 % gone.
first_frag=$("$fvv" info "$dir/depth.fvv" | grep -o 'frag@[0-9]*([0-9]*)' | head -1 | tr '@()' '   ')
read -r _ offset size <<<"$first_frag"
cp "$dir/depth.fvv" "$dir/damaged.fvv"
at=$((offset + size / 2))
printf '\xA5' | dd of="$dir/damaged.fvv" bs=1 seek="$at" conv=notrunc status=none
total=$(stat -c %s "$dir/depth.fvv")
head -c $((total * 6 / 10)) "$dir/depth.fvv" >"$dir/cut.fvv"
: >"$dir/empty.fvv"
node "$here/web_player_test.mjs" "$site" "$dir"
