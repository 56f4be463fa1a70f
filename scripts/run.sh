#!/usr/bin/env bash
# Installs what is missing, builds, and runs the sample open-world level: in a window when a display is
# available, otherwise headless, writing out/sample.png. Extra arguments go to `cumulo run`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
BUILD_DIR=${CUMULO_BUILD_DIR:-build}
LEVEL=content/levels/sample/level.json
scripts/bake-content.sh
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  exec "$BUILD_DIR/cumulo" run "$LEVEL" "$@"
fi
mkdir -p out
"$BUILD_DIR/cumulo" run "$LEVEL" --headless --frames 8 --size 640x360 --camera ground --screenshot out/sample.png "$@"
echo "cumulo: wrote $(pwd)/out/sample.png"
