#!/usr/bin/env bash
# Regenerates the README's screenshots: the sample level's three cameras (ground, mixed, immersed) at noon
# and near sunset, headless, with the clouds (docs/images/<camera>_<time>.png), and the shipped weather
# states from the mixed camera (docs/images/weather/<state>_<time>.png), and the Stormbird encounter
# (docs/images/stormbird/: the storm cloud before, during and after stormbird_killed, a ground discharge
# with its rain, the lair lit from inside by a flash), and the sky at dawn, noon, sunset and night from the
# ground and the air (docs/images/sky/, with the 2.5D sky beyond the voxel clouds), the clouds' shadows and
# light shafts with and without them (docs/images/sky/{shadows,shafts}_{on,off}.png). Builds first.
# Usage: scripts/screenshots.sh [WxH] [FRAMES]   (default 480x270, 16 frames: the temporal accumulation
# settles and the 2.5D sky's 1-in-16 reprojection has marched every pixel)
set -euo pipefail
cd "$(dirname "$0")/.."
SIZE=${1:-480x270}
FRAMES=${2:-16}
scripts/build.sh >/dev/null
BUILD_DIR=${CUMULO_BUILD_DIR:-build}
mkdir -p docs/images
for cam in ground mixed immersed; do
  for tod in noon:12.5 sunset:18.0; do
    name=${tod%%:*}
    hours=${tod##*:}
    "$BUILD_DIR/cumulo" run content/levels/sample/level.json --headless --camera "$cam" --time-of-day "$hours" \
      --size "$SIZE" --frames "$FRAMES" --screenshot "docs/images/${cam}_${name}.png" >/dev/null
    echo "docs/images/${cam}_${name}.png"
  done
done
# The shipped weather states from the mixed camera at noon and near sunset (docs/images/weather/).
mkdir -p docs/images/weather
for state in clear fair_cumulus overcast_stratus storm stormbird; do
  for tod in noon:12.5 sunset:18.0; do
    "$BUILD_DIR/cumulo" run content/levels/sample/level.json --headless --camera mixed --weather "$state" \
      --time-of-day "${tod##*:}" --size 320x180 --frames "$FRAMES" \
      --screenshot "docs/images/weather/${state}_${tod%%:*}.png" >/dev/null
    echo "docs/images/weather/${state}_${tod%%:*}.png"
  done
done
# The Stormbird encounter (docs/images/stormbird/): dissipation with the level's default 20 s, a bolt, the lair.
mkdir -p docs/images/stormbird
run_storm() {  # NAME ARGS...
  local name=$1
  shift
  "$BUILD_DIR/cumulo" run content/levels/sample/level.json --headless --size "$SIZE" "$@" \
    --screenshot "docs/images/stormbird/$name.png" >/dev/null
  echo "docs/images/stormbird/$name.png"
}
run_storm before --camera stormbird --start-at 40 --frames 2
run_storm during --camera stormbird --event stormbird_killed@1 --start-at 13 --frames 2
run_storm after --camera stormbird --event stormbird_killed@1 --start-at 40 --frames 2
run_storm bolt --camera stormbird --event storm_bolt@1.02 --start-at 1 --frames 3
run_storm bolt_night --camera stormbird --time-of-day 21.5 --event storm_bolt@1.02 --start-at 1 --frames 3
run_storm lair --camera lair --start-at 3 --frames "$FRAMES"
run_storm lair_flash --camera lair --event lair_flash@1 --start-at 0.95 --frames 3
# The sky at dawn, noon, sunset and night from the ground and from the air (docs/images/sky/).
mkdir -p docs/images/sky
for tod in dawn:5.9 noon:12.5 sunset:18.9 night:22.5; do
  for view in ground:ground air:mixed; do
    "$BUILD_DIR/cumulo" run content/levels/sample/level.json --headless --camera "${view##*:}" \
      --time-of-day "${tod##*:}" --size 320x180 --frames "$FRAMES" \
      --screenshot "docs/images/sky/${tod%%:*}_${view%%:*}.png" >/dev/null
    echo "docs/images/sky/${tod%%:*}_${view%%:*}.png"
  done
done
# The clouds' shadows on the terrain and the ocean, and light shafts through gaps toward a low sun.
for m in on off; do
  "$BUILD_DIR/cumulo" run content/levels/sample/level.json --headless --camera mixed --time-of-day 12.5 \
    --size "$SIZE" --frames "$FRAMES" --cloud-shadows "$m" --screenshot "docs/images/sky/shadows_$m.png" >/dev/null
  echo "docs/images/sky/shadows_$m.png"
  "$BUILD_DIR/cumulo" run content/levels/sample/level.json --headless --camera shafts --time-of-day 17 \
    --size "$SIZE" --frames "$FRAMES" --cloud-light-shafts "$m" --screenshot "docs/images/sky/shafts_$m.png" >/dev/null
  echo "docs/images/sky/shafts_$m.png"
done
