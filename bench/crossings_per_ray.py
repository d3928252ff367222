#!/usr/bin/env python3
"""How many spheres a ray crosses, and what that leaves a k-nearest query to save.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/crossings_per_ray.py [--spheres N]

Scene and rays: the renderer's random:N recipe and the benchmark's incoherent rays (origins
uniform in the box, directions uniform on the sphere), drawn with numpy
(bench/python_workload.py). For each ray, count_hits gives its crossings in all (a sphere's entry
and exit each count). It prints their mean and median, the share of rays with fewer than k
crossings, for which intersect_nearest with room for k must walk the whole segment as
count_hits does, and a bound on what pruning can save: a ray with c >= k crossings needs at
least the part of its segment up to its k-th crossing, about k / c of it when crossings are
spread evenly along the segment, so the pruned walks cost at least the mean of min(1, k / c)
of the full walks (docs/queries.md, "The nearest crossings alone").
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphray  # noqa: E402
from python_workload import random_rays, random_scene  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--spheres", type=int, default=65536)
    p.add_argument("--rays", type=int, default=200000)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()
    centers, radii = random_scene(args.spheres, args.seed)
    origins, directions = random_rays(args.rays, args.seed + 1)
    counts = np.asarray(sphray.Scene(centers, radii).count_hits(origins, directions))
    print("random:%d, %d incoherent rays: %.1f crossings per ray on average, median %d"
          % (args.spheres, args.rays, counts.mean(), np.median(counts)))
    for k in (1, 2, 4, 8, 16, 32):
        fewer = (counts < k).mean()
        share = np.minimum(1.0, k / np.maximum(counts, 1)).mean()
        print("k = %2d: %4.1f%% of rays have fewer than k crossings; the pruned walks cost at "
              "least %.2f of the full ones" % (k, 100 * fewer, share))


if __name__ == "__main__":
    main()
