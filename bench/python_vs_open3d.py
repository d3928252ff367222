#!/usr/bin/env python3
"""sphray's Python module against Open3D's RaycastingScene.cast_rays on the same spheres and
rays: rays per second and build time on all cores, and how far Open3D's answer on tessellated
spheres lies from the exact one.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_vs_open3d.py [--out FILE.json]

Scenes: N spheres uniform in a 100-unit box, radii uniform in [0.5, 1.5) x 50 / cbrt(N) (the
renderer's random:N recipe, drawn with numpy), N = 4096 and 65536. Rays: 262,144 with origins
uniform in the box and directions uniform on the unit sphere, the same for both libraries.
Open3D traces every sphere as Open3D's own TriangleMesh.create_sphere(radius, resolution)
moved into place (resolutions 4 and 8: 48 and 224 triangles a sphere), merged into one mesh.
Each trace is timed best of --repeats; a build is timed once (Open3D builds its BVH on the
first cast_rays: its build is that first call on one ray, plus add_triangles).

Needs numpy, Open3D (Debian: python3-open3d) and the sphray module on PYTHONPATH.
Writes the figures as JSON for bench/report.py and prints a table.
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
from python_workload import best_of, random_rays, random_scene

SCENES = (4096, 65536)
RESOLUTIONS = (4, 8)


def tessellate(centers, radii, resolution):
    """One mesh of every sphere: Open3D's unit sphere at this resolution, scaled and moved."""
    unit = o3d.geometry.TriangleMesh.create_sphere(1.0, resolution)
    v = np.asarray(unit.vertices, dtype=np.float32)
    t = np.asarray(unit.triangles, dtype=np.uint32)
    vertices = (centers[:, None, :] + radii[:, None, None] * v[None, :, :]).reshape(-1, 3)
    offsets = (np.arange(len(centers), dtype=np.uint32) * len(v))[:, None, None]
    triangles = (t[None, :, :] + offsets).reshape(-1, 3)
    return vertices, triangles, len(t)


def run_sphray(centers, radii, origins, directions, repeats):
    build, scene = best_of(1, lambda: sphray.Scene(centers, radii))
    trace, (t, ids) = best_of(repeats, lambda: scene.intersect(origins, directions))
    return {"build_s": build, "trace_s": trace, "rays_per_s": len(origins) / trace}, t, ids


def run_open3d(vertices, triangles, origins, directions, repeats):
    rays = o3d.core.Tensor(np.hstack([origins, directions]), dtype=o3d.core.Dtype.Float32)

    def build():
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.core.Tensor(vertices), o3d.core.Tensor(triangles))
        scene.cast_rays(rays[:1])  # Open3D commits (builds) its scene on the first query
        return scene

    build_s, scene = best_of(1, build)
    trace, ans = best_of(repeats, lambda: scene.cast_rays(rays, nthreads=0))
    t = ans["t_hit"].numpy()
    prim = ans["primitive_ids"].numpy().astype(np.int64)
    return {"build_s": build_s, "trace_s": trace, "rays_per_s": len(origins) / trace}, t, prim


def tessellation_error(centers, radii, resolution, origins, directions, t_exact, ids):
    """What tracing the tessellated spheres costs in accuracy, measured with an exact
    ray/triangle test (Moller-Trumbore, float64) of every ray that hits a sphere against that
    sphere's own triangles: the fraction of those rays that miss the polyhedron (it lies inside
    the sphere), and the distance error |t_mesh - t| |dir| / r of the others."""
    unit = o3d.geometry.TriangleMesh.create_sphere(1.0, resolution)
    v = np.asarray(unit.vertices, dtype=np.float64)[np.asarray(unit.triangles)]  # (T, 3, 3)
    hit = np.flatnonzero(ids != sphray.NO_HIT)
    t_mesh = np.full(len(hit), np.inf)
    for chunk in np.array_split(hit, max(1, len(hit) // 4096)):
        i = ids[chunk]
        c, r = centers[i].astype(np.float64), radii[i].astype(np.float64)
        # In the sphere's unit frame: o' = (o - c) / r, d' = d / r, t unchanged.
        o = (origins[chunk] - c) / r[:, None]
        d = directions[chunk].astype(np.float64) / r[:, None]
        e1, e2 = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]              # (T, 3)
        p = np.cross(d[:, None, :], e2[None])                       # (K, T, 3)
        det = np.einsum("ktj,tj->kt", p, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            s = o[:, None, :] - v[None, :, 0]
            u = np.einsum("ktj,ktj->kt", s, p) * inv
            q = np.cross(s, e1[None])
            w = np.einsum("ktj,kj->kt", q, d) * inv
            t = np.einsum("ktj,tj->kt", q, e2) * inv
        ok = (det != 0) & (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 0)
        t_mesh[np.searchsorted(hit, chunk)] = np.where(ok, t, np.inf).min(axis=1)
    found = np.isfinite(t_mesh)
    length = np.linalg.norm(directions[hit].astype(np.float64), axis=1)
    err = np.abs(t_mesh[found] - t_exact[hit][found]) * length[found] / radii[ids[hit][found]]
    return {
        "exact_hits": int(len(hit)),
        "mesh_missed_fraction": float(1 - found.mean()) if len(hit) else 0.0,
        "error_median_radii": float(np.median(err)) if err.size else None,
        "error_max_radii": float(np.max(err)) if err.size else None,
    }


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="build/bench-results/python_vs_open3d.json")
    ap.add_argument("--rays", type=int, default=262144)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--scenes", type=int, nargs="+", default=list(SCENES))
    ap.add_argument("--resolutions", type=int, nargs="+", default=list(RESOLUTIONS))
    args = ap.parse_args(argv)

    origins, directions = random_rays(args.rays, seed=2)
    rows = []
    for n in args.scenes:
        centers, radii = random_scene(n, seed=1)
        ours, t, ids = run_sphray(centers, radii, origins, directions, args.repeats)
        rows.append({"spheres": n, "impl": "sphray", "triangles_per_sphere": 0, **ours})
        print(f"{n:>6} spheres  sphray            {ours['rays_per_s'] / 1e6:8.2f} M rays/s  "
              f"build {ours['build_s'] * 1e3:8.1f} ms", flush=True)
        for res in args.resolutions:
            vertices, triangles, per_sphere = tessellate(centers, radii, res)
            theirs, t_o3d, prim = run_open3d(vertices, triangles, origins, directions, args.repeats)
            acc = tessellation_error(centers, radii, res, origins, directions, t, ids)
            # Open3D's own answer: how many rays it reports a hit for (see docs/python.md:
            # Debian 12's build reports none at all on the machines tried).
            acc["open3d_hits"] = int(np.isfinite(t_o3d).sum())
            same = (ids != sphray.NO_HIT) & np.isfinite(t_o3d) & (prim // per_sphere == ids)
            acc["open3d_same_sphere"] = int(same.sum())
            rows.append({"spheres": n, "impl": "open3d", "resolution": res,
                         "triangles_per_sphere": per_sphere, **theirs, **acc,
                         "sphray_speedup": ours["rays_per_s"] / theirs["rays_per_s"]})
            print(f"{n:>6} spheres  open3d {per_sphere:>4} tri  {theirs['rays_per_s'] / 1e6:8.2f} M rays/s  "
                  f"build {theirs['build_s'] * 1e3:8.1f} ms  sphray x{rows[-1]['sphray_speedup']:.1f}  "
                  f"mesh misses {acc['mesh_missed_fraction']:.2%} of hits, error median "
                  f"{acc['error_median_radii']:.3g} r max {acc['error_max_radii']:.3g} r, "
                  f"open3d hits {acc['open3d_hits']} of {acc['exact_hits']}",
                  flush=True)
            del vertices, triangles

    context = {
        "rays": args.rays, "repeats": args.repeats, "threads": os.cpu_count(),
        "sphray": sphray.__version__, "sphray_isa": sphray.active_isa(),
        "open3d": o3d.__version__, "numpy": np.__version__, "python": platform.python_version(),
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": "bench/python_vs_open3d.py " + " ".join(argv),
    }
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump({"context": context, "rows": rows}, f, indent=1)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main(sys.argv[1:])
