#!/usr/bin/env bash
# tools/check_layers.py on the real tree (no include against the layers) and on
# small trees that break a layer, cross between siblings, or sit in no room.
set -euo pipefail
checker=$1
work=$2
python3 "$checker"

rm -rf "$work" && mkdir -p "$work"
make_tree() {
  local dir=$1 include=$2
  mkdir -p "$dir/codec/base" "$dir/encoder/track" "$dir/player/render"
  echo '#include "codec/base/status.h"' > "$dir/codec/base/status.h"
  printf '#include "codec/base/status.h"\n#include <vector>\n#include "%s"\n' "$include" \
    > "$dir/encoder/track/tracker.cc"
}
expect() {
  local want=$1 dir=$2 pattern=$3 rc=0
  python3 "$checker" --root "$dir" > "$dir.out" 2>&1 || rc=$?
  [ "$rc" -eq "$want" ] || { echo "exit $rc, expected $want:"; cat "$dir.out"; exit 1; }
  grep -q "$pattern" "$dir.out" || { echo "no '$pattern' in:"; cat "$dir.out"; exit 1; }
}
make_tree "$work/ok" "container/cameras.h"
expect 0 "$work/ok" "none against the layers"
make_tree "$work/up" "tools/fvv/frame_range.h"
expect 1 "$work/up" "encoder/track/tracker.cc:3: encoder/track includes tools/fvv/frame_range.h"
make_tree "$work/across" "player/render/renderer.h"
expect 1 "$work/across" "encoder/track includes player/render/renderer.h"
make_tree "$work/stray" "container/cameras.h"
mkdir -p "$work/stray/codec/../encoder/misc" && touch "$work/stray/encoder/misc/x.h"
expect 1 "$work/stray" "encoder/misc/x.h: in no room"
echo "check_layers: the tree passes; an arrow up, across and a file in no room fail"
