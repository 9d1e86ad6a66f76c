#!/usr/bin/env bash
# bench/run_real_bench.sh refuses what it cannot run before it starts any
# work: a take that is not there, one without a calibration or videos, an
# unknown option, --strict without --refine. (The runs themselves need the
# real take and the person models: bench/README.md.)
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
expect 1 "no videos in $dir/take/videos" --take=take
touch "$dir/take/videos/cam01.mp4"
expect 2 "unknown option --bogus" --take=take --bogus
expect 2 "--strict needs --refine" --take=take --strict
expect 2 "--refine=keypoints, silhouettes or tangents, not outlines" --take=take --refine=outlines
[ ! -e "$dir/out" ] && [ ! -e "$dir/take/out" ] || fail "a refused run left output behind"
echo "run_real_bench.sh: every refusal checked"
