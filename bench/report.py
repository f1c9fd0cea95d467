#!/usr/bin/env python3
"""Reads criterion's results (target/criterion) after `cargo bench --bench render`, prints the
markdown tables of docs/speed.md and draws docs/time_vs_spheres.png (stdlib only).

    python3 bench/report.py [CRITERION_DIR] [PNG]

The plot: frame time (log scale over the whole decades that hold the data, at least two, e.g.
1 .. 100 ms; grid at every decade and at 2 and 5 of each) against sphere count (log scale, 1 .. 1024) at
640x480; one colour per kind (primary blue, shaded green, shadowed red), filled squares for
spread spheres, hollow for clustered; grid lines at every decade. The numbers are in the tables.
"""
import json
import math
import os
import struct
import sys
import zlib

root = sys.argv[1] if len(sys.argv) > 1 else "target/criterion"
png = sys.argv[2] if len(sys.argv) > 2 else "docs/time_vs_spheres.png"


def est(*parts):
    p = os.path.join(root, *parts, "new", "estimates.json")
    if not os.path.exists(p):
        return None
    return json.load(open(p))["median"]["point_estimate"] / 1e6  # ms


kinds = ["primary", "shaded", "shadowed"]
layouts = ["spread", "clustered"]
counts = [1, 16, 256, 1024]

print("| kind | layout | " + " | ".join("%d spheres" % n for n in counts) + " | 16 → 256 |")
print("| --- | --- | " + " | ".join("---:" for _ in counts) + " | ---: |")
data = {}
for k in kinds:
    for l in layouts:
        row = [est("spheres_%s" % k, l, str(n)) for n in counts]
        data[(k, l)] = row
        cells = ["%.2f ms" % v if v is not None else "–" for v in row]
        grow = "%.2f×" % (row[2] / row[1]) if row[1] and row[2] else "–"
        print("| %s | %s | %s | %s |" % (k, l, " | ".join(cells), grow))
print()
print("| resolution | pixels | time | ns / pixel |")
print("| --- | ---: | ---: | ---: |")
for w, h in [(160, 120), (320, 240), (640, 480), (1280, 720), (1920, 1080)]:
    v = est("pixels_shadowed_spread16", "%dx%d" % (w, h))
    if v is not None:
        print("| %dx%d | %d | %.2f ms | %.1f |" % (w, h, w * h, v, v * 1e6 / (w * h)))
print()
a, b = est("target", "accelerated"), est("target", "brute")
if a and b:
    print("| target scene (640x480, 25 spheres, 3 lights, shadows) | time |")
    print("| --- | ---: |")
    print("| accelerated | %.2f ms |" % a)
    print("| brute force | %.2f ms |" % b)
    print("| speed-up | %.1f× |" % (b / a))

# --- the plot -------------------------------------------------------------------------------
W, H = 640, 420
img = [[(255, 255, 255)] * W for _ in range(H)]
x0, x1, y0, y1 = 60, W - 20, H - 40, 20  # plot area (y0 bottom)


def put(x, y, c):
    if 0 <= x < W and 0 <= y < H:
        img[y][x] = c


def line(xa, ya, xb, yb, c):
    n = max(abs(xb - xa), abs(yb - ya), 1)
    for i in range(n + 1):
        put(round(xa + (xb - xa) * i / n), round(ya + (yb - ya) * i / n), c)


def px(n):
    return x0 + (x1 - x0) * math.log10(n) / math.log10(1024)


values = [v for row in data.values() for v in row if v]
lo = math.floor(math.log10(min(values))) if values else 1
hi = max(math.ceil(math.log10(max(values))) if values else 3, lo + 2)
print(f"plot: frame time 10^{lo} .. 10^{hi} ms", file=sys.stderr)


def py(ms):
    return y0 - (y0 - y1) * (math.log10(ms) - lo) / (hi - lo)


grey, black = (215, 215, 215), (0, 0, 0)
light = (235, 235, 235)
for d in range(lo, hi):
    for m in (2, 5):
        line(x0, round(py(m * 10 ** d)), x1, round(py(m * 10 ** d)), light)
for d in range(lo, hi + 1):  # every decade
    y = round(py(10 ** d))
    line(x0, y, x1, y, grey)
    line(x0 - 6, y, x0, y, black)
for n in counts:
    x = round(px(n))
    line(x, y0, x, y1, grey)
    line(x, y0, x, y0 + 6, black)
line(x0, y0, x1, y0, black)
line(x0, y0, x0, y1, black)
colours = {"primary": (40, 90, 220), "shaded": (30, 160, 60), "shadowed": (220, 50, 40)}
for (k, l), row in data.items():
    c = colours[k]
    pts = [(round(px(n)), round(py(v))) for n, v in zip(counts, row) if v]
    for (xa, ya), (xb, yb) in zip(pts, pts[1:]):
        line(xa, ya, xb, yb, c)
    for x, y in pts:
        for dx in range(-4, 5):
            for dy in range(-4, 5):
                if l == "spread" or max(abs(dx), abs(dy)) == 4:
                    put(x + dx, y + dy, c)
raw = b"".join(b"\x00" + bytes(v for p in r for v in p) for r in img)


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


os.makedirs(os.path.dirname(png) or ".", exist_ok=True)
with open(png, "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
print("\nwrote", png, file=sys.stderr)
