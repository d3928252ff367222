#!/usr/bin/python3
"""Particles at scale: from a particle file on disk to the first image, at 1M, 10M and 100M.

For each size it writes a .sphp file of random spheres (bench/make_cloud.py; kept and reused
when already there), then
  - renders it: `sphray render -s FILE -m normals -W 1920 -H 1080 --spp 1`, whose second summary
    line gives the phases (scene read, tree, render, write), the first image's time and the peak
    resident memory;
  - times reading it and building sphray's tree and Embree's over the same spheres, on one and on
    all threads: `sphray_bench_particles --particles=FILE`.
It prints the section "Particles at scale" of docs/performance.md (the table and the goals of
issue 34, met or missed) and, with --write-docs, replaces that section of the page (bench/run.sh
keeps it as it stands). A size that does not fit the machine's free memory is left out, said so.

Run from the repository root after a release build (about 15 minutes at the three sizes, 1.8 GB
of files in --dir), on a quiet machine:
    /usr/bin/python3 bench/particles_scale.py --dir /tmp/particles --out scale.json --write-docs
    /usr/bin/python3 bench/particles_scale.py --sizes 1000000 --dir /tmp/particles   # quick
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import make_cloud  # noqa: E402

PHASES = re.compile(
    r"phases: scene (?P<scene>[\d.]+) s, tree (?P<tree>[\d.]+) s, render (?P<render>[\d.]+) s, "
    r"write (?P<write>[\d.]+) s; first image in (?P<first>[\d.]+) s; peak memory (?P<mb>[\d.]+) MB")


def free_bytes():
    with open("/proc/meminfo") as f:
        for line in f:
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    return 0


def render(sphray, path, out_png):
    cmd = [sphray, "render", "-s", path, "-m", "normals", "-W", "1920", "-H", "1080", "--spp", "1",
           "-o", out_png, "--force"]
    run = subprocess.run(cmd, capture_output=True, text=True, check=True)
    m = PHASES.search(run.stdout)
    if not m:
        sys.exit("no phases line in: " + run.stdout)
    shown = cmd[:-3] + ["-o", "cloud.png"]
    return {k: float(v) for k, v in m.groupdict().items()}, " ".join(shown)


def bench(program, path, min_time, repetitions):
    """Each row's median over the repetitions, and its first repetition apart ("/first")."""
    cmd = [program, "--particles=" + path, "--benchmark_min_time=%g" % min_time,
           "--benchmark_repetitions=%d" % repetitions, "--benchmark_format=json"]
    run = subprocess.run(cmd, capture_output=True, text=True, check=True)
    rows = {}
    for b in json.loads(run.stdout)["benchmarks"]:
        name = b["run_name"].replace("/manual_time", "")
        if b["run_type"] == "aggregate" and b["aggregate_name"] == "median":
            rows[name] = b
        elif b["run_type"] == "iteration" and b["repetition_index"] == 0:
            rows[name + "/first"] = b
    return rows, " ".join(cmd[:-1])


def seconds(row):
    assert row["time_unit"] == "ms"
    return row["real_time"] / 1e3


def measure(n, args):
    path = os.path.join(args.dir, "cloud%d.sphp" % n)
    if not os.path.exists(path) or os.path.getsize(path) != 32 + 16 * n:
        make_cloud.write_cloud(n, path, seed=1)
    phases, render_cmd = render(args.sphray, path, os.path.join(args.dir, "cloud%d.png" % n))
    rows, bench_cmd = bench(args.bench, path, args.min_time, args.repetitions)
    return {"spheres": n, "file_bytes": 32 + 16 * n, "render": phases, "rows": rows,
            "render_command": render_cmd, "bench_command": bench_cmd}


def short(n):
    return "%dM" % (n // 1000000) if n % 1000000 == 0 else str(n)


def table(results, threads, baseline_mb):
    lines = [
        "| spheres | read (GB/s) | tree build, %d threads (ns per sphere; the first build) "
        "| tree bytes per sphere "
        "| rtcCommitScene, %d threads (ns per sphere; the first build) | Embree bytes per sphere "
        "| build / Embree's "
        "| first image: scene, tree, render, write | peak memory (bytes per sphere) "
        "| peak over the one-sphere render (bytes per sphere) |" % (threads, threads),
        "|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        n, rows, p = r["spheres"], r["rows"], r["render"]
        read = rows["particles/read"]
        tree = rows["particles/build/bvh/threads:%d" % threads]
        emb = rows.get("particles/build/embree/threads:%d" % threads)
        t = seconds(tree)
        e = seconds(emb) if emb else None

        def first(name):
            return seconds(rows[name + "/first"]) / n * 1e9
        lines.append(
            "| %s | %.3f s (%.2f) | %.2f s (%.0f; %.0f) | %.1f | %s | %s | %s "
            "| %.1f s: %.2f, %.2f, %.2f, %.2f s "
            "| %.2f GB (%.1f) | %.1f |" % (
                short(n), seconds(read), read["bytes_per_second"] / 1e9, t, t / n * 1e9,
                first("particles/build/bvh/threads:%d" % threads), tree["bytes_per_sphere"],
                "%.2f s (%.0f; %.0f)" % (
                    e, e / n * 1e9, first("particles/build/embree/threads:%d" % threads))
                if e else "-",
                "%.1f" % emb["bytes_per_sphere"] if emb else "-",
                "%.2fx" % (t / e) if e else "-",
                p["first"], p["scene"], p["tree"], p["render"], p["write"],
                p["mb"] / 1e3, p["mb"] * 1e6 / n, per_sphere_over_baseline(r, baseline_mb) + 16))
    return "\n".join(lines)


def per_sphere_over_baseline(r, baseline_mb):
    """Peak bytes per sphere above the same render of a one-sphere file, less the file's 16."""
    return (r["render"]["mb"] - baseline_mb) * 1e6 / r["spheres"] - 16


def goals(results, threads, baseline_mb):
    out = []
    first, last = results[0], results[-1]
    for r in results:
        over = per_sphere_over_baseline(r, baseline_mb)
        out.append("- peak memory per sphere over the file's 16 bytes, %s: %.1f bytes (goal <= 48): "
                   "%s" % (short(r["spheres"]), over, "met" if over <= 48 else "missed"))
    key = "particles/build/bvh/threads:%d" % threads
    per = [seconds(r["rows"][key]) / r["spheres"] for r in results]
    ratio = per[-1] / per[0]
    out.append("- tree build per sphere, %s against %s: %.2fx (goal <= 1.3x): %s"
               % (short(last["spheres"]), short(first["spheres"]), ratio,
                  "met" if ratio <= 1.3 else "missed"))
    for r in results:
        emb = r["rows"].get("particles/build/embree/threads:%d" % threads)
        if emb:
            x = seconds(r["rows"][key]) / seconds(emb)
            out.append("- tree build against rtcCommitScene, %s: %.2fx (goal <= 0.5x): %s"
                       % (short(r["spheres"]), x, "met" if x <= 0.5 else "missed"))
        gbs = r["rows"]["particles/read"]["bytes_per_second"] / 1e9
        mapped = r["rows"]["particles/read_mapped"]["bytes_per_second"] / 1e9
        out.append("- reading the .sphp, %s: %.2f GB/s with pread (goal >= 1): %s; through a "
                   "memory map, for comparison: %.2f GB/s"
                   % (short(r["spheres"]), gbs, "met" if gbs >= 1 else "missed", mapped))
    return "\n".join(out)


HEADING = "## Particles at scale"

INTRO = """Issue 34: from a particle file on disk to the first image, for 1M, 10M and 100M random spheres
(`bench/make_cloud.py`: uniform in a cube that grows with the count, radii 0.2 to 0.6, the same
density at every size) in `.sphp` files of 16 bytes a sphere. The render is `sphray render -m
normals`, 1920x1080, one sample per pixel, on every core; its second summary line gives each
phase and the peak resident memory of the whole process (the spheres, the tree, the build's
records, the image). Read and build times are `sphray_bench_particles` on the same file, in
another process: the read into a `SphereSoA` (the library's `pread`, and a memory map beside it
for comparison), sphray's tree build and Embree's `rtcCommitScene` (its `bytes_per_sphere` from
Embree's own memory monitor, the spheres' buffer included) on the same spheres. Each is timed
three times in the process and its figure is the median, at every size and for both libraries,
and the goals are judged on these. The first build of a process is shown beside it: it also pays
for the system handing the process fresh memory, page by page, which later builds reuse (at 1M
from the allocator's own free lists, at 100M from the system's), so that comparing one process's
first build at 100M with repeated builds at 1M, as this page did until 2026-11-26, measured the
memory's history as much as the build. Regenerate this
section with `bench/particles_scale.py --write-docs` (the commands below); `bench/run.sh` keeps it
as it stands."""


def section(results, threads, load, when, baseline_mb):
    def shown(command):  # the file by its name, wherever --dir put it
        return re.sub(r"[^ =]*/(cloud\d+\.sphp)", r"\1", command)

    return "\n".join([
        HEADING, "", INTRO, "",
        "Measured %s on the machine above, load average %s at the end. Commands, per size (the "
        "files written by `bench/make_cloud.py N cloudN.sphp`): `%s`, `%s`." % (when, ", ".join(load), shown(results[0]["render_command"]),
                                 shown(results[0]["bench_command"])),
        "", "The same render of a one-sphere file peaks at %.1f MB (the program, its libraries, "
        "the 1920x1080 image and its PNG): the last column is the peak above that, per sphere, "
        "which is what the spheres cost (at 1M the fixed part is a large share of the raw figure)."
        % baseline_mb,
        "", table(results, threads, baseline_mb), "", goals(results, threads, baseline_mb)])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", type=int, nargs="+", default=[1000000, 10000000, 100000000])
    p.add_argument("--dir", default="build/particles-scale", help="where the files go")
    p.add_argument("--sphray", default="build/release/render/sphray")
    p.add_argument("--bench", default="build/release/bench/sphray_bench_particles")
    p.add_argument("--min-time", type=float, default=1.0,
                   help="Google Benchmark's, per row and repetition")
    p.add_argument("--repetitions", type=int, default=3,
                   help="times each row is timed in the process: its figure is their median")
    p.add_argument("--threads", type=int, default=os.cpu_count())
    p.add_argument("--out", help="also write the measurements as JSON")
    p.add_argument("--write-docs", action="store_true",
                   help="replace the section of docs/performance.md")
    p.add_argument("--from-json", help="no measuring: the section from a JSON --out wrote")
    args = p.parse_args()
    if args.from_json:
        with open(args.from_json) as f:
            saved = json.load(f)
        results, load = saved["results"], saved["load_average"]
        baseline_mb = saved["baseline_mb"]
        when = saved.get("date", time.strftime("%Y-%m-%d"))
    else:
        results, baseline_mb = measure_all(args)
        load = loadavg()
        when = time.strftime("%Y-%m-%d")
    text = section(results, args.threads, load, when, baseline_mb)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            json.dump({"load_average": load, "date": when, "baseline_mb": baseline_mb,
                       "results": results}, f, indent=1)
    if args.write_docs:
        from report import update_section  # needs matplotlib, only here
        update_section(Path(ROOT) / "docs", HEADING, text, before="## The Python module against numpy")


def loadavg():
    with open("/proc/loadavg") as f:
        return f.read().split()[:3]


def measure_all(args):
    os.makedirs(args.dir, exist_ok=True)
    one = os.path.join(args.dir, "cloud1.sphp")
    make_cloud.write_cloud(1, one, seed=1)
    baseline_mb = render(args.sphray, one, os.path.join(args.dir, "cloud1.png"))[0]["mb"]
    results = []
    for n in args.sizes:
        # The render holds the spheres and a tree; the bench holds them, sphray's tree and
        # Embree's: about 150 bytes per sphere at most.
        if free_bytes() < 150 * n:
            print("left out: %d spheres need about %.1f GB, %.1f GB available"
                  % (n, 150 * n / 1e9, free_bytes() / 1e9), file=sys.stderr)
            continue
        start = time.time()
        results.append(measure(n, args))
        print("measured %d spheres in %.0f s" % (n, time.time() - start), file=sys.stderr)
    if not results:
        sys.exit("nothing measured")
    return results, baseline_mb


if __name__ == "__main__":
    main()
