#!/usr/bin/env python3
"""Writes mitsuba-rays.txt for tests/test_sdfgrid.cpp: Mitsuba 3's own answers for rays
against shape.vol (identity to_world): per ray the origin, direction, hit distance (or
inf), geometric normal, and shading normals for normals="smooth" and "analytic".
Rays: seeded, from outside the unit cube through random points inside it."""
import math
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")
scenes = {n: mi.load_dict({"type": "scene", "s": {"type": "sdfgrid", "filename": "shape.vol", "normals": n}})
          for n in ("smooth", "analytic")}
rng = random.Random(1)
with open("mitsuba-rays.txt", "w") as f:
    f.write("# ox oy oz dx dy dz t nx ny nz smooth_x smooth_y smooth_z analytic_x analytic_y analytic_z\n")
    for _ in range(400):
        target = [rng.uniform(0.1, 0.9) for _ in range(3)]
        z = rng.uniform(-1, 1)
        phi = rng.uniform(0, 2 * math.pi)
        d = [math.sqrt(1 - z * z) * math.cos(phi), math.sqrt(1 - z * z) * math.sin(phi), z]
        o = [target[i] - 2.0 * d[i] for i in range(3)]
        row = o + d
        si = {n: s.ray_intersect(mi.Ray3f(o, d)) for n, s in scenes.items()}
        if si["smooth"].is_valid():
            row += [si["smooth"].t] + list(si["smooth"].n) + list(si["smooth"].sh_frame.n) + list(si["analytic"].sh_frame.n)
        else:
            row += [math.inf] + [0.0] * 9
        f.write(" ".join("%.9g" % v for v in row) + "\n")
