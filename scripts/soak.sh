#!/usr/bin/env bash
# The long soak (issue 25): `cumulo soak` on the sample level, 10,000 frames at 160x90 in laps of 1,000, once
# without the validation layers (resident memory is measured there) and once with them (validation messages
# counted), the JSON and tables written to docs/soak/. Hours of play in about an hour and a half on lavapipe.
#   scripts/soak.sh [FRAMES] [WxH]
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${CUMULO_BUILD_DIR:-build}
FRAMES=${1:-10000}
SIZE=${2:-160x90}
OUT=docs/soak
mkdir -p "$OUT"
name="lavapipe_${SIZE}_${FRAMES}"
status=0
CUMULO_VALIDATION=0 "$BUILD_DIR/cumulo" soak content/levels/sample/level.json --frames "$FRAMES" --size "$SIZE" \
  --lap 1000 --strict-timing --out "$OUT/$name.json" | tee "$OUT/$name.md" || status=$?
CUMULO_VALIDATION=1 "$BUILD_DIR/cumulo" soak content/levels/sample/level.json --frames "$FRAMES" --size "$SIZE" \
  --lap 1000 --out "$OUT/${name}_validation.json" | tee "$OUT/${name}_validation.md" || status=$?
exit $status
