#!/usr/bin/env bash
# The real-footage benchmark (bench/README.md): imports the real capture's
# Qualisys calibration and videos, brings the cameras in step (fvv capture
# sync), with --refine refines the camera poses from the keypoints of later
# frames (fvv capture refine-calib), then runs build/bench/real_bench on it
# (leave one camera out: tracking, Renderer II and Renderer I on the held-out
# view). Usage: bench/run_real_bench.sh [FRAMES A:B] [RENDER_FRAMES N] [--refine]
# Needs the person models (tools/setup.sh fetches them) and a Release build in build/.
set -euo pipefail
cd "$(dirname "$0")/.."
real=../shared/data/real/pose2sim_single
if [ ! -d "$real" ]; then
  echo "run_real_bench: no real capture at $real (see ../shared/data/README.md)" >&2
  exit 1
fi
refine=0
args=()
for a in "$@"; do
  case $a in
    --refine) refine=1 ;;
    *) args+=("$a") ;;
  esac
done
frames=${args[0]:-0:29}
render_frames=${args[1]:-4}
out=out/real_bench
mkdir -p "$out/capture"
build/tools/fvv/fvv capture import-calib "$real/calibration/Calib.qca.txt" -o "$out/capture" \
  --video "$(cd "$real/videos" && pwd)/{camera}.mp4"
# The cameras were not started together: skip each one's early frames.
build/tools/fvv/fvv capture sync "$out/capture" --write
# With --refine, the camera poses refined from the keypoints of the 68 frames
# after the scored ones: no keypoint of a scored frame shapes the calibration,
# but the held-out camera's keypoints of the later frames do (docs/tracking.md:
# not a held-out figure in the strict sense).
if [ $refine = 1 ]; then
  last=${frames#*:}
  build/tools/fvv/fvv capture refine-calib "$out/capture" --frames "$((last + 1)):$((last + 68))" \
    --write
fi
build/bench/real_bench "$out/capture" --frames "$frames" --render-frames "$render_frames" \
  --out "$out" --fvv build/tools/fvv/fvv
