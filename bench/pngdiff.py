#!/usr/bin/env python3
"""Compares two 8-bit PNGs pixel by pixel (stdlib only) with the conformance statistic:
the share of pixels within 1 level in every channel, and how many are off by more than 8.

    pngdiff.py A.png B.png   -> prints "within1=99.95% over1=.. over8=.. max=.." ; exit 1 if < 99.9%
"""
import struct
import sys
import zlib


def read_samples(path):
    """Width, height, channels (3 or 4), bit depth (8 or 16) and the rows of an RGB or RGBA PNG,
    each a list of samples (channel values, alpha included)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, info = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            info = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    w, h, depth, ctype, _, _, interlace = info
    assert depth in (8, 16) and interlace == 0 and ctype in (2, 6), (path, info)
    ch = 3 if ctype == 2 else 4
    bpp = ch * depth // 8
    raw = zlib.decompress(idat)
    stride = w * bpp
    prev = bytearray(stride)
    rows = []
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pr) & 255
        rows.append(list(line) if depth == 8 else list(struct.unpack(">%dH" % (stride // 2), line)))
        prev = line
    return w, h, ch, depth, rows


def read_png(path):
    """An 8-bit PNG's width, height and RGB pixels, row by row."""
    w, h, ch, depth, rows = read_samples(path)
    assert depth == 8, (path, depth)
    px = [row[x * ch:x * ch + 3] for row in rows for x in range(w)]
    return w, h, px


def main():
    wa, ha, a = read_png(sys.argv[1])
    wb, hb, b = read_png(sys.argv[2])
    assert (wa, ha) == (wb, hb), "sizes differ"
    over1 = over8 = worst = 0
    for p, q in zip(a, b):
        m = max(abs(p[0] - q[0]), abs(p[1] - q[1]), abs(p[2] - q[2]))
        worst = max(worst, m)
        over1 += m > 1
        over8 += m > 8
    n = len(a)
    within = 100.0 * (n - over1) / n
    print("within1=%.3f%% over1=%d over8=%d max=%d pixels=%d" % (within, over1, over8, worst, n))
    sys.exit(0 if over1 <= 0.001 * n and over8 <= 0.0005 * n else 1)


if __name__ == "__main__":
    main()
