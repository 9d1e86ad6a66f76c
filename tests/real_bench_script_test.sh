#!/usr/bin/env bash
# bench/run_real_bench.sh refuses what it cannot run before it starts any
# work: a take that is not there, one without a calibration or frames, an
# unknown option, --strict without --refine; and bench/take_layout.py reads a
# take's layout (videos, or numbered images) as import-calib arguments. (The
# runs themselves need the real take and the person models: bench/README.md.)
set -u
script=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
expect() {  # expect CODE MESSAGE ARGS...: the script exits with CODE, saying MESSAGE
  local code=$1 message=$2
  shift 2
  local out rc
  out=$(cd "$dir" && "$script" "$@" 2>&1)
  rc=$?
  [ "$rc" = "$code" ] || fail "$* exited $rc, not $code: $out"
  grep -qF -- "$message" <<<"$out" || fail "$*: no \"$message\" in: $out"
}

expect 1 "no take at $dir/nowhere" --take="$dir/nowhere"
# A relative --take is read from where the script is run, not from the repository.
expect 1 "no take at $dir/nowhere" --take=nowhere
mkdir -p "$dir/take/calibration" "$dir/take/videos"
expect 1 "no calibration in $dir/take/calibration" --take=take
touch "$dir/take/calibration/Calib.toml"
expect 1 "no frames in $dir/take: one video per camera in videos/" --take=take
touch "$dir/take/videos/cam01.mp4"
expect 2 "unknown option --bogus" --take=take --bogus
expect 2 "--strict needs --refine" --take=take --strict
expect 2 "--refine=keypoints, silhouettes or tangents, not outlines" --take=take --refine=outlines
[ ! -e "$dir/out" ] && [ ! -e "$dir/take/out" ] || fail "a refused run left output behind"

layout="$(dirname "$script")/take_layout.py"
expect_layout() {  # expect_layout TAKE LINES...: take_layout.py prints these lines
  local take=$1 out
  shift
  out=$(python3 "$layout" "$take" 2>&1) || fail "take_layout $take: $out"
  [ "$out" = "$(printf '%s\n' "$@")" ] || fail "take_layout $take: $out"
}
expect_layout "$dir/take" "$dir/take/calibration/Calib.toml" --video "$dir/take/videos/{camera}.mp4"
# Images: the numbering's width and first number from the first camera's images.
mkdir -p "$dir/padded/calibration" "$dir/padded/images/cam01" "$dir/padded/images/cam02"
touch "$dir/padded/calibration/intri.yml" "$dir/padded/calibration/extri.yml"
touch "$dir/padded/images/cam01/frame_0008.jpg" "$dir/padded/images/cam01/frame_0011.jpg"
expect_layout "$dir/padded" "$dir/padded/calibration/extri.yml" "$dir/padded/calibration/intri.yml" \
  --images "$dir/padded/images/{camera}/frame_%04d.jpg" --first 8
mkdir -p "$dir/grown/calibration" "$dir/grown/images/a"
touch "$dir/grown/calibration/rig.toml" "$dir/grown/images/a/img9.PNG" "$dir/grown/images/a/img10.PNG"
expect_layout "$dir/grown" "$dir/grown/calibration/rig.toml" \
  --images "$dir/grown/images/{camera}/img%d.PNG" --first 9
touch "$dir/grown/images/a/img011.PNG"
out=$(python3 "$layout" "$dir/grown" 2>&1) && fail "images of two widths accepted: $out"
grep -q "numbered with more than one width" <<<"$out" || fail "two widths message: $out"
mkdir -p "$dir/none/calibration" "$dir/none/images/a"
touch "$dir/none/calibration/rig.toml" "$dir/none/images/a/notes.txt"
out=$(python3 "$layout" "$dir/none" 2>&1) && fail "a camera folder without images accepted: $out"
grep -q "no numbered images (PNG or JPEG) in $dir/none/images/a" <<<"$out" || fail "no images message: $out"
echo "run_real_bench.sh: every refusal checked"
