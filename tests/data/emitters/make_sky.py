#!/usr/bin/env python3
"""Writes sky.exr (and slide.exr, see below), the 64 x 32 latitude-longitude map of tests/data/emitters/envmap.xml:
a dim blue-to-brown gradient (zenith to nadir) with a small bright warm "sun" patch
above the horizon, a quarter of the width across (+X in Mitsuba's envmap frame).
Deterministic (no randomness); needs only Mitsuba 3 (pip install mitsuba) for the EXR.

    python3 tests/data/emitters/make_sky.py tests/data/emitters/sky.exr tests/data/emitters/slide.exr
"""
import math
import sys

import mitsuba as mi

W, H = 64, 32


def texel(x, y):
    t = (y + 0.5) / H  # 0 at the zenith, 1 at the nadir
    sky = (0.25 + 0.35 * (1 - t), 0.35 + 0.3 * (1 - t), 0.6 + 0.5 * (1 - t))
    ground = (0.25, 0.18, 0.1)
    # Smooth transition at the horizon (row H/2).
    s = 1.0 / (1.0 + math.exp((t - 0.5) * 40.0))
    c = [s * a + (1 - s) * b for a, b in zip(sky, ground)]
    # The sun: 3 x 3 texels centred at u = 0.25 (phi = 90 deg), 30 deg above the horizon.
    if abs(x - W // 4) <= 1 and abs(y - H // 3) <= 1:
        c = [60.0, 45.0, 30.0]
    return c


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "sky.exr"
    mi.set_variant("scalar_rgb")
    data = [v for y in range(H) for x in range(W) for v in texel(x, y)]
    bmp = mi.Bitmap(mi.TensorXf(data, shape=(H, W, 3)), mi.Bitmap.PixelFormat.RGB)
    bmp.write(out)
    print(f"wrote {out} ({W} x {H})")


if __name__ == "__main__":
    main()


# --- slide.exr: the 16 x 16 image of projector.xml, asymmetric in u and v (an "L" of
# warm texels in the top-left quarter, a blue block lower right, grey elsewhere) so that
# a flip of either axis shows. Texels stay within [0, 1]: Mitsuba's spectral bitmap
# texture clamps brighter ones before upsampling (projector.xml's scale brightens).
def slide_texel(x, y):
    if (x == 2 and 2 <= y <= 7) or (y == 7 and 2 <= x <= 5):
        return [1.0, 0.62, 0.25]
    if 10 <= x <= 13 and 11 <= y <= 13:
        return [0.08, 0.15, 0.75]
    return [0.15, 0.15, 0.15]


def write_slide(out):
    mi.set_variant("scalar_rgb")
    data = [v for y in range(16) for x in range(16) for v in slide_texel(x, y)]
    mi.Bitmap(mi.TensorXf(data, shape=(16, 16, 3)), mi.Bitmap.PixelFormat.RGB).write(out)
    print(f"wrote {out} (16 x 16)")


if __name__ == "__main__" and len(sys.argv) > 2:
    write_slide(sys.argv[2])
