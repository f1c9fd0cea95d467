#!/usr/bin/env python3
"""Turns POV-Ray's trace of a supersampled scene into microray's pixels, in place: the 16-bit
linear PNG traced at n·W × n·H with the emitted light divided by SCALE (toml2pov.py
--supersampled --scale SCALE) becomes the 8-bit W × H image, each n×n block averaged, multiplied
by SCALE, clamped and encoded (linear or sRGB) as microray does.

    supersample.py IMAGE.png N linear|srgb SCALE
"""
import struct
import sys
import zlib

from pngdiff import read_samples


def main():
    path, n, enc, scale = sys.argv[1], int(sys.argv[2]), sys.argv[3], float(sys.argv[4])
    w, h, ch, depth, rows = read_samples(path)
    assert depth == 16, (path, depth)
    px = bytearray()
    for j in range(h // n):
        px.append(0)  # filter type 0
        for i in range(w // n):
            for k in range(3):
                s = sum(rows[j * n + b][(i * n + a) * ch + k] for a in range(n) for b in range(n))
                c = min(max(s * scale / (65535.0 * n * n), 0.0), 1.0)
                if enc == "srgb":
                    c = 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
                px.append(min(int(255 * c + 0.5), 255))

    def chunk(t, b):
        return struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b))

    header = struct.pack(">IIBBBBB", w // n, h // n, 8, 2, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                           + chunk(b"IDAT", zlib.compress(bytes(px))) + chunk(b"IEND", b""))


main()
