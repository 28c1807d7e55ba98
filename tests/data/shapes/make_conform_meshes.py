#!/usr/bin/env python3
"""Writes the small meshes of the shape conformance configurations (effigi-conform,
conformance/shape_suite.cpp): a coarse torus, non-convex (rays cross it up to four
times), as torus.obj (positions, normals, uvs: 'v/vt/vn' corners) and torus.ply (binary
little endian, positions only: effigi computes smooth vertex normals).

    python3 tests/data/shapes/make_conform_meshes.py
"""
import math
import pathlib
import struct

MAJOR, MINOR, NU, NV = 1.0, 0.35, 12, 8


def torus():
    pos, nrm, uv = [], [], []
    for i in range(NU):
        a = 2 * math.pi * i / NU
        for j in range(NV):
            b = 2 * math.pi * j / NV
            n = (math.cos(a) * math.cos(b), math.sin(a) * math.cos(b), math.sin(b))
            pos.append(((MAJOR + MINOR * math.cos(b)) * math.cos(a), (MAJOR + MINOR * math.cos(b)) * math.sin(a),
                        MINOR * math.sin(b)))
            nrm.append(n)
            uv.append((i / NU, j / NV))
    faces = []
    for i in range(NU):
        for j in range(NV):
            k00, k10 = i * NV + j, ((i + 1) % NU) * NV + j
            k01, k11 = i * NV + (j + 1) % NV, ((i + 1) % NU) * NV + (j + 1) % NV
            # Counter-clockwise seen from outside: the normal points away from the tube's axis.
            faces += [(k00, k10, k11), (k00, k11, k01)]
    return pos, nrm, uv, faces


def fmt(v):
    return " ".join("%.6f" % x for x in v)


if __name__ == "__main__":
    here = pathlib.Path(__file__).resolve().parent
    pos, nrm, uv, faces = torus()
    lines = ["# coarse torus (tests/data/shapes/make_conform_meshes.py)"]
    lines += ["v " + fmt(p) for p in pos] + ["vt " + fmt(t) for t in uv] + ["vn " + fmt(n) for n in nrm]
    lines += ["f " + " ".join("%d/%d/%d" % (k + 1, k + 1, k + 1) for k in f) for f in faces]
    (here / "torus.obj").write_text("\n".join(lines) + "\n")
    header = ("ply\nformat binary_little_endian 1.0\ncomment coarse torus (make_conform_meshes.py)\n"
              "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
              "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(pos), len(faces)))
    body = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<B3i", 3, *f) for f in faces)
    (here / "torus.ply").write_bytes(header.encode() + body)
