#!/usr/bin/env python3
"""What a Python user can run here that finds the hits: sphray's Python module against numpy
written the way a scientist vectorises the ray/sphere quadratic, and against sphray's own C
stream calls on the same arrays (through ctypes: one call, so the difference from the module
is the binding's cost). Rays per second, and how many answers agree.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_vs_numpy.py \\
        --library build/release/kernel/libsphray.so.2 [--out FILE.json]

Scenes: N spheres uniform in a 100-unit box, radii uniform in [0.5, 1.5) x 50 / cbrt(N) (the
renderer's random:N recipe, drawn with numpy), N = 256, 4096 and 65536. Rays: origins uniform
in the box, directions uniform on the unit sphere; 262,144 for sphray, fewer for numpy (which
tests every sphere: 2^24 / N rays, the first ones of the same set). Each trace: best of
--repeats. numpy runs on one thread (its element-wise operations do); the module and
sphray_intersect with threads SPHRAY_THREADS_ALL on every core; sphray_intersect on one.

Needs numpy and the sphray module on PYTHONPATH. Writes the figures as JSON for
bench/report.py and prints a table.
"""

import argparse
import ctypes
import json
import os
import platform
import sys
import time

import numpy as np

import sphray
from python_workload import best_of, random_rays, random_scene

SCENES = (256, 4096, 65536)
RAYS = 262_144
NUMPY_TESTS = 1 << 24  # sphere tests numpy is given per scene


def numpy_intersect(centers, radii, origins, directions, chunk_elements=1 << 22):
    """Closest hits the way numpy users write them: every ray of a chunk against every sphere,
    the quadratic for unit directions, the near root unless it lies behind the origin."""
    t_out = np.full(len(origins), np.inf, np.float32)
    id_out = np.full(len(origins), sphray.NO_HIT, np.uint32)
    rows = max(1, chunk_elements // len(centers))
    r2 = radii * radii
    for start in range(0, len(origins), rows):
        o = origins[start:start + rows, None, :]
        d = directions[start:start + rows, None, :]
        oc = o - centers[None, :, :]
        b = np.sum(oc * d, axis=2)
        c = np.sum(oc * oc, axis=2) - r2[None, :]
        disc = b * b - c
        root = np.sqrt(np.maximum(disc, 0))
        near, far = -b - root, -b + root
        t = np.where(near > 0, near, far)
        t = np.where((disc >= 0) & (t > 0), t, np.inf)
        ids = np.argmin(t, axis=1)
        best = t[np.arange(len(ids)), ids]
        t_out[start:start + rows] = best
        id_out[start:start + rows] = np.where(np.isfinite(best), ids, sphray.NO_HIT)
    return t_out, id_out


SPHRAY_THREADS_ALL = 0xFFFFFFFF


class QueryArgs(ctypes.Structure):
    """sphray_query_args: struct_size, masks (NULL: every bit), threads."""
    _fields_ = [("struct_size", ctypes.c_size_t), ("masks", ctypes.POINTER(ctypes.c_uint32)),
                ("threads", ctypes.c_uint)]


class CApi:
    """sphray's C API through ctypes: a scene, and the closest-hit stream call on one thread or
    on many."""

    def __init__(self, path):
        self.lib = ctypes.CDLL(path)
        f = ctypes.POINTER(ctypes.c_float)
        self.lib.sphray_scene_create.argtypes = [f, f, f, f, ctypes.c_size_t, ctypes.c_size_t,
                                                 ctypes.c_void_p, ctypes.POINTER(ctypes.c_void_p)]
        self.lib.sphray_scene_release.argtypes = [ctypes.c_void_p]
        self.lib.sphray_intersect.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t,
                                              ctypes.c_void_p, ctypes.POINTER(QueryArgs)]

    def scene(self, centers, radii):
        columns = [np.ascontiguousarray(centers[:, k]) for k in range(3)] + [radii]
        ptrs = [a.ctypes.data_as(ctypes.POINTER(ctypes.c_float)) for a in columns]
        handle = ctypes.c_void_p()
        if self.lib.sphray_scene_create(*ptrs, len(radii), 0, None, ctypes.byref(handle)) != 0:
            raise RuntimeError("sphray_scene_create failed")
        return handle

    @staticmethod
    def rays(origins, directions):
        """The rays as sphray_ray structs: origin, direction, tmin 0, tmax infinity."""
        out = np.empty((len(origins), 8), np.float32)
        out[:, 0:3], out[:, 3:6], out[:, 6], out[:, 7] = origins, directions, 0, np.inf
        return out

    def intersect(self, scene, rays, threads=None):
        """threads None: the defaults (args NULL, the calling thread); else the threads field."""
        hits = np.empty(len(rays), dtype=[("t", np.float32), ("id", np.uint32)])
        args = None if threads is None else ctypes.byref(
            QueryArgs(ctypes.sizeof(QueryArgs), None, threads))
        status = self.lib.sphray_intersect(scene, rays.ctypes.data, len(rays), hits.ctypes.data,
                                           args)
        if status != 0:
            raise RuntimeError("sphray_intersect failed")
        return hits["t"], hits["id"]


def agreement(ids, reference):
    return float(np.mean(ids == reference))


def run(args):
    load_at_start = os.getloadavg()[0]
    capi = CApi(args.library)
    origins, directions = random_rays(RAYS, 2)
    c_rays = CApi.rays(origins, directions)
    rows = []
    for n in SCENES:
        centers, radii = random_scene(n, 1)
        scene = sphray.Scene(centers, radii)
        module_s, (_, ids) = best_of(args.repeats, lambda: scene.intersect(origins, directions))
        handle = capi.scene(centers, radii)
        one_s, (_, ids_one) = best_of(args.repeats, lambda: capi.intersect(handle, c_rays))
        all_s, (_, ids_all) = best_of(
            args.repeats, lambda: capi.intersect(handle, c_rays, SPHRAY_THREADS_ALL))
        capi.lib.sphray_scene_release(handle)
        m = max(1, min(RAYS, NUMPY_TESTS // n))
        numpy_s, (_, ids_np) = best_of(
            args.repeats, lambda: numpy_intersect(centers, radii, origins[:m], directions[:m]))
        row = {
            "spheres": n, "numpy_rays": m,
            "module_rays_per_s": RAYS / module_s,
            "c_parallel_rays_per_s": RAYS / all_s,
            "c_one_thread_rays_per_s": RAYS / one_s,
            "numpy_rays_per_s": m / numpy_s,
            # Bit for bit: the module is the C++ call the C API makes.
            "module_matches_c": bool(np.array_equal(ids, ids_one) and np.array_equal(ids, ids_all)),
            # numpy's float32 quadratic is not the kernel's precision-safe one: near-tangent
            # rays and ties may differ.
            "numpy_agreement": agreement(ids_np, ids[:m]),
        }
        rows.append(row)
        print(f"{n:>7} spheres: numpy {row['numpy_rays_per_s'] / 1e6:8.4f} Mrays/s (1 thread), "
              f"sphray C {row['c_one_thread_rays_per_s'] / 1e6:7.2f} (1 thread), "
              f"module {row['module_rays_per_s'] / 1e6:7.2f}, "
              f"C parallel {row['c_parallel_rays_per_s'] / 1e6:7.2f} (all threads); "
              f"numpy agrees on {row['numpy_agreement']:.4%} of its rays", flush=True)
    return {
        "context": {
            "python": platform.python_version(), "numpy": np.__version__,
            "sphray": sphray.__version__, "sphray_isa": sphray.active_isa(),
            "threads": os.cpu_count(), "rays": RAYS, "repeats": args.repeats,
            "date": time.strftime("%Y-%m-%d"), "command": args.command,
            "cpu": cpu_name(), "load_avg": load_at_start,
        },
        "rows": rows,
    }


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "?"


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--library", required=True, help="libsphray.so.2 of the same build")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", help="write the figures here as JSON")
    ap.add_argument("--command", default="bench/python_vs_numpy.py")
    args = ap.parse_args(argv[1:])
    data = run(args)
    bad = [r["spheres"] for r in data["rows"]
           if not r["module_matches_c"] or r["numpy_agreement"] < 0.999]
    if args.out:
        with open(args.out, "w") as f:
            json.dump(data, f, indent=1)
    if bad:
        print(f"python_vs_numpy: the answers disagree on the scenes of {bad} spheres",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
