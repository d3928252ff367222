#!/usr/bin/env python3
"""The model of sphray-mpi's two split-scene designs at 16 to 2048 ranks, from the simulation.

    /usr/bin/python3 bench/mpi_model.py [--build build/release] [--rays 262144]

Runs `sphray-mpi-simulate random:4194304` for both splits (equal Morton runs and planes) and
takes its work terms per rank count: for shared batches, the busiest rank's crossings a ray;
for routed rays, the busiest rank's visits a ray and the exchanges a batch. It then prices one
batch of N rays (a 1920x1080 frame's camera rays) on P ranks with the per-ray costs measured on
one rank (the defaults; docs/distributed.md gives the commands) and stated network figures,
for 10^9 spheres spread over the ranks, and prints rays per second, a markdown table:

  shared: T = N t_r + c N t_d(n) + 2 ceil(log2 P) alpha + 16 N beta + 8 N gamma
  routed: T = v N (t_d(n) + t_route) + v N 64 beta
              + W (3 ceil(log2 P) alpha + 4 P beta + min(P - 1, k) alpha)

c: the busiest rank's crossings a ray; v: its visits a ray; W: exchanges; n = 10^9 / P spheres a
rank, t_d(n) = t_d log2(n) / log2(4194304) (a tree's depth). A routed wave: the count of rays in
flight (an allreduce), the counts each rank sends each other (an alltoall of P ints, log2 P
rounds), and a message to each of the k ranks a rank has records for (at most its region's
neighbours: k = 26 assumed).
"""

import argparse
import math
import os
import re
import subprocess
import sys

N = 1920 * 1080
SPHERES = 1e9


def simulate(simulator, split, ranks, rays):
    """{P: (busiest visits, waves, busiest shared crossings)} from the simulation's table."""
    done = subprocess.run([simulator, "random:4194304", "--rays", str(rays), "--ranks",
                           ",".join(map(str, ranks)), "--split", split],
                          capture_output=True, text=True, check=True)
    terms = {}
    for line in done.stdout.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if not cells or not re.fullmatch(r"\d+", cells[0]):
            continue
        terms[int(cells[0])] = (float(cells[3]), int(cells[6]), float(cells[7]))
    return terms


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--rays", type=int, default=262144, help="the simulation's rays")
    ap.add_argument("--t-reject", type=float, default=14e-9, help="t_r: a root's rejection, s")
    ap.add_argument("--t-deep", type=float, default=74e-9,
                    help="t_d: a closest-hit search in 4194304 spheres, s")
    ap.add_argument("--t-route", type=float, default=29e-9, help="t_route: routing a visit, s")
    ap.add_argument("--alpha", type=float, default=2e-6, help="a message's latency, s")
    ap.add_argument("--neighbours", type=int, default=26,
                    help="k: the ranks a rank sends records to in a wave (assumed)")
    ap.add_argument("--bandwidth", type=float, default=12.5e9, help="bytes/s a link (1/beta)")
    ap.add_argument("--gamma", type=float, default=0.125e-9, help="reduction, s a byte")
    args = ap.parse_args(argv)
    simulator = os.path.join(args.build, "mpi", "sphray-mpi-simulate")
    ranks = [512, 1024, 2048]
    morton = simulate(simulator, "morton", ranks, args.rays)
    planes = simulate(simulator, "planes", ranks, args.rays)
    beta = 1.0 / args.bandwidth
    print(f"N = {N} rays a batch, {SPHERES:.0e} spheres, 32 ranks a node")
    print("| nodes | ranks | spheres a rank | shared batches: rays/s | routed, Morton runs: rays/s "
          "| routed, planes: rays/s |")
    print("|---|---|---|---|---|---|")
    for p in ranks:
        n = SPHERES / p
        t_deep = args.t_deep * math.log2(n) / math.log2(4194304)
        hops = 2 * math.ceil(math.log2(p)) * args.alpha
        crossings = planes[p][2]  # the shared design keeps plane shares too
        shared = (N * args.t_reject + crossings * N * t_deep + hops + 16 * N * beta +
                  8 * N * args.gamma)

        def routed(terms):
            visits, waves, _ = terms[p]
            wave = (3 * math.ceil(math.log2(p)) * args.alpha + 4 * p * beta +
                    min(p - 1, args.neighbours) * args.alpha)
            return visits * N * (t_deep + args.t_route) + visits * N * 64 * beta + waves * wave

        print(f"| {p // 32} | {p} | {n / 1e6:.2f} M | {N / shared:.3g} | "
              f"{N / routed(morton):.3g} | {N / routed(planes):.3g} |")


if __name__ == "__main__":
    main(sys.argv[1:])
