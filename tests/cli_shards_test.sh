#!/usr/bin/env bash
# End-to-end test of encoding in shards as docs/scale-out.md tells a studio to:
# fvv encode --prepare, the shards through each engine's script (GNU parallel
# for real with --sshlogin : standing in for hosts; the Slurm array script with
# the variables Slurm sets; the Kubernetes Indexed Job's own command line with
# the index Kubernetes sets), fvv join, each joined stream byte for byte the
# single run's. A missing part is named; a failed shard rerun alone joins.
# Then shards that track their own frames (a take prepared without poses).
set -u
fvv=$(readlink -f "$1")
dir=$2
src=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
py=/usr/bin/python3
[ -x $py ] || py=python3

"$fvv" synth -o "$dir/cap" --cameras 2 --width 160 --height 120 --frames 5 --held-out 0 --unlit \
  --noise 0 >/dev/null 2>&1 || fail "synth"
poses=$dir/cap/truth/truth.json
out=$("$fvv" encode "$dir/cap" --poses "$poses" --atlas 128 --gop-frames 2 --prepare "$dir/prep" \
  --prepare-frames 2 2>&1) || fail "prepare: $out"
for word in "prepared take" "frames 0..4 (5), 3 GOPs of 2 frames" "--shard K/N"; do
  grep -q -- "$word" <<<"$out" || fail "prepare output lacks '$word': $out"
done
[ -f "$dir/prep/prepared.json" ] && [ -f "$dir/prep/model.bin" ] && [ -f "$dir/prep/static.png" ] ||
  fail "prepared take incomplete"
# The atlas and GOP length come from the prepared take.
"$fvv" encode "$dir/cap" --poses "$poses" --prepared "$dir/prep" -q -o "$dir/single.fvv" \
  >/dev/null 2>&1 || fail "single run"

# GNU parallel, this machine as two hosts' worth of job slots.
out=$(FVV="$fvv" "$src/tools/scale-out/parallel_shards.sh" 2 2/: "$dir/cap" "$poses" "$dir/prep" \
  "$dir/parallel_parts" "$dir/parallel.fvv" 2>&1) || fail "parallel_shards.sh: $out"
cmp -s "$dir/single.fvv" "$dir/parallel.fvv" || fail "GNU parallel's joined stream differs"
[ -f "$dir/parallel_parts/part_0.fvv" ] && [ -f "$dir/parallel_parts/part_1.fvv" ] ||
  fail "parallel parts not named by shard"

# Slurm: an array 3..5 (indices need not start at 0); its tasks as Slurm runs them.
for id in 3 4 5; do
  SLURM_ARRAY_TASK_ID=$id SLURM_ARRAY_TASK_MIN=3 SLURM_ARRAY_TASK_COUNT=3 SLURM_CPUS_PER_TASK=1 \
    FVV="$fvv" "$src/tools/scale-out/slurm_array.sh" "$dir/cap" "$poses" "$dir/prep" \
    "$dir/slurm_parts" >/dev/null 2>&1 || fail "slurm task $id"
done
"$fvv" join "$dir"/slurm_parts/part_*.fvv -o "$dir/slurm.fvv" -q >/dev/null 2>&1 ||
  fail "join slurm parts"
cmp -s "$dir/single.fvv" "$dir/slurm.fvv" || fail "Slurm's joined stream differs"
out=$(FVV="$fvv" "$src/tools/scale-out/slurm_array.sh" "$dir/cap" "$poses" "$dir/prep" \
  "$dir/slurm_parts" 2>&1) && fail "the Slurm script ran outside an array task"
grep -q "not a Slurm array task" <<<"$out" || fail "Slurm script's message: $out"

# Kubernetes: the manifest parses as an Indexed Job whose completions are its
# shard count, and its container's command, run as the pods would (/take on
# this test's files, SHARDS set to 2), writes parts that join.
manifest=$src/tools/scale-out/indexed_job.yaml
cmd=$($py - "$manifest" <<'PY'
import sys, yaml
job = yaml.safe_load(open(sys.argv[1]))
assert job["apiVersion"] == "batch/v1" and job["kind"] == "Job", "not a batch/v1 Job"
spec = job["spec"]
assert spec["completionMode"] == "Indexed", "not an Indexed Job"
pod = spec["template"]["spec"]
assert pod["restartPolicy"] in ("Never", "OnFailure")
c = pod["containers"][0]
env = {e["name"]: e["value"] for e in c.get("env", [])}
assert int(env["SHARDS"]) == spec["completions"], "SHARDS is not completions"
assert spec["parallelism"] <= spec["completions"]
script = c["command"][-1]
assert "$JOB_COMPLETION_INDEX/$SHARDS" in script, "the shard is not the completion index"
mounts = {m["mountPath"] for m in c["volumeMounts"]}
assert "/take" in mounts
print(script)
PY
) || fail "the Kubernetes manifest: $cmd"
mkdir -p "$dir/take"
ln -s "$dir/cap" "$dir/take/capture"
ln -s "$poses" "$dir/take/poses.json"
ln -s "$dir/prep" "$dir/take/prepared"
mkdir -p "$dir/bin" && ln -s "$fvv" "$dir/bin/fvv"
for index in 0 1; do
  JOB_COMPLETION_INDEX=$index SHARDS=2 PATH="$dir/bin:$PATH" sh -c "${cmd//\/take/$dir/take}" \
    >/dev/null 2>&1 || fail "the manifest's command, index $index"
done
"$fvv" join "$dir"/take/parts/part_*.fvv -o "$dir/k8s.fvv" -q >/dev/null 2>&1 || fail "join k8s parts"
# The stream's metadata names the capture as the command gave it: the pods' path.
"$fvv" encode "$dir/take/capture" --poses "$poses" --prepared "$dir/prep" -q -o "$dir/single_k8s.fvv" \
  >/dev/null 2>&1 || fail "single run on the pods' paths"
cmp -s "$dir/single_k8s.fvv" "$dir/k8s.fvv" || fail "the Indexed Job's joined stream differs"

# A missing part is named; the shard rerun alone completes the join.
rm "$dir/slurm_parts/part_1.fvv"
out=$("$fvv" join "$dir"/slurm_parts/part_*.fvv -o "$dir/partial.fvv" 2>&1) &&
  fail "joined without part 1"
grep -q "part 1 of 3 is missing" <<<"$out" || fail "missing part message: $out"
[ ! -e "$dir/partial.fvv" ] || fail "a refused join left an output"
"$fvv" encode "$dir/cap" --poses "$poses" --prepared "$dir/prep" --shard 1/3 -q \
  -o "$dir/slurm_parts/part_1.fvv" >/dev/null 2>&1 || fail "rerun shard 1"
"$fvv" join "$dir"/slurm_parts/part_*.fvv -o "$dir/rerun.fvv" -q >/dev/null 2>&1 || fail "rejoin"
cmp -s "$dir/single.fvv" "$dir/rerun.fvv" || fail "the rerun's joined stream differs"

out=$("$fvv" encode "$dir/cap" --poses "$poses" --shard 0/2 -o "$dir/x.fvv" 2>&1) &&
  fail "a shard without a prepared take"
grep -q -- "--shard needs --prepared" <<<"$out" || fail "message: $out"
out=$("$fvv" encode "$dir/cap" --poses "$poses" --prepared "$dir/prep" --shard 2of3 -o "$dir/x.fvv" 2>&1) &&
  fail "--shard 2of3"
grep -q "is not K/N" <<<"$out" || fail "message: $out"

# Shards that track their own frames: a take prepared without poses, the
# shards through the GNU parallel script with POSES "-", the join.
out=$("$fvv" encode "$dir/cap" --atlas 128 --gop-frames 2 --prepare "$dir/tprep" --prepare-frames 2 \
  --warm-up 2 2>&1) || fail "prepare without poses: $out"
grep -q "shards track their own frames, with 2 frames' warm-up" <<<"$out" || fail "prepare: $out"
grep -q '"shards_track": true' "$dir/tprep/prepared.json" || fail "prepared.json: shards_track"
# On this small take (2 cameras at 160x120) a shard's first-frame search loses
# the actor: the join names the shard, and the script's join step encodes it
# again going on from the part before it (--after), then joins.
out=$(FVV="$fvv" "$src/tools/scale-out/parallel_shards.sh" 3 2/: "$dir/cap" - "$dir/tprep" \
  "$dir/tracked_parts" "$dir/tracked.fvv" 2>&1) || fail "parallel_shards.sh, tracking: $out"
# (Here it is shard 2, whose search starts at frame 2; the join below passing is what counts.)
if grep -q "join_parts: shard" <<<"$out"; then
  grep -Eq "join_parts: shard [12] disagrees with the part before it; encoding it again after" \
    <<<"$out" || fail "join_parts' message: $out"
fi
# --after goes on from the part just before, no other.
out=$("$fvv" encode "$dir/cap" --prepared "$dir/tprep" --shard 2/3 --after \
  "$dir/tracked_parts/part_0.fvv" -o "$dir/x.fvv" 2>&1) && fail "--after a part not just before"
grep -q "is part 0 of 3, not part 1 of 3 (the part just before shard 2)" <<<"$out" || fail "--after message: $out"
out=$("$fvv" info "$dir/tracked.fvv" 2>&1) || fail "the tracked shards' joined stream: $out"
grep -Eq "frames: 5\b|5 frames" <<<"$out" || fail "joined stream's frames: $out"
# fvv track shows what a shard tracks: its frames, reported, and the warm-up around them.
out=$("$fvv" track "$dir/cap" --prepared "$dir/tprep" --shard 1/3 -q -o "$dir/shard1.json" 2>&1) ||
  fail "fvv track --prepared --shard: $out"
grep -q "tracked frames 2..3" <<<"$out" && grep -q "warm-up: 3 frames" <<<"$out" ||
  fail "fvv track --shard 1/3: $out"
[ "$($py -c 'import json,sys; print([f["frame"] for f in json.load(open(sys.argv[1]))["frames"]])' \
  "$dir/shard1.json")" = "[2, 3]" ] || fail "shard1.json frames"
refused() {  # refused "what it says" command...
  local says=$1
  shift
  out=$("$@" 2>&1) && fail "accepted: $*"
  grep -q -- "$says" <<<"$out" || fail "message of $*: $out"
}
refused "leave out --poses" "$fvv" encode "$dir/cap" --poses "$poses" --prepared "$dir/tprep" \
  --shard 0/3 -o "$dir/x.fvv"
refused "--warm-up belongs to --prepare without --poses" "$fvv" encode "$dir/cap" --poses "$poses" \
  --prepare "$dir/x_prep" --warm-up 4
refused "--shard needs --prepared" "$fvv" track "$dir/cap" --shard 0/2 -o "$dir/x.json"
refused "was prepared with poses" "$fvv" track "$dir/cap" --prepared "$dir/prep" -o "$dir/x.json"
echo "PASS"
