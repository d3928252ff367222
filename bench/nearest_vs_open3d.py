#!/usr/bin/env python3
"""sphray's Scene.nearest against Open3D's RaycastingScene.compute_distance on the same spheres
and points: points per second on all cores, and how far Open3D's answer on tessellated spheres
lies from the exact distance.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/nearest_vs_open3d.py [--out FILE.json]

Scene: N spheres uniform in a 100-unit box, radii uniform in [0.5, 1.5) x 50 / cbrt(N) (the
renderer's random:N recipe, drawn with numpy, as bench/python_vs_open3d.py), N = 1,048,576.
Points: 10^6 uniform in the box. Open3D measures the distance to every sphere tessellated as
its own TriangleMesh.create_sphere(radius, resolution) moved into place, merged into one mesh;
resolution 4 (48 triangles a sphere, 50 million in all) is the coarsest whose distances stay
within a fifth of a radius of the true ones; resolution 2 (an octahedron) is not a sphere.
sphray answers the exact signed distance |p - c| - r of the nearest sphere; the comparison is
on the points outside every sphere, where both are the distance to the nearest surface.
Each query is timed best of --repeats; Open3D's build (add_triangles and its first query, which
builds its tree) is timed once, as is sphray's Scene.

Needs numpy, Open3D (Debian: python3-open3d) and the sphray module on PYTHONPATH.
"""

import argparse
import json
import os
import platform
import sys
import time

import numpy as np

import open3d as o3d
import sphray

from python_vs_open3d import tessellate
from python_workload import best_of, random_scene


def exact_distance(centers, radii, ids, points):
    """|p - c| - r in float64 for the sphere sphray named: the check that its answer is the
    nearest is the test suite's job (tests against a long-double brute force); this gives the
    exact value to measure Open3D's error against."""
    c = centers[ids].astype(np.float64)
    return np.linalg.norm(points.astype(np.float64) - c, axis=1) - radii[ids].astype(np.float64)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="build/bench-results/nearest_vs_open3d.json")
    ap.add_argument("--spheres", type=int, default=1 << 20)
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--resolution", type=int, default=4)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)

    centers, radii = random_scene(args.spheres, seed=1)
    points = np.random.default_rng(3).uniform(-50, 50, size=(args.points, 3)).astype(np.float32)

    build_s, scene = best_of(1, lambda: sphray.Scene(centers, radii))
    ours_s, (ids, dist, _) = best_of(args.repeats, lambda: scene.nearest(points))
    exact = exact_distance(centers, radii, ids, points)
    ours_err = np.abs(dist.astype(np.float64) - exact) / radii[ids]
    print(f"sphray  nearest  {args.points / ours_s / 1e6:8.2f} M points/s  "
          f"build {build_s * 1e3:8.1f} ms  max error {ours_err.max():.2g} r", flush=True)

    vertices, triangles, per_sphere = tessellate(centers, radii, args.resolution)
    query = o3d.core.Tensor(points)

    def build():
        s = o3d.t.geometry.RaycastingScene()
        s.add_triangles(o3d.core.Tensor(vertices), o3d.core.Tensor(triangles))
        s.compute_distance(query[:1])  # Open3D builds its tree on the first query
        return s

    o3d_build_s, o3d_scene = best_of(1, build)
    theirs_s, theirs = best_of(args.repeats, lambda: o3d_scene.compute_distance(query, nthreads=0))
    theirs = theirs.numpy().astype(np.float64)
    outside = exact > 0
    err = np.abs(theirs[outside] - exact[outside]) / radii[ids[outside]]
    speedup = ours_s and theirs_s / ours_s
    print(f"open3d compute_distance {per_sphere} tri/sphere  {args.points / theirs_s / 1e6:8.2f} M "
          f"points/s  build {o3d_build_s * 1e3:8.1f} ms  error on {outside.sum()} outside points: "
          f"median {np.median(err):.3g} r, max {err.max():.3g} r  sphray x{speedup:.2f}",
          flush=True)

    rows = [
        {"impl": "sphray", "spheres": args.spheres, "points": args.points, "build_s": build_s,
         "query_s": ours_s, "points_per_s": args.points / ours_s,
         "error_max_radii": float(ours_err.max())},
        {"impl": "open3d", "spheres": args.spheres, "points": args.points,
         "resolution": args.resolution, "triangles_per_sphere": per_sphere,
         "build_s": o3d_build_s, "query_s": theirs_s, "points_per_s": args.points / theirs_s,
         "outside_points": int(outside.sum()), "error_median_radii": float(np.median(err)),
         "error_max_radii": float(err.max()), "sphray_speedup": speedup},
    ]
    context = {
        "threads": os.cpu_count(), "sphray": sphray.__version__,
        "sphray_isa": sphray.active_isa(), "open3d": o3d.__version__, "numpy": np.__version__,
        "python": platform.python_version(), "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": "bench/nearest_vs_open3d.py " + " ".join(argv),
    }
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump({"context": context, "rows": rows}, f, indent=1)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main(sys.argv[1:])
