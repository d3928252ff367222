#!/usr/bin/python3
"""Writes a particle file (.sphp) of N random spheres in a cube, for the scale measurements.

The centres are uniform in a cube whose side grows with the cube root of N, the radii uniform
in [0.2, 0.6], so that every size has the same density (about 0.24 of space filled, counting
overlaps): a deeper tree, not a denser one. Written a million particles at a time, so the
writer's memory stays small at any N; the same N and seed give the same bytes.

    /usr/bin/python3 bench/make_cloud.py 1000000 cloud1m.sphp [--seed 1]
"""
import argparse
import os
import struct

import numpy as np

CHUNK = 1 << 20


def write_cloud(count, path, seed):
    side = float(np.cbrt(count)) * 1.2
    rng = np.random.default_rng(seed)
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        # The header of docs/distributed.md: magic, version 1, reserved, count, reserved.
        f.write(b"SPHRAYP\0" + struct.pack("<IIQQ", 1, 0, count, 0))
        for start in range(0, count, CHUNK):
            n = min(CHUNK, count - start)
            rec = np.empty((n, 4), "<f4")
            rec[:, :3] = rng.uniform(-side / 2, side / 2, (n, 3))
            rec[:, 3] = rng.uniform(0.2, 0.6, n)
            f.write(rec.tobytes())
    os.replace(tmp, path)  # a reader never sees half a file


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("count", type=int)
    p.add_argument("output")
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    if not 0 < a.count < 2**32 - 1:
        p.error("count must be in [1, 2^32 - 2]")
    write_cloud(a.count, a.output, a.seed)


if __name__ == "__main__":
    main()
