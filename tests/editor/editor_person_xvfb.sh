#!/usr/bin/env bash
# A person at the editor, played by xdotool in an Xvfb display (CTest runs this under xvfb-run): the mouse
# drags the coverage slider, Ctrl+S saves, W held while a text field has the keyboard does not move the
# camera and Esc there leaves the field without quitting (the document is clean then: a leaked Esc would
# end the run), Ctrl+Z undoes. The editor's own script checks the state once the person is done.
# Usage: editor_person_xvfb.sh CUMULO_EXE   (from the repository root; needs xdotool)
set -u
exe=$1
command -v xdotool >/dev/null || { echo "SKIP: xdotool is not installed"; exit 0; }
work=$(mktemp -d)
pid=""
cleanup() { [ -n "$pid" ] && kill "$pid" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; cat "$work/log" 2>/dev/null; exit 1; }
mkdir "$work/weather"
cp content/weather/*.json "$work/weather/"
cat > "$work/script.json" <<JSON
[{"do": "select_state", "name": "fair_cumulus"},
 {"do": "wait", "file": "$work/done", "seconds": 400},
 {"do": "expect", "param": "coverage", "value": 0.4},
 {"do": "expect_dirty", "value": true},
 {"do": "expect_camera", "position": [292, 3, -288]},
 {"do": "quit", "discard": true}]
JSON
# Under load the display can take a moment to accept clients after xvfb-run hands over (a CTest run once saw the
# editor fail to open :99 at its start): wait for it rather than fail the person for the server's delay.
for _ in $(seq 1 30); do xdotool getdisplaygeometry >/dev/null 2>&1 && break; sleep 1; done
xdotool getdisplaygeometry >/dev/null 2>&1 || fail "the display ${DISPLAY:-(none)} accepts no clients"
# 1280x720: the panels' first-use layout, so the widgets are where the README's screenshot shows them.
CUMULO_VALIDATION=1 "$exe" edit content/levels/sample/level.json --weather-dir "$work/weather" --size 1280x720 \
  --camera ground --script "$work/script.json" >"$work/log" 2>&1 &
pid=$!
win=""
for _ in $(seq 1 180); do
  win=$(xdotool search --name "cumulo - " 2>/dev/null | head -1)
  [ -n "$win" ] && xdotool getwindowname "$win" | grep -q " ms " && break
  kill -0 "$pid" 2>/dev/null || fail "the editor ended before its window showed frames"
  sleep 1
done
[ -n "$win" ] || fail "no window"
# Frames take a second or more each on lavapipe at this size: every step waits for frames to pass (the
# window's title counts them), so two inputs never land in one frame whatever the machine's load.
frame_now() { xdotool getwindowname "$win" 2>/dev/null | sed -n 's/.* - frame \([0-9]*\).*/\1/p'; }
frames() {  # wait until $1 more frames have been rendered
  local start now
  start=$(frame_now)
  for _ in $(seq 1 600); do
    now=$(frame_now)
    [ -n "$start" ] && [ -n "$now" ] && [ "$now" -ge $((start + $1)) ] && return 0
    kill -0 "$pid" 2>/dev/null || fail "the editor ended"
    sleep 0.2
  done
  fail "no frames for two minutes"
}
xdotool mousemove 150 267 mousedown 1
frames 2
xdotool mouseup 1
frames 2
xdotool keydown ctrl key s keyup ctrl
frames 3
grep -q '"coverage": 0.4,' "$work/weather/fair_cumulus.json" && fail "Ctrl+S after the slider's drag did not save"
[ -f "$work/weather/fair_cumulus.json.bak" ] || fail "no backup of the saved state"
# New state: its name field takes the keyboard.
xdotool mousemove 22 153 mousedown 1
frames 1
xdotool mouseup 1
frames 2
xdotool keydown w
frames 3
xdotool keyup w keydown Escape
frames 2
xdotool keyup Escape
frames 2
kill -0 "$pid" 2>/dev/null || fail "Esc in a text field ended the editor"
# Close the popup (a click outside it), then undo the saved edit: coverage 0.4 again, unsaved.
xdotool mousemove 700 120 mousedown 1
frames 1
xdotool mouseup 1
frames 2
xdotool keydown ctrl key z keyup ctrl
frames 3
touch "$work/done"
wait "$pid"
rc=$?
pid=""
grep -q "validation error" "$work/log" && fail "Vulkan validation errors"
[ "$rc" -eq 0 ] || fail "the editor's checks failed (exit $rc)"
echo "PASS: slider drag, Ctrl+S, keys in a text field kept from the camera, Esc left the field, Ctrl+Z"
