#!/usr/bin/env python3
"""Writes grid.png, the 4x4 sRGB texture of the texture tests and scene.xml (pure Python:
no imaging library needed). Texel (0, 0) is the top-left pixel; colours include fully
saturated primaries (spectral upsampling at its limits), white, black and greys."""
import pathlib
import struct
import zlib

TEXELS = [
    [(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 255)],
    [(0, 0, 0), (128, 128, 128), (200, 150, 40), (30, 90, 200)],
    [(255, 255, 0), (0, 255, 255), (255, 0, 255), (64, 64, 64)],
    [(230, 200, 180), (20, 140, 60), (150, 30, 60), (250, 250, 250)],
]


def png(rows):
    h, w = len(rows), len(rows[0])
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


if __name__ == "__main__":
    here = pathlib.Path(__file__).resolve().parent
    (here / "grid.png").write_bytes(png(TEXELS))
