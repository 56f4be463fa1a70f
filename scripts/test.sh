#!/usr/bin/env bash
# The test command: install what is missing, build, run every CTest test. Exits non-zero on failure.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
BUILD_DIR=${CUMULO_BUILD_DIR:-build}
# lavapipe is the only Vulkan device on CI; tests render at small sizes and count validation messages.
export CUMULO_VALIDATION=1
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$(nproc)" --timeout 600 "$@"
