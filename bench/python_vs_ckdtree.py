#!/usr/bin/env python3
"""The batch overlap queries against scipy's cKDTree, the tool a numpy user reaches for in a
simulation's broad phase: Scene.overlaps (points or balls against the scene's spheres) against
cKDTree.query_ball_point, and Scene.overlapping_pairs against cKDTree.query_pairs, on the same
data, both on every core (workers=-1), with how many answers agree.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_vs_ckdtree.py [--out FILE.json]

Data: N equal spheres (cKDTree's balls are of one radius) with centres uniform in a box of side
N^(1/3), so one sphere a unit of volume, radius R = 0.5, and N points uniform in the same box.
query_ball_point(points, R) finds the centres within R of each point: the spheres a point lies
in, as overlaps(points, 0); query_pairs(2R) the pairs of spheres that overlap. cKDTree counts
a distance equal to the radius as inside, sphray as outside (touching is not overlapping):
agreement is counted. Each call: best of --repeats; the trees' builds are timed apart.

Needs numpy, scipy and the sphray module on PYTHONPATH. Writes the figures as JSON for
bench/report.py and prints a table.
"""

import argparse
import json
import os
import platform
import sys
import time

import numpy as np
import scipy
from scipy.spatial import cKDTree

import sphray
from python_workload import best_of

RADIUS = 0.5


def equal_spheres(n, seed):
    rng = np.random.default_rng(seed)
    side = np.cbrt(n)
    centers = rng.uniform(0, side, size=(n, 3)).astype(np.float32)
    points = rng.uniform(0, side, size=(n, 3)).astype(np.float32)
    return centers, np.full(n, RADIUS, np.float32), points


def csr_of_lists(lists):
    """cKDTree's array of lists in the sparse row layout, for comparison (not timed)."""
    counts = np.fromiter((len(x) for x in lists), np.int64, len(lists))
    offsets = np.concatenate([[0], np.cumsum(counts)])
    ids = np.fromiter((i for x in lists for i in sorted(x)), np.int64, offsets[-1])
    return offsets, ids


def run(n, repeats):
    centers, radii, points = equal_spheres(n, seed=n)
    build_sphray, scene = best_of(repeats, lambda: sphray.Scene(centers, radii))
    build_kd, tree = best_of(repeats, lambda: cKDTree(centers))
    t_overlaps, (offsets, ids) = best_of(repeats, lambda: scene.overlaps(points, 0.0))
    t_ball, lists = best_of(repeats,
                            lambda: tree.query_ball_point(points, RADIUS, workers=-1))
    kd_offsets, kd_ids = csr_of_lists(lists)
    same_rows = sum(np.array_equal(ids[offsets[i]:offsets[i + 1]],
                                   kd_ids[kd_offsets[i]:kd_offsets[i + 1]]) for i in range(n))
    t_pairs, pairs = best_of(repeats, scene.overlapping_pairs)
    t_kd_pairs, kd_pairs = best_of(
        repeats, lambda: tree.query_pairs(2 * RADIUS, output_type="ndarray"))
    ours = set(map(tuple, pairs.astype(np.int64).tolist()))
    theirs = set(map(tuple, np.sort(kd_pairs, axis=1).tolist()))
    return {"spheres": n, "points": n,
            "sphray_build_s": build_sphray, "ckdtree_build_s": build_kd,
            "overlaps_s": t_overlaps, "query_ball_point_s": t_ball,
            "found": int(offsets[-1]), "rows_agree": same_rows / n,
            "overlapping_pairs_s": t_pairs, "query_pairs_s": t_kd_pairs,
            "pairs": len(ours), "pairs_agree": len(ours & theirs) / max(1, len(ours | theirs))}


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100_000, 1_000_000])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", help="write the figures as JSON here")
    ap.add_argument("--command", default="bench/python_vs_ckdtree.py",
                    help="the command to name on the page")
    args = ap.parse_args(argv)
    context = {"python": platform.python_version(), "numpy": np.__version__,
               "scipy": scipy.__version__, "sphray_isa": sphray.active_isa(),
               "threads": os.cpu_count(), "cpu": platform.processor() or platform.machine(),
               "load_avg": os.getloadavg()[0], "repeats": args.repeats,
               "command": args.command, "date": time.strftime("%Y-%m-%d")}
    rows = []
    print("spheres    overlaps  query_ball_point  ratio  rows agree   "
          "overlapping_pairs  query_pairs  ratio  pairs agree")
    for n in args.sizes:
        r = run(n, args.repeats)
        rows.append(r)
        print(f"{n:>9,}  {r['overlaps_s']:8.3f}s  {r['query_ball_point_s']:15.3f}s  "
              f"{r['query_ball_point_s'] / r['overlaps_s']:5.1f}x  {r['rows_agree']:9.4%}   "
              f"{r['overlapping_pairs_s']:16.3f}s  {r['query_pairs_s']:10.3f}s  "
              f"{r['query_pairs_s'] / r['overlapping_pairs_s']:5.1f}x  {r['pairs_agree']:9.4%}")
        sys.stdout.flush()
    if args.out:
        with open(args.out, "w") as f:
            json.dump({"context": context, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[1:])
