#!/usr/bin/env python3
"""Writes shape.vol for tests/test_sdfgrid.cpp: the SDF of a torus (axis x) united with a
sphere, on a 24^3 grid over [0,1]^3; the shape has no symmetry that would hide a mix-up
of the axes or of the x-fastest layout in the comparison with Mitsuba. (The grid is cubic
because Mitsuba 3.9's sdfgrid mis-sizes the voxels of non-cubic grids: it takes the voxel
size of axis x from the z resolution and vice versa, and then misses hits.)
Format: Mitsuba .vol version 3 (see include/effigi/render/vol_reader.hpp)."""
import math
import struct

NX, NY, NZ = 24, 24, 24


def sdf(x, y, z):
    # Torus around the x axis through (0.42, 0.5, 0.45): major radius 0.25, minor 0.09.
    q = math.hypot(y - 0.5, z - 0.45) - 0.25
    torus = math.hypot(x - 0.42, q) - 0.09
    sphere = math.sqrt((x - 0.72) ** 2 + (y - 0.7) ** 2 + (z - 0.7) ** 2) - 0.15
    return min(torus, sphere)


with open("shape.vol", "wb") as f:
    f.write(b"VOL" + bytes([3]))
    f.write(struct.pack("<iiiii", 1, NX, NY, NZ, 1))
    f.write(struct.pack("<6f", 0, 0, 0, 1, 1, 1))
    for k in range(NZ):
        for j in range(NY):
            for i in range(NX):
                f.write(struct.pack("<f", sdf(i / (NX - 1), j / (NY - 1), k / (NZ - 1))))
