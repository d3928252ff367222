#!/usr/bin/env python3
"""Writes a point cloud as a binary little-endian PLY file: points scattered over the surface of
a tube around a trefoil knot, as a scanner or photogrammetry would sample a solid, coloured
along the knot by a rainbow. Each vertex has float x, y, z, radius and uchar red, green, blue.
Standard library only; the same count and seed give the same bytes.

    python3 docs/gallery/make_knot_ply.py knot.ply [COUNT]
    sphray render -s knot.ply -m shaded -o knot.png

The trefoil: (sin t + 2 sin 2t, cos t - 2 cos 2t, -sin 3t), t in [0, 2 pi); the tube's radius
0.45; every point's radius 0.03.
"""
import colorsys
import math
import random
import struct
import sys

TUBE = 0.45
POINT_RADIUS = 0.03


def knot(t):
    return (math.sin(t) + 2 * math.sin(2 * t), math.cos(t) - 2 * math.cos(2 * t), -math.sin(3 * t))


def frame(t):
    """The knot's point at t, its unit tangent and two unit normals across the tube."""
    h = 1e-4
    p, q = knot(t), knot(t + h)
    d = [(b - a) / h for a, b in zip(p, q)]
    n = math.sqrt(sum(c * c for c in d))
    tangent = [c / n for c in d]
    up = (0.0, 0.0, 1.0) if abs(tangent[2]) < 0.9 else (1.0, 0.0, 0.0)
    u = [up[1] * tangent[2] - up[2] * tangent[1], up[2] * tangent[0] - up[0] * tangent[2],
         up[0] * tangent[1] - up[1] * tangent[0]]
    m = math.sqrt(sum(c * c for c in u))
    u = [c / m for c in u]
    v = [tangent[1] * u[2] - tangent[2] * u[1], tangent[2] * u[0] - tangent[0] * u[2],
         tangent[0] * u[1] - tangent[1] * u[0]]
    return p, u, v


def points(count, seed=1):
    rng = random.Random(seed)
    for _ in range(count):
        t = rng.uniform(0, 2 * math.pi)
        a = rng.uniform(0, 2 * math.pi)
        p, u, v = frame(t)
        xyz = [p[k] + TUBE * (math.cos(a) * u[k] + math.sin(a) * v[k]) for k in range(3)]
        r, g, b = colorsys.hsv_to_rgb(t / (2 * math.pi), 0.75, 0.95)
        yield xyz, (round(255 * r), round(255 * g), round(255 * b))


def write(path, count):
    header = ("ply\nformat binary_little_endian 1.0\ncomment a trefoil knot's tube, sampled\n"
              "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
              "property float radius\nproperty uchar red\nproperty uchar green\n"
              "property uchar blue\nend_header\n" % count)
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        for (x, y, z), (r, g, b) in points(count):
            f.write(struct.pack("<4f3B", x, y, z, POINT_RADIUS, r, g, b))


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: make_knot_ply.py OUT.ply [COUNT]")
    write(sys.argv[1], int(sys.argv[2]) if len(sys.argv) == 3 else 60000)
