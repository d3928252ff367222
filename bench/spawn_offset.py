#!/usr/bin/python3
"""How far sphray.spawn() moves a ray's origin off the surface it leaves, measured in double.

For the book's ground sphere (radius 1000 at (0, -1000, 0), the rtiow scenes' ground) and a unit
sphere, rays from above hit the surface at a few points; each hit spawns one ray straight out
(along the normal) and one straight in. The offset is the spawned origin's distance from the
sphere, |o - c| - r, evaluated in double on the float values. Beside it, the offset of the bound
sphray used before issue 32, gamma(16) (|c_i| + r) per coordinate projected on the normal.

Run from the repository root after a release build:
    PYTHONPATH=build/release/python /usr/bin/python3 bench/spawn_offset.py
"""
import numpy as np

import sphray


def gamma(n):
    u = 2.0**-24
    return n * u / (1 - n * u)


def offsets(center, radius, points_xz):
    """(point, outward offset, inward offset, before-issue-32 offset) for hits below each (x, z)."""
    scene = sphray.Scene(np.array([center], np.float32), np.array([radius], np.float32))
    top = center[1] + radius
    origins = np.array([[x, top + 5.0, z] for x, z in points_xz], np.float32)
    directions = np.tile(np.array([0, -1, 0], np.float32), (len(points_xz), 1))
    t, ids = scene.intersect(origins, directions)
    points, normals, _ = scene.surface(origins, directions, t, ids)
    out = scene.spawn(origins, directions, t, ids, normals)
    inward = scene.spawn(origins, directions, t, ids, -normals)
    c = np.array(center, np.float64)

    def distance(o):
        return np.linalg.norm(o.astype(np.float64) - c, axis=1) - radius

    before = (np.abs(normals.astype(np.float64)) * gamma(16) * (np.abs(c) + radius)).sum(axis=1)
    return points, distance(out), -distance(inward), before


def main():
    cases = [
        ("ground r=1000 at (0,-1000,0)", (0.0, -1000.0, 0.0), 1000.0,
         [(0.0, 0.0), (4.0, -1.0), (-4.0, -1.0), (11.0, 11.0)]),
        ("unit sphere at the origin", (0.0, 0.0, 0.0), 1.0, [(0.0, 0.0), (0.5, 0.5)]),
        ("ball r=0.5 at (0,0.5,0)", (0.0, 0.5, 0.0), 0.5, [(0.0, 0.0), (0.3, 0.0)]),
    ]
    print(f"{'sphere':32} {'hit point':>28} {'out':>10} {'in':>10} {'before':>10} {'now/before':>10}")
    for name, center, radius, xz in cases:
        points, out, inward, before = offsets(center, radius, xz)
        for p, o, i, b in zip(points, out, inward, before):
            where = f"({p[0]:.3g}, {p[1]:.3g}, {p[2]:.3g})"
            print(f"{name:32} {where:>28} {o:10.3e} {i:10.3e} {b:10.3e} {o / b:10.3f}")


if __name__ == "__main__":
    main()
