#!/usr/bin/env python3
"""What reading C-ordered (N, 3) centres costs the sphray module: the one copy into columns
against the Scene build and a query, and a brute-force trace over the copy against one over
the caller's own column-ordered array (read in place). docs/decisions.md, "Python module".

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_layout.py
"""

import time

import numpy as np

import sphray


def best(fn, repeats=5):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    rng = np.random.default_rng(1)
    rays = 65536
    origins = rng.uniform(-50, 50, size=(rays, 3)).astype(np.float32)
    directions = rng.normal(size=(rays, 3)).astype(np.float32)
    print("| spheres | copy to columns | Scene(), C order (copy + BVH) | Scene(), column order (BVH) |"
          " brute-force trace, over the copy | over the caller's columns |")
    print("|---|---|---|---|---|---|")
    for n in (64, 4096, 65536, 1048576):
        c = rng.uniform(-50, 50, size=(n, 3)).astype(np.float32)
        r = (rng.uniform(0.5, 1.5, size=n) * 50 / np.cbrt(n)).astype(np.float32)
        f = np.asfortranarray(c)
        copy = best(lambda: np.asfortranarray(c))
        build_c = best(lambda: sphray.Scene(c, r, accel="bvh"), 3)
        build_f = best(lambda: sphray.Scene(f, r, accel="bvh"), 3)
        m = max(256, min(rays, 2**24 // n))  # brute force: at most 2^24 ray/sphere pairs
        brute_c, brute_f = sphray.Scene(c, r, accel="brute"), sphray.Scene(f, r, accel="brute")
        assert not np.shares_memory(brute_c.centers, c) and np.shares_memory(brute_f.centers, f)
        trace_c = best(lambda: brute_c.intersect(origins[:m], directions[:m]))
        trace_f = best(lambda: brute_f.intersect(origins[:m], directions[:m]))
        print(f"| {n:,} | {copy * 1e3:.3g} ms | {build_c * 1e3:.3g} ms | {build_f * 1e3:.3g} ms |"
              f" {m / trace_c / 1e6:.3g} M rays/s | {m / trace_f / 1e6:.3g} M rays/s |")


if __name__ == "__main__":
    main()
