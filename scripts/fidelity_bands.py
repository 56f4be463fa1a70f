#!/usr/bin/env python3
"""Where a `cumulo fidelity` run's real-time clouds are too dark or too bright, by band (issue 21).

    scripts/fidelity_bands.py IMAGES_DIR [VIEW,VIEW,...]

IMAGES_DIR is a fidelity run's `--images` folder (VIEW_reference.exr, VIEW_realtime.exr). Over the pixels in cloud
(reference opacity >= 0.5, the fidelity metric's mask) it prints, per view, the real-time / reference ratio of the
mean luminance:
  - by tercile of the two images' mean luminance blurred over 1.5 px: dark, middle, bright. Sorting by one image
    alone regresses to the mean: where the two differ pixel by pixel without any bias (a detail a pixel apart), the
    pixels the reference puts in its bright third are on average less bright in the other image, and its dark third
    brighter, which reads as a lighting gradient that is not there (session 56: sorted by the reference, `mixed` read
    1.04 / 1.02 / 0.95; sorted by the real-time image 0.95 / 0.98 / 1.01; by the mean of both 0.99 / 0.99 / 0.99);
  - by depth inside the silhouette in pixels (1-2: the edge, 3-4, 5-8, 9 and more: the core).
Ratios of means are not biased by the reference's noise. Needs numpy (Debian: python3-numpy).
"""
import struct
import sys
import zlib
from pathlib import Path

import numpy as np


def read_exr(path):
    """Scanline OpenEXR, uncompressed or ZIP/ZIPS, half or float channels (what `cumulo fidelity` writes)."""
    b = Path(path).read_bytes()
    if b[:4] != b"v/1\x01":
        sys.exit(f"{path}: not an OpenEXR file")
    i, chans, attrs = 8, [], {}
    while True:
        j = b.index(b"\0", i)
        name = b[i:j].decode()
        i = j + 1
        if not name:
            break
        j = b.index(b"\0", i)
        i = j + 1
        size = struct.unpack("<i", b[i:i + 4])[0]
        i += 4
        val = b[i:i + size]
        i += size
        if name == "channels":
            k = 0
            while val[k] != 0:
                e = val.index(b"\0", k)
                cn = val[k:e].decode()
                k = e + 1
                chans.append((cn, struct.unpack("<i", val[k:k + 4])[0]))
                k += 16
        attrs[name] = val
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    comp = attrs["compression"][0]
    if comp not in (0, 2, 3):
        sys.exit(f"{path}: compression {comp} is not read here (none, ZIPS and ZIP are)")
    lines = {0: 1, 2: 1, 3: 16}[comp]
    nb = (h + lines - 1) // lines
    offs = struct.unpack("<%dQ" % nb, b[i:i + 8 * nb])
    img = {c: np.zeros((h, w), np.float32) for c, _ in chans}
    for o in offs:
        y = struct.unpack("<i", b[o:o + 4])[0] - y0
        sz = struct.unpack("<i", b[o + 4:o + 8])[0]
        data = b[o + 8:o + 8 + sz]
        nl = min(lines, h - y)
        raw = sum((4 if pt == 2 else 2) * w for _, pt in chans) * nl
        if comp != 0 and sz < raw:
            t = np.frombuffer(zlib.decompress(data), np.uint8).astype(np.int32)
            t = (np.cumsum(np.concatenate([t[:1], t[1:] - 128])) % 256).astype(np.uint8)
            half = (len(t) + 1) // 2
            out = np.empty_like(t)
            out[0::2], out[1::2] = t[:half], t[half:]
            data = out.tobytes()
        p = 0
        for yy in range(nl):
            for c, pt in chans:
                n = 4 if pt == 2 else 2
                img[c][y + yy] = np.frombuffer(data[p:p + n * w], np.float32 if pt == 2 else np.float16)
                p += n * w
    return img


def lum(img):
    return 0.2126 * img["R"] + 0.7152 * img["G"] + 0.0722 * img["B"]


def blur(a, s):
    r = int(3 * s)
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / s) ** 2)
    k /= k.sum()
    f = lambda x: np.convolve(np.pad(x, r, mode="edge"), k, "valid")
    return np.apply_along_axis(f, 0, np.apply_along_axis(f, 1, a))


def depth_in(mask):
    """Pixels from the silhouette's edge (1 on it); the image border counts as outside."""
    m = mask.copy()
    m[0, :] = m[-1, :] = m[:, 0] = m[:, -1] = False
    d = np.zeros(m.shape, int)
    k = 0
    while m.any():
        k += 1
        d[m] = k
        e = m.copy()
        e[1:, :] &= m[:-1, :]
        e[:-1, :] &= m[1:, :]
        e[:, 1:] &= m[:, :-1]
        e[:, :-1] &= m[:, 1:]
        m = e
    return d


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    d = Path(sys.argv[1])
    views = sys.argv[2].split(",") if len(sys.argv) > 2 else sorted(
        p.name[:-len("_reference.exr")] for p in d.glob("*_reference.exr"))
    bands = [(1, 2), (3, 4), (5, 8), (9, 10**6)]
    print("%-22s %-20s  %s" % ("view", "terciles dark/mid/bright", "edge 1-2 px / 3-4 / 5-8 / core 9+ (pixels)"))
    for v in views:
        r, t = read_exr(d / f"{v}_reference.exr"), read_exr(d / f"{v}_realtime.exr")
        m = r["A"] >= 0.5
        if m.sum() < 20:
            print("%-22s (under 20 pixels in cloud)" % v)
            continue
        lr, lt = lum(r), lum(t)
        br = blur(0.5 * (lr + lt), 1.5)
        q = np.quantile(br[m], [0, 1 / 3, 2 / 3, 1])
        ter = []
        for a, b in zip(q[:-1], q[1:]):
            k = m & (br >= a) & (br <= b)
            ter.append("%.2f" % (lt[k].mean() / lr[k].mean()))
        dd = depth_in(m)
        out = []
        for a, b in bands:
            k = (dd >= a) & (dd <= b)
            out.append("%.2f (%d)" % (lt[k].mean() / lr[k].mean(), k.sum()) if k.sum() > 20 else "-")
        print("%-22s %-20s  %s" % (v, " / ".join(ter), " / ".join(out)))


if __name__ == "__main__":
    main()
