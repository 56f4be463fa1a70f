#!/usr/bin/env bash
# A windowed `cumulo run` under Xvfb: must open a window (not fall back to headless), render, exit 0.
# xvfb-run -a picks a display number by looking for free lock files, which races with other Xvfb
# servers started at the same moment (parallel tests); a "cannot open display" start is retried.
set -u
for attempt in 1 2 3; do
  out=$(xvfb-run -a -s "-screen 0 640x480x24" "$@" 2>&1)
  rc=$?
  if grep -q "Failed to open display" <<<"$out"; then
    echo "attempt $attempt: Xvfb display race, retrying" >&2
    sleep $((attempt * 2))
    continue
  fi
  echo "$out"
  if [ $rc -ne 0 ]; then echo "FAIL: exit code $rc" >&2; exit 1; fi
  if ! grep -q "frames rendered in a window" <<<"$out"; then echo "FAIL: no windowed frames" >&2; exit 1; fi
  exit 0
done
echo "FAIL: could not start Xvfb after 3 attempts" >&2
exit 1
