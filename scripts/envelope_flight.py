#!/usr/bin/env python3
"""Writes content/levels/sample/paths/fly_through_bank.json: a recording (engine/app/recording.h) of a camera that
flies in from the sea west of the main island, through the Envelope method's bank on its windward slopes, and climbs
out past the cap cloud on the summit (issue 24). Deterministic: run it again to regenerate the same file.

    python3 scripts/envelope_flight.py
    build/cumulo run --replay content/levels/sample/paths/fly_through_bank.json --headless --frames N --screenshot f.png
"""
import json
import math
import os

STEPS = 720  # 12 s at 60 Hz
# Catmull-Rom through these points (world x, y, z): the sea, the bank's edge, inside it, out over the upper slopes.
POINTS = [(-1500.0, 140.0, -150.0), (-1000.0, 150.0, -20.0), (-650.0, 165.0, 90.0), (-380.0, 200.0, 190.0),
          (-180.0, 300.0, 300.0), (150.0, 460.0, 520.0)]


def catmull(p0, p1, p2, p3, t):
    return tuple(0.5 * ((2 * b) + (-a + c) * t + (2 * a - 5 * b + 4 * c - d) * t * t + (-a + 3 * b - 3 * c + d) * t ** 3)
                 for a, b, c, d in zip(p0, p1, p2, p3))


def position(s):
    """The path at s in [0, 1]."""
    n = len(POINTS) - 1
    f = min(s * n, n - 1e-9)
    i = int(f)
    pts = [POINTS[max(i - 1, 0)], POINTS[i], POINTS[i + 1], POINTS[min(i + 2, n)]]
    return catmull(*pts, f - i)


def normalize(v):
    l = math.sqrt(sum(x * x for x in v))
    return tuple(x / l for x in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def look_rotation(forward):
    """The camera's rotation (w, x, y, z) that turns its -z toward `forward` with y up."""
    f = normalize(forward)
    r = normalize(cross(f, (0.0, 1.0, 0.0)))
    u = cross(r, f)
    m = [[r[0], u[0], -f[0]], [r[1], u[1], -f[1]], [r[2], u[2], -f[2]]]  # columns: right, up, back
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return (0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s)
    if m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        return ((m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s)
    if m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        return ((m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s)
    s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
    return ((m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s)


def main():
    path = []
    for step in range(0, STEPS + 1, 2):
        s = step / STEPS
        p = position(s)
        ahead = position(min(s + 0.02, 1.0)) if s < 0.98 else tuple(2 * a - b for a, b in zip(p, position(s - 0.02)))
        d = tuple(a - b for a, b in zip(ahead, p))
        q = look_rotation(d)
        path.append({"step": step, "position": [round(x, 2) for x in p], "rotation": [round(x, 6) for x in q]})
    rec = {"format": "cumulo-recording", "version": 1, "level": "content/levels/sample/level.json", "seed": 1,
           "sim_hz": 60, "time_of_day": 12.0, "camera": "mixed", "steps": STEPS, "camera_path": path, "events": []}
    out = os.path.join(os.path.dirname(__file__), "..", "content", "levels", "sample", "paths", "fly_through_bank.json")
    with open(out, "w") as f:
        json.dump(rec, f, separators=(",", ":"))
        f.write("\n")
    print(os.path.normpath(out))


if __name__ == "__main__":
    main()
