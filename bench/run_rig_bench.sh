#!/usr/bin/env bash
# What the real take's rig allows, and what each of a real take's conditions
# costs (bench/README.md, docs/tracking.md "What the rig allows"): a synthetic
# take filmed by the real capture's cameras (fvv synth --rig), its actor moving
# as the real take's tracked poses say (--rig-poses), then
# build/bench/real_bench on it, each camera held out in turn, as on the real
# take. Conditions, one per run:
#   exact        the cameras exactly as calibrated
#   shape        the actor's surface up to 3 cm off the body model (--surface-detail 0.03)
#   colour       the cameras' responses 10 % apart (--colour-mismatch 0.1), calibrated from
#                the frames after the scored ones (fvv capture calibrate-colour)
#   calibration  every camera filming turned 0.15 degrees from its calibration, about 4.4
#                pixels at this rig's focal length (--calibration-error 0.15)
#   refined      as calibration, then the cameras refined from the outlines of the frames
#                after the scored ones (fvv capture refine-calib --from silhouettes), as the
#                real take's studio protocol does
#   tangents     as calibration, then the cameras refined from the tangents of their person
#                masks in the same frames (fvv capture refine-calib --from tangents)
#   all          shape, colour and calibration together
#   all-tangents all, the cameras refined from their tangents first, then their colours
# and two of another size, exactly calibrated, for the person-mask margin
# (docs/encoder.md, "The margin scales with the person"); not in the default:
#   closeup      focal lengths times 1.5: the actor 1.5 times as large in the same frames
#   halfsize     focal lengths, principal points and image sizes halved (540x960)
#
# Usage: bench/run_rig_bench.sh [--margin=N] [CONDITION ...]   (default: the first eight)
#   --margin=N   the encoder's --silhouette-margin N instead of its default (the
#                results go to out/rig_bench/CONDITION_marginN)
# Needs bench/run_real_bench.sh run first (its imported capture, in step, and
# its poses of frames 0-29 with cam01 held out), the person models and a
# Release build in build/. Frames 0-15 are scored and 0-7 rendered; the
# calibrations read frames 16-29.
set -euo pipefail
cd "$(dirname "$0")/.."
fvv=build/tools/fvv/fvv
capture=out/real_bench/capture
poses=out/real_bench/without_cam01/poses.json
for f in "$capture/capture.json" "$poses"; do
  if [ ! -f "$f" ]; then
    echo "run_rig_bench: no $f: run bench/run_real_bench.sh first" >&2
    exit 1
  fi
done
conditions=()
margin=()
suffix=""
for a in "$@"; do
  case $a in
    --margin=*)
      margin=(--silhouette-margin "${a#--margin=}")
      suffix="_margin${a#--margin=}"
      ;;
    *) conditions+=("$a") ;;
  esac
done
[ ${#conditions[@]} -gt 0 ] ||
  conditions=(exact shape colour calibration refined tangents all all-tangents)
out=out/rig_bench
mkdir -p "$out"
results=()
for c in "${conditions[@]}"; do
  rig=$capture
  case $c in
    exact | closeup | halfsize) extra=() ;;
    shape) extra=(--surface-detail 0.03) ;;
    colour) extra=(--colour-mismatch 0.1) ;;
    calibration | refined | tangents) extra=(--calibration-error 0.15) ;;
    all | all-tangents) extra=(--surface-detail 0.03 --colour-mismatch 0.1 --calibration-error 0.15) ;;
    *)
      echo "run_rig_bench: no condition $c (exact shape colour calibration refined tangents all" \
        "all-tangents closeup halfsize)" >&2
      exit 2
      ;;
  esac
  dir="$out/$c$suffix"
  take="$dir/take"
  rm -rf "$take"
  mkdir -p "$dir"
  case $c in
    closeup | halfsize)
      # The rig's cameras at another size: a calibration of their own.
      rig="$dir/rig"
      mkdir -p "$rig"
      python3 - "$capture/capture.json" "$rig/capture.json" "$c" <<'EOF'
import json, sys
source, target, condition = sys.argv[1:]
capture = json.load(open(source))
for camera in capture["cameras"]:
    K = camera["K"]
    if condition == "closeup":
        K[0][0] *= 1.5
        K[1][1] *= 1.5
    else:
        for row in (0, 1):
            K[row] = [v / 2 for v in K[row]]
        camera["width"] //= 2
        camera["height"] //= 2
json.dump(capture, open(target, "w"), indent=1)
EOF
      ;;
  esac
  echo "== $c$suffix: filming"
  $fvv synth --rig "$rig" --rig-poses "$poses" --no-plates --frames 30 --fps 60 \
    "${extra[@]}" -o "$take" >/dev/null
  case $c in
    colour | all) $fvv capture calibrate-colour "$take" --frames 16:29 --write -q ;;
    refined) $fvv capture refine-calib "$take" --from silhouettes --frames 16:29 --write ;;
    tangents) $fvv capture refine-calib "$take" --from tangents --frames 16:29 --write ;;
    all-tangents)
      $fvv capture refine-calib "$take" --from tangents --frames 16:29 --write
      $fvv capture calibrate-colour "$take" --frames 16:29 --write -q
      ;;
  esac
  build/bench/real_bench "$take" --frames 0:15 --render-frames 8 --surface --out "$dir" \
    --fvv $fvv "${margin[@]}" >"$dir/real_bench.log"
  echo "== $c$suffix: $(grep -A3 '^Renderer II as rendered, mean' "$dir/real_bench.log" | tr '\n' ' ')"
  results+=("$c$suffix")
done
python3 - "$out" "${results[@]}" <<'EOF'
import json, sys
out, conditions = sys.argv[1], sys.argv[2:]
keys = [("held_out_iou", "held-out IoU"), ("own_iou", "IoU used"), ("renderer2_iou", "II IoU"),
        ("renderer2_psnr", "II dB"), ("renderer2_psnr_both_cover", "II both dB"),
        ("renderer2_psnr_box", "II box dB")]
print("\nthe real take's rig, a synthetic actor, each camera held out (means over the cameras)")
print("%-12s" % "condition" + "".join("%14s" % k[1] for k in keys))
for c in conditions:
    rows = json.load(open(f"{out}/{c}/real_bench.json"))["cameras"]
    print("%-12s" % c + "".join("%14.3f" % (sum(r[k[0]] for r in rows) / len(rows)) for k in keys))
EOF
