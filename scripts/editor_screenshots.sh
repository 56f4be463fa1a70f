#!/usr/bin/env bash
# Regenerates the README's pictures of the weather editor (docs/images/editor/): `cumulo edit` in a
# 1280x720 window under Xvfb, driven by a script, on a copy of the shipped weather states (nothing in
# content/ changes): the editor over the sample level, and an overcast sky before and after a hole is
# painted into its cloud map. Also prints the editor's CPU time per frame with every panel open. Builds first.
# Usage: scripts/editor_screenshots.sh [WxH]   (default 1280x720)
set -euo pipefail
cd "$(dirname "$0")/.."
SIZE=${1:-1280x720}
scripts/build.sh >/dev/null
BUILD_DIR=${CUMULO_BUILD_DIR:-build}
out=docs/images/editor
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/weather"
cp content/weather/*.json "$work/weather/"
cat > "$work/editor.json" <<JSON
[{"do": "select_state", "name": "fair_cumulus"},
 {"do": "wait", "frames": 16},
 {"do": "screenshot", "path": "$out/editor.png"},
 {"do": "select_state", "name": "overcast_stratus"},
 {"do": "set", "param": "wind.speed", "value": 0},
 {"do": "wait", "frames": 16},
 {"do": "screenshot", "path": "$out/hole_before.png"},
 {"do": "paint", "channel": "coverage", "x": 0.0, "y": 0.0, "radius": 0.45, "value": 0},
 {"do": "paint", "channel": "coverage", "x": 0.5, "y": 0.0, "radius": 0.45, "value": 0},
 {"do": "paint", "channel": "coverage", "x": 0.0, "y": 0.5, "radius": 0.45, "value": 0},
 {"do": "paint", "channel": "coverage", "x": 0.5, "y": 0.5, "radius": 0.45, "value": 0},
 {"do": "wait", "frames": 16},
 {"do": "screenshot", "path": "$out/hole_after.png"},
 {"do": "quit", "discard": true}]
JSON
xvfb-run -a -s "-screen 0 ${SIZE}x24" "$BUILD_DIR/cumulo" edit content/levels/sample/level.json \
  --weather-dir "$work/weather" --size "$SIZE" --camera ground --script "$work/editor.json" | grep -E "^cumulo: (wrote|editor CPU)"
