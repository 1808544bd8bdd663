#!/usr/bin/env python3
"""Writes the example textures in this folder (no dependencies beyond Python).

gobo-window.png: a four-pane window with a soft round vignette, for a spot
light to project. tiles.png: square tiles with darker grout, for material
textures (roughness and emission scaled per texel).
"""
import math
import struct
import zlib


def write_png(path, size, pixel):
    rows = b"".join(
        b"\x00" + bytes(c for x in range(size) for c in pixel(x, y)) for y in range(size)
    )

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", size, size, 8, 6, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def gobo(x, y, n=64):
    u, v = (x + 0.5) / n * 2 - 1, (y + 0.5) / n * 2 - 1
    frame = abs(u) < 0.06 or abs(v) < 0.06
    r = math.hypot(u, v)
    fade = max(0.0, min(1.0, (0.95 - r) / 0.25))
    value = 0 if frame else int(255 * fade)
    warm = (value, int(value * 0.9), int(value * 0.75), 255)
    return warm


def tiles(x, y, n=64):
    grout = x % 16 < 2 or y % 16 < 2
    shade = 90 if grout else 255 - 20 * (((x // 16) + (y // 16)) % 2)
    return (shade, shade, shade, 255)


write_png("gobo-window.png", 64, gobo)
write_png("tiles.png", 64, tiles)
