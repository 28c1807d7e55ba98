#!/usr/bin/env python3
"""Writes prism.obj (a 60-degree triangular prism, axis along y) and prints the placement
of the prism, the wall and the camera used in scene.xml, computed from Snell's law for
Schott N-SF11 at 550 nm (minimum deviation). Run from scenes/prism/: python3 generate.py"""
import math

A = math.radians(60.0)      # apex angle
SIDE = 0.3                  # triangle side [m]
HALF_HEIGHT = 1.0           # half length along the prism axis (y)
WALL_DISTANCE = 1.2         # from the exit point along the 550 nm ray


def sf11(lam_nm):
    # Schott N-SF11 Sellmeier coefficients (Schott data sheet), lambda in um.
    B = (1.73759695, 0.313747346, 1.89878101)
    C = (0.013188707, 0.0623068142, 155.23629)
    l2 = (lam_nm * 1e-3) ** 2
    return math.sqrt(1 + sum(b * l2 / (l2 - c) for b, c in zip(B, C)))


def write_obj(path):
    # Cross-section in the prism's own (x, z) plane: base on z = 0, apex up.
    h = SIDE * math.sqrt(3) / 2
    tri = [(-SIDE / 2, 0.0), (SIDE / 2, 0.0), (0.0, h)]
    v = [(x, y, z) for y in (-HALF_HEIGHT, HALF_HEIGHT) for (x, z) in tri]  # 1-3 bottom, 4-6 top
    # Counter-clockwise seen from outside, so geometric normals point out.
    faces = [(1, 2, 3), (4, 6, 5),                 # ends (y = -1 faces -y, y = +1 faces +y)
             (1, 4, 5), (1, 5, 2),                 # base (z = 0, normal -z)
             (2, 5, 6), (2, 6, 3),                 # right face
             (3, 6, 4), (3, 4, 1)]                 # left face (light enters here)
    with open(path, "w") as f:
        f.write("# 60-degree triangular prism, side 0.3 m, axis along y (scenes/prism/generate.py)\n")
        for p in v:
            f.write("v {:.6f} {:.6f} {:.6f}\n".format(*p))
        for t in faces:
            f.write("f {} {} {}\n".format(*t))


def main():
    write_obj("prism.obj")
    n = sf11(550.0)
    theta1 = math.asin(n * math.sin(A / 2))           # incidence for minimum deviation
    tilt = theta1 - A / 2                              # incoming ray above the prism's base line
    dev = 2 * theta1 - A
    # Rotating the prism by `tilt` about y turns its frame so that the incoming ray is +x.
    c, s = math.cos(tilt), math.sin(tilt)
    rot = lambda x, z: (x * c + z * s, -x * s + z * c)
    h = SIDE * math.sqrt(3) / 2
    mid_left = (-SIDE / 4, h / 2)                      # middle of the entry face
    px, pz = rot(*mid_left)
    translate = (-px, 0.0, -pz)                        # entry point at the origin
    ex, ez = rot(SIDE / 2, 0.0)                        # exit point (the inside ray is parallel to the base)
    out = (math.cos(-dev), math.sin(-dev))             # 550 nm ray leaving, in world (x, z)
    wall = (ex + WALL_DISTANCE * out[0], ez + WALL_DISTANCE * out[1])
    wall_angle = math.degrees(math.atan2(-out[0], -out[1]))  # rotate y: +z normal -> toward the prism
    print(f"n(550) = {n:.5f}, theta1 = {math.degrees(theta1):.3f} deg, deviation = {math.degrees(dev):.3f} deg")
    for lam in (450, 650):
        nl = sf11(lam)
        d = theta1 + math.asin(nl * math.sin(A - math.asin(math.sin(theta1) / nl))) - A
        print(f"deviation at {lam} nm: {math.degrees(d):.3f} deg")
    print(f"prism: rotate y {math.degrees(tilt):.4f}, translate {translate[0]:.5f} 0 {translate[2]:.5f}")
    print(f"exit point ({ex:.5f}, 0, {ez:.5f}); wall centre ({wall[0]:.5f}, 0, {wall[1]:.5f}), rotate y {wall_angle:.4f}")


if __name__ == "__main__":
    main()
