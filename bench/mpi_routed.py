#!/usr/bin/env python3
"""Routed sphray-mpi queries against one process and against shared batches, on 4.2M spheres.

    /usr/bin/python3 bench/mpi_routed.py [--build build/release] [--repeats 3]

Writes random:4194304 as a particle file (once, in a temporary directory), then for each view
(looking along z, the axis of the first Morton cut, then along x and y, across it) runs
`sphray-mpi bench` on 1 rank (one process: the kernel alone, shared batches) and on 2 ranks
with shared batches (every rank traces every ray, one reduction per batch) and with --routed
(each rank its run of every batch, sent only to the regions a ray crosses), interleaved, best
of --repeats by rays per second. Each rank traces on one thread (its tree is built on all).
Prints a markdown table for
docs/distributed.md.
"""

import subprocess
import sys
import tempfile

import mpi_runs

RAYS = "4194304"


def bench(command):
    """The bench's table row, split into cells."""
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    rows = [line for line in done.stdout.splitlines() if line.startswith("|")]
    if not rows:
        sys.exit(f"no row in the output of {' '.join(command)}:\n{done.stdout}{done.stderr}")
    return [cell.strip() for cell in rows[-1].strip("|").split("|")]


def main(argv):
    args, programs = mpi_runs.parse(__doc__, argv)
    sphray_mpi, mpiexec = programs.sphray_mpi, programs.mpiexec
    print("| view | 1 process: rays/s | 2 ranks, shared: rays/s | 2 ranks, routed: rays/s | "
          "routed / 1 process | busiest rank traced, of all rays | all ranks traced, of all rays "
          "| exchanges a batch |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        particles = mpi_runs.particle_file(programs, tmp)
        for axis in ("z", "x", "y"):
            options = [particles, "--rays", RAYS, "--from", axis]
            one, shared, routed = [], [], []
            for _ in range(args.repeats):
                one.append(bench([*mpiexec, "-n", "1", sphray_mpi, "bench", *options]))
                shared.append(bench([*mpiexec, "-n", "2", sphray_mpi, "bench", *options]))
                routed.append(bench([*mpiexec, "-n", "2", sphray_mpi, "bench", *options,
                                     "--routed"]))
            rate1 = max(float(row[5]) for row in one)
            rate_shared = max(float(row[5]) for row in shared)
            best = max(routed, key=lambda row: float(row[2]))
            rate_routed = float(best[2])
            print(f"| from {axis} | {rate1:.3g} | {rate_shared:.3g} | {rate_routed:.3g} | "
                  f"{rate_routed / rate1:.2f}x | {best[5]} | {best[6]} | {best[8]} |")
            sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv[1:])
