#!/usr/bin/env python3
"""Replicated sphray-mpi against one process: the same image, rays per second on 1 and 2 ranks.

    /usr/bin/python3 bench/mpi_replicated.py [--build build/release] [--repeats 3]

Each case renders with `sphray render -j 1` (one process, one thread) and with `mpiexec -n 2
sphray-mpi render --distribution replicated -j 1` (two ranks, one thread each), interleaved,
best of --repeats; the images must be byte-identical. Rays per second are both commands' own
figure: the rays traced over the tracing's wall time (the slowest rank's), the tree's build
apart; the whole commands' wall times are given too (start-up, scene, build and output
included). Prints a markdown table for docs/distributed.md.
"""

import filecmp
import os
import re
import subprocess
import sys
import tempfile
import time

import mpi_runs

CASES = [
    ("rtiow-final, path", ["-s", "rtiow-final", "-m", "path", "--spp", "64", "-W", "400",
                           "-H", "225"]),
    ("random:4194304, normals", ["-s", "random:4194304", "-m", "normals", "--spp", "4", "-W",
                                 "1200", "-H", "675"]),
]

SUMMARY = re.compile(r"([\d.]+) s, [\d.]+ M?rays/s \((\d+) camera \+ (\d+) bounce \+ (\d+) shadow")


def run(command):
    """(rays per second of the tracing, wall seconds of the whole command)."""
    start = time.monotonic()
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    wall = time.monotonic() - start
    m = SUMMARY.search(done.stdout)
    if not m:
        sys.exit(f"no summary line in the output of {' '.join(command)}:\n{done.stdout}")
    seconds = float(m.group(1))
    rays = sum(int(m.group(k)) for k in (2, 3, 4))
    return rays / seconds, wall


def main(argv):
    args, programs = mpi_runs.parse(__doc__, argv)
    sphray, sphray_mpi = programs.sphray, programs.sphray_mpi
    print("| scene, mode | 1 process: rays/s | 2 ranks: rays/s | ratio | 1 process: wall s | "
          "2 ranks: wall s | same image |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        single, ranks = os.path.join(tmp, "single.ppm"), os.path.join(tmp, "ranks.ppm")
        for name, options in CASES:
            one, two = [], []
            for _ in range(args.repeats):
                one.append(run([sphray, "render", *options, "-j", "1", "-o", single]))
                two.append(run([*programs.mpiexec, "-n", "2", sphray_mpi,
                                "render", *options, "--distribution", "replicated", "-j", "1",
                                "-o", ranks]))
            same = filecmp.cmp(single, ranks, shallow=False)
            rate1, rate2 = max(r for r, _ in one), max(r for r, _ in two)
            wall1, wall2 = min(w for _, w in one), min(w for _, w in two)
            print(f"| {name} | {rate1:.3g} | {rate2:.3g} | {rate2 / rate1:.2f}x | {wall1:.2f} | "
                  f"{wall2:.2f} | {'yes' if same else 'NO'} |")
            sys.stdout.flush()
            if not same:
                sys.exit("the images differ")


if __name__ == "__main__":
    main(sys.argv[1:])
