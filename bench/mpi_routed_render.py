#!/usr/bin/env python3
"""sphray-mpi render --distribution routed on 2 ranks against sphray render -j 1, 4.2M spheres.

    /usr/bin/python3 bench/mpi_routed_render.py [--build build/release] [--repeats 3]

Writes random:4194304 as a particle file (once, in a temporary directory) and renders it,
normals 1024x1024 at 16 samples per pixel, from the file's own camera and from each axis, with
one process on one thread and with 2 ranks of one thread each (the spheres split by planes
across the view, every rank its own tiles, every ray routed only to the regions it crosses);
interleaved, best of --repeats by the rendering time each command prints (the tree's build and
the file's reading are not in it). Checks that both images are the same bytes. Prints a
markdown table for docs/distributed.md.
"""

import filecmp
import os
import re
import subprocess
import sys
import tempfile

import mpi_runs

VIEWS = [("the file's camera", []),
         ("from x", ["--lookfrom", "300,0,0", "--lookat", "0,0,0"]),
         ("from y", ["--lookfrom", "0,300,0.001", "--lookat", "0,0,0"]),
         ("from z", ["--lookfrom", "0,0,300", "--lookat", "0,0,0"])]
IMAGE = ["-m", "normals", "-W", "1024", "-H", "1024", "--spp", "16"]


def run(command):
    """The command's 'wrote ...' line."""
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    for line in done.stdout.splitlines() + done.stderr.splitlines():
        if line.startswith("wrote "):
            return line
    sys.exit(f"no 'wrote' line from {' '.join(command)}:\n{done.stdout}{done.stderr}")


def seconds_and_rate(line):
    """The rendering time and rays per second a 'wrote' line states."""
    match = re.search(r", ([0-9.]+) s, ([0-9.e+]+) (M?)rays/s", line)
    if not match:
        sys.exit(f"no time in: {line}")
    rate = float(match.group(2)) * (1e6 if match.group(3) else 1.0)
    return float(match.group(1)), rate


def main(argv):
    args, programs = mpi_runs.parse(__doc__, argv)
    sphray, sphray_mpi = programs.sphray, programs.sphray_mpi
    mpiexec = [*programs.mpiexec, "-n", "2"]
    print("| view | 1 process: s | 1 process: rays/s | 2 ranks, routed: s | 2 ranks: rays/s | "
          "2 ranks / 1 process | rays traced in the trees a ray: all ranks | the busiest rank "
          "| same image |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        particles = mpi_runs.particle_file(programs, tmp)
        one_png, two_png = os.path.join(tmp, "one.png"), os.path.join(tmp, "two.png")
        for name, camera in VIEWS:
            scene = ["-s", particles, *IMAGE, *camera]
            ones, twos = [], []
            for _ in range(args.repeats):
                ones.append(run([sphray, "render", *scene, "-j", "1", "-o", one_png]))
                twos.append(run([*mpiexec, sphray_mpi, "render", *scene, "--distribution",
                                 "routed", "-o", two_png, "--force"]))
            one = min((seconds_and_rate(line) for line in ones), key=lambda sr: sr[0])
            best = min(twos, key=lambda line: seconds_and_rate(line)[0])
            two = seconds_and_rate(best)
            traced = re.search(r"([0-9.]+) rays traced in the trees a ray, ([0-9.]+) in", best)
            same = "yes" if filecmp.cmp(one_png, two_png, shallow=False) else "NO"
            print(f"| {name} | {one[0]:.3f} | {one[1]:.3g} | {two[0]:.3f} | {two[1]:.3g} | "
                  f"{one[0] / two[0]:.2f}x | {traced.group(1)} | {traced.group(2)} | {same} |")
            sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv[1:])
