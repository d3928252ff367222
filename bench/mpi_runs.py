"""What the MPI benchmark scripts share: their options, the programs they run, the load line."""

import argparse
import os
import subprocess


class Programs:
    """The build's sphray and sphray-mpi, and mpiexec with the flags asked for."""

    def __init__(self, args):
        self.sphray = os.path.join(args.build, "render", "sphray")
        self.sphray_mpi = os.path.join(args.build, "mpi", "sphray-mpi")
        self.mpiexec = ["mpiexec", *args.mpiexec_flags.split()]


def parse(doc, argv):
    """The scripts' options (--build, --repeats, --mpiexec-flags); prints the load line."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--mpiexec-flags", default="--oversubscribe",
                    help="extra flags for mpiexec (as root add --allow-run-as-root)")
    args = ap.parse_args(argv)
    print(f"load average {os.getloadavg()[0]:.1f} at the start, {os.cpu_count()} cores")
    return args, Programs(args)


def particle_file(programs, folder, preset="random:4194304"):
    """preset written as a particle file in folder; its path."""
    path = os.path.join(folder, "particles.sphp")
    subprocess.run([programs.sphray_mpi, "generate", preset, "-o", path], check=True,
                   capture_output=True)
    return path
