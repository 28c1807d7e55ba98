#!/usr/bin/env python3
"""Writes tests/data/shapes/prism.serialized, a small Mitsuba .serialized file (format
version 4, zlib-compressed, two meshes + the end-of-file offset dictionary) used by the
camera end-to-end scenes (tests/data/cameras/*.xml), which load it in effigi and in
Mitsuba 3 alike. Mesh 0: a unit quad (positions only). Mesh 1: a triangular prism with
per-vertex normals and uvs (flat-shaded: every face has its own vertices).

    python3 tests/data/shapes/make_serialized.py
"""
import pathlib
import struct
import zlib


def mesh_record(positions, faces, normals=None, uvs=None, name="mesh"):
    flags = 0x1000 | (0x1 if normals else 0) | (0x2 if uvs else 0)
    data = struct.pack("<I", flags) + name.encode() + b"\0"
    data += struct.pack("<QQ", len(positions), len(faces))
    for arr in (positions, normals, uvs):
        if arr:
            for v in arr:
                data += struct.pack("<%df" % len(v), *v)
    for f in faces:
        data += struct.pack("<3I", *f)
    return struct.pack("<HH", 0x041C, 4) + zlib.compress(data, 9)


def prism():
    # Triangle (-0.5,0)-(0.5,0)-(0,0.8) in the xy plane, extruded from z = -0.4 to 0.4.
    tri = [(-0.5, 0.0), (0.5, 0.0), (0.0, 0.8)]
    pos, nrm, uv, faces = [], [], [], []

    def quad(a, b, c, d, n):
        base = len(pos)
        pos.extend([a, b, c, d])
        nrm.extend([n] * 4)
        uv.extend([(0, 0), (1, 0), (1, 1), (0, 1)])
        faces.extend([(base, base + 1, base + 2), (base, base + 2, base + 3)])

    for z, sign in ((0.4, 1), (-0.4, -1)):  # caps, wound to face outward
        base = len(pos)
        order = tri if sign > 0 else tri[::-1]
        pos.extend([(x, y, z) for x, y in order])
        nrm.extend([(0.0, 0.0, float(sign))] * 3)
        uv.extend([(0, 0), (1, 0), (0.5, 1)])
        faces.append((base, base + 1, base + 2))
    for i in range(3):
        (x0, y0), (x1, y1) = tri[i], tri[(i + 1) % 3]
        ex, ey = x1 - x0, y1 - y0
        ln = (ex * ex + ey * ey) ** 0.5
        n = (ey / ln, -ex / ln, 0.0)  # outward for the counter-clockwise triangle
        quad((x0, y0, -0.4), (x1, y1, -0.4), (x1, y1, 0.4), (x0, y0, 0.4), n)
    return pos, faces, nrm, uv


def main():
    quad_pos = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    records = [mesh_record(quad_pos, [(0, 1, 2), (0, 2, 3)], name="quad")]
    p, f, n, t = prism()
    records.append(mesh_record(p, f, n, t, name="prism"))
    out, offsets = b"", []
    for r in records:
        offsets.append(len(out))
        out += r
    out += b"".join(struct.pack("<Q", o) for o in offsets) + struct.pack("<I", len(records))
    path = pathlib.Path(__file__).with_name("prism.serialized")
    path.write_bytes(out)
    print(f"wrote {path} ({len(out)} bytes, {len(records)} meshes)")


if __name__ == "__main__":
    main()
