#!/usr/bin/env bash
# Bakes the sample level's generated data into build/content/sample/ when missing or older than its
# sources: the cloud noises (cumulo noise) and the cloudscape NVDFs (cumulo bake). Baked outputs are not
# committed (the field NVDFs are ~10 MB); they are reproducible from the recipe and seed.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${CUMULO_BUILD_DIR:-build}
OUT="$BUILD_DIR/content/sample"
RECIPE=content/levels/sample/cloudscape.json
if [ ! -f "$OUT/noise/voxel_noise.nvdf" ] || [ "$BUILD_DIR/cumulo" -nt "$OUT/noise/voxel_noise.nvdf" ]; then
  "$BUILD_DIR/cumulo" noise -o "$OUT/noise" --no-previews
fi
if [ ! -f "$OUT/cloudscape/field_bc1.nvdf" ] || [ "$RECIPE" -nt "$OUT/cloudscape/field_bc1.nvdf" ] \
   || [ "$BUILD_DIR/cumulo" -nt "$OUT/cloudscape/field_bc1.nvdf" ]; then
  "$BUILD_DIR/cumulo" bake "$RECIPE" -o "$OUT/cloudscape"
fi
