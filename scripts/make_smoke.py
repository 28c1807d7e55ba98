#!/usr/bin/env python3
"""Write the procedural smoke plume of scenes/smoke: a 64^3 density grid in Mitsuba's .vol
format (scenes/smoke/smoke.vol, 1 MB, committed so that the scene loads as it is in
effigi and in Mitsuba 3), read by the `heterogeneous` medium of scenes/smoke/scene.xml.

    python3 scripts/make_smoke.py [--res 64] [--seed 7] [--out scenes/smoke/smoke.vol]

Pure Python (no numpy): the density is a column of smoke rising along +y whose radius
grows with height, bent by a slow sideways drift and broken up by fractal value noise
(4 octaves of trilinearly interpolated lattice noise, Perlin 1985 / Musgrave's fBm),
with the noise domain warped by a second noise field so that the edges curl. It fades
in above the floor of the cube and out below its top, and is zero at the grid's faces,
so the bounding cube never shows. Values lie in [0, 1]; the scene's `scale` makes them
an extinction coefficient. Deterministic for a given seed.

.vol layout (little endian): "VOL", version 3, int32 encoding 1 (float32), int32 x, y, z
resolution, int32 channels (1), float32 bbox (min xyz, max xyz), then float32 values with
x fastest, then y, then z.
"""
import argparse
import math
import pathlib
import random
import struct


class ValueNoise:
    """Lattice noise: random values at integer points of a periodic lattice, blended with
    a smoothstep-weighted trilinear interpolation."""

    def __init__(self, rng, period=32):
        self.n = period
        self.v = [rng.random() for _ in range(period ** 3)]

    def __call__(self, x, y, z):
        n, v = self.n, self.v
        ix, iy, iz = math.floor(x), math.floor(y), math.floor(z)
        fx, fy, fz = x - ix, y - iy, z - iz
        sx, sy, sz = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy), fz * fz * (3 - 2 * fz)
        x0, y0, z0 = ix % n, iy % n, iz % n
        x1, y1, z1 = (x0 + 1) % n, (y0 + 1) % n, (z0 + 1) % n

        def at(a, b, c):
            return v[(c * n + b) * n + a]

        def lerp(t, a, b):
            return a + t * (b - a)

        return lerp(sz,
                    lerp(sy, lerp(sx, at(x0, y0, z0), at(x1, y0, z0)), lerp(sx, at(x0, y1, z0), at(x1, y1, z0))),
                    lerp(sy, lerp(sx, at(x0, y0, z1), at(x1, y0, z1)), lerp(sx, at(x0, y1, z1), at(x1, y1, z1))))


def fbm(noise, x, y, z, octaves=4):
    """Fractal sum in [0, 1]: each octave twice the frequency, half the amplitude."""
    total, amp, norm = 0.0, 1.0, 0.0
    for _ in range(octaves):
        total += amp * noise(x, y, z)
        norm += amp
        x, y, z, amp = 2.03 * x + 17.1, 2.03 * y + 5.3, 2.03 * z + 11.7, amp * 0.5
    return total / norm


def smoothstep(a, b, t):
    t = min(1.0, max(0.0, (t - a) / (b - a)))
    return t * t * (3 - 2 * t)


def density(res, seed):
    rng = random.Random(seed)
    shape, warp = ValueNoise(rng), ValueNoise(rng)
    out = []
    for k in range(res):
        z = (k + 0.5) / res
        for j in range(res):
            y = (j + 0.5) / res
            # The column's axis drifts sideways as it rises; its radius grows.
            cx = 0.5 + 0.12 * math.sin(3.1 * y + 0.4) * y
            cz = 0.5 + 0.08 * math.cos(2.3 * y) * y
            radius = 0.08 + 0.34 * y
            vertical = smoothstep(0.02, 0.12, y) * (1.0 - smoothstep(0.72, 0.97, y))
            for i in range(res):
                x = (i + 0.5) / res
                if vertical <= 0.0:
                    out.append(0.0)
                    continue
                # Curl the edges: displace the lookup by a low-frequency noise field.
                wx = 0.2 * (warp(3 * x, 3 * y - 1.5, 3 * z) - 0.5)
                wz = 0.2 * (warp(3 * x + 7.7, 3 * y, 3 * z + 3.1) - 0.5)
                d = math.hypot(x + wx - cx, z + wz - cz) / radius
                if d >= 1.0:
                    out.append(0.0)
                    continue
                falloff = (1.0 - d * d) ** 1.5
                n = fbm(shape, 4 * x + 2 * wx, 4 * y - 1.5 * y * y, 4 * z + 2 * wz)
                v = falloff * vertical * smoothstep(0.35, 0.7, n)
                out.append(min(1.0, v))
    return out


def write_vol(path, res, values):
    header = b"VOL" + bytes([3]) + struct.pack("<i", 1) + struct.pack("<3i", res, res, res) + struct.pack("<i", 1)
    header += struct.pack("<6f", 0.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "wb") as f:
        f.write(header)
        f.write(struct.pack("<%df" % len(values), *values))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--out", default=str(pathlib.Path(__file__).resolve().parent.parent / "scenes/smoke/smoke.vol"))
    args = ap.parse_args()
    values = density(args.res, args.seed)
    write_vol(pathlib.Path(args.out), args.res, values)
    filled = sum(1 for v in values if v > 0.0)
    print(f"{args.out}: {args.res}^3 voxels, {filled} non-zero ({100.0 * filled / len(values):.1f} %), "
          f"max {max(values):.3f}, mean {sum(values) / len(values):.4f}")


if __name__ == "__main__":
    main()
