#!/usr/bin/env python3
"""Writes the example textures in this folder (no dependencies beyond Python).

gobo-window.png: a four-pane window with a soft round vignette, for a spot
light to project. tiles.png: square tiles with darker grout, for material
textures (roughness and emission scaled per texel). matcap-clay.png and
matcap-chrome.png: matcaps (a lit sphere seen head-on) for AddMatCap, a warm
clay with a soft key light and rim, and a chrome with a sky, a horizon and a
bright window.
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


def sphere_normal(x, y, n):
    """The view-space normal a matcap texel stands for, or None off the disc."""
    u, v = (x + 0.5) / n * 2 - 1, 1 - (y + 0.5) / n * 2
    r2 = u * u + v * v
    if r2 > 1:
        return None
    return u, v, math.sqrt(1 - r2)


def to8(c):
    # Linear to sRGB, 8 bits: the files are colour data.
    c = max(0.0, min(1.0, c))
    c = 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
    return int(round(c * 255))


def matcap_clay(x, y, n=128):
    nrm = sphere_normal(x, y, n)
    if nrm is None:
        return (0, 0, 0, 255)
    nx, ny, nz = nrm
    key = max(0.0, -0.5 * nx + 0.6 * ny + 0.62 * nz)
    rim = (1 - nz) ** 3
    base = (0.55, 0.22, 0.15)
    spec = key ** 24 * 0.5
    rgb = [0.03 + b * (0.15 + 0.85 * key) + 0.35 * rim * w + spec
           for b, w in zip(base, (1.0, 0.8, 0.7))]
    return tuple(to8(c) for c in rgb) + (255,)


def matcap_chrome(x, y, n=128):
    nrm = sphere_normal(x, y, n)
    if nrm is None:
        return (0, 0, 0, 255)
    nx, ny, nz = nrm
    # The reflected view direction's height decides sky or ground.
    ry = 2 * nz * ny
    if ry > 0:
        sky = (0.35 + 0.5 * ry, 0.5 + 0.4 * ry, 0.8 + 0.2 * ry)
    else:
        sky = (0.25 + 0.2 * ry, 0.2 + 0.15 * ry, 0.15 + 0.1 * ry)
    window = 1.0 if abs(nx + 0.35) < 0.12 and 0.25 < ny < 0.6 else 0.0
    horizon = math.exp(-(ry / 0.05) ** 2) * 0.6
    rgb = [c + window + horizon for c in sky]
    return tuple(to8(c) for c in rgb) + (255,)


write_png("gobo-window.png", 64, gobo)
write_png("tiles.png", 64, tiles)
write_png("matcap-clay.png", 128, matcap_clay)
write_png("matcap-chrome.png", 128, matcap_chrome)
