#!/usr/bin/env bash
# The real-footage benchmark (bench/README.md): imports the real capture's
# Qualisys calibration and videos, brings the cameras in step (fvv capture
# sync), optionally refines the calibration from the frames after the scored
# ones (fvv capture refine-calib), then runs build/bench/real_bench on it
# (leave one camera out: tracking, Renderer II and Renderer I on the held-out
# view).
#
# Usage: bench/run_real_bench.sh [FRAMES A:B] [RENDER_FRAMES N] [--refine[=FROM]] [--strict]
#                               [--surface] [--no-colour] [--take=DIR] [--out=DIR]
#   --take=DIR          the take to run (default ../shared/data/real/pose2sim_single): its
#                       calibration in DIR/calibration (every *.qca.txt, *.toml, *.yml and
#                       *.yaml there, read together by fvv capture import-calib), and one video
#                       per camera in DIR/videos or one folder of numbered PNG or JPEG images
#                       per camera in DIR/images, named as the calibration names the camera
#                       (bench/take_layout.py)
#   --fps=R             the take's frame rate, where its frames do not say (images: 25 unless
#                       given; it sets the streams' playback rate, not the scores)
#   --out=DIR           where the results go (default out/real_bench for the default take,
#                       out/real_bench_NAME for a take in a directory NAME)
#   --refine            camera poses from the keypoints (refine-calib --from keypoints)
#   --refine=silhouettes  camera orientations from the tracked actor's outlines
#   --refine=tangents   the frame offsets checked again and the camera orientations refined
#                       from the tangents of the actor's person masks (sync and refine-calib
#                       --from tangents; no body model)
#   --strict            the held-out camera as imported, the other cameras refined among
#                       themselves, once per held-out camera (without it: the "studio"
#                       protocol, every camera refined together, as a studio would before a
#                       shoot). Either way the refinement reads the 68 frames after B only:
#                       no scored frame shapes the calibration.
#   --surface           encode with the surface of every frame (fvv encode --surface)
#   --no-colour         with --refine: the cameras' colour gains left out (without it the
#                       refined cameras' gains come from the same frames, fvv capture
#                       calibrate-colour, and the held-out camera's response is applied to the
#                       renders it is scored against)
# Needs the person models (tools/setup.sh fetches them) and a Release build in build/.
set -euo pipefail
# Paths given on the command line are read from where the script is run.
here=$PWD
absolute() { case $1 in /*) echo "$1" ;; *) echo "$here/$1" ;; esac; }
cd "$(dirname "$0")/.."
default_take=../shared/data/real/pose2sim_single
real=$default_take
out=""
fps=()
refine=""
strict=0
colour=1
args=()
bench_args=()
for a in "$@"; do
  case $a in
    --refine) refine=keypoints ;;
    --refine=*) refine=${a#--refine=} ;;
    --strict) strict=1 ;;
    --surface) bench_args+=(--surface) ;;
    --no-colour) colour=0 ;;
    --take=*) real=$(absolute "${a#--take=}") ;;
    --out=*) out=$(absolute "${a#--out=}") ;;
    --fps=*) fps=(--fps "${a#--fps=}") ;;
    --*) echo "run_real_bench: unknown option $a (see the usage at the top of $0)" >&2; exit 2 ;;
    *) args+=("$a") ;;
  esac
done
case $refine in
  "" | keypoints | silhouettes | tangents) ;;
  *) echo "run_real_bench: --refine=keypoints, silhouettes or tangents, not $refine" >&2; exit 2 ;;
esac
if [ $strict = 1 ] && [ -z "$refine" ]; then
  echo "run_real_bench: --strict needs --refine (as imported, every protocol is the same)" >&2
  exit 2
fi
if [ ! -d "$real" ]; then
  echo "run_real_bench: no take at $real (the default's is described in ../shared/data/README.md)" >&2
  exit 1
fi
real=$(cd "$real" && pwd)
if [ -z "$out" ]; then
  if [ "$real" = "$(cd "$default_take" 2>/dev/null && pwd)" ]; then
    out=out/real_bench
  else
    out=out/real_bench_$(basename "$real")
  fi
fi
# The calibration files, then the videos' or the images' pattern.
layout=$(python3 bench/take_layout.py "$real") || exit 1
mapfile -t import_args <<<"$layout"
frames=${args[0]:-0:29}
render_frames=${args[1]:-30}
last=${frames#*:}
fvv=build/tools/fvv/fvv
mkdir -p "$out/capture"
# The up axis comes from the format (Qualisys: z) or from the cameras.
$fvv capture import-calib "${import_args[@]}" "${fps[@]}" -o "$out/capture"
# The cameras were not started together: skip each one's early frames.
$fvv capture sync "$out/capture" --write
# The refinement reads the 68 frames after the scored ones, or as many as the take has after
# them (at least 24).
count=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["frame_count"])' \
  "$out/capture/capture.json")
if [ "$count" -le "$last" ]; then
  echo "run_real_bench: frames $frames reach beyond the take's $count frames in step" >&2
  exit 1
fi
end=$((last + 68 < count - 1 ? last + 68 : count - 1))
span="$((last + 1)):$end"
if [ -n "$refine" ] && [ $((end - last)) -lt 24 ]; then
  echo "run_real_bench: --refine reads the frames after $frames, and the take has $((end - last))" \
    "of them in step (24 at least); score earlier frames" >&2
  exit 1
fi
# The keypoints can leave a camera a frame or two off; the masks' tangents,
# from the frames after the scored ones, check each offset again.
if [ "$refine" = tangents ]; then
  $fvv capture sync "$out/capture" --from tangents --write \
    --frames "$((last + 3)):$((last + 64 < count - 1 ? last + 64 : count - 1))"
fi
if [ $strict = 0 ]; then
  if [ -n "$refine" ]; then
    $fvv capture refine-calib "$out/capture" --from "$refine" --frames "$span" --write
    if [ $colour = 1 ]; then
      $fvv capture calibrate-colour "$out/capture" --frames "$span" --write -q
    fi
  fi
  build/bench/real_bench "$out/capture" --frames "$frames" --render-frames "$render_frames" \
    --out "$out" --fvv $fvv "${bench_args[@]}"
  exit 0
fi
# Strict: per held-out camera, a capture of its own whose other cameras are
# refined among themselves.
names=$(python3 -c 'import json,sys; print(" ".join(c["name"] for c in json.load(open(sys.argv[1]))["cameras"]))' \
  "$out/capture/capture.json")
for held in $names; do
  dir="$out/strict_$held"
  mkdir -p "$dir/capture"
  cp "$out/capture/capture.json" "$dir/capture/"
  others=$(tr ' ' '\n' <<<"$names" | grep -vx "$held" | paste -sd, -)
  echo "== $held held out: $others refined among themselves"
  $fvv capture refine-calib "$dir/capture" --from "$refine" --cameras "$others" --frames "$span" \
    --write
  if [ $colour = 1 ]; then
    $fvv capture calibrate-colour "$dir/capture" --cameras "$others" --frames "$span" --write -q
  fi
  build/bench/real_bench "$dir/capture" --frames "$frames" --render-frames "$render_frames" \
    --out "$dir" --fvv $fvv --held-out "$held" "${bench_args[@]}"
done
python3 - "$out" $names <<'EOF'
import json, sys
out, names = sys.argv[1], sys.argv[2:]
keys = ["held_out_iou", "held_out_joint_px", "own_iou", "renderer2_iou", "renderer2_psnr",
        "renderer2_psnr_both_cover", "renderer1_psnr"]
rows = []
for n in names:
    for c in json.load(open(f"{out}/strict_{n}/real_bench.json"))["cameras"]:
        if c["camera"] == n:
            rows.append(c)
print("strict protocol: each camera held out as imported, the others refined among themselves")
labels = ["IoU held out", "joints (px)", "IoU used", "IoU rendered", "R. II (dB)", "both cover",
          "R. I (dB)"]
print("%-10s" % "held out" + "".join("%14s" % k for k in labels))
for r in rows:
    print("%-10s" % r["camera"] + "".join("%14.3f" % r[k] for k in keys))
print("%-10s" % "mean" + "".join("%14.3f" % (sum(r[k] for r in rows) / len(rows)) for k in keys))
json.dump({"protocol": "strict", "cameras": rows}, open(f"{out}/real_bench_strict.json", "w"), indent=1)
EOF
