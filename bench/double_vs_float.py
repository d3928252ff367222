#!/usr/bin/python3
"""Double precision against float: rays per second of each instruction set's brute force and
tree, one query per ray, on the same scenes and rays in one run of sphray_bench (its double/,
double-tree/ and double-points/ rows), the ratio double/float, for the trees the ratio to
Embree's float rtcIntersect1 on one thread, and the nearest sphere to a point through a tree.
Prints the markdown tables of docs/double.md.

Run from the repository root after a release build:
    /usr/bin/python3 bench/double_vs_float.py [--bench build/release/bench/sphray_bench]
"""
import argparse
import json
import subprocess
import tempfile


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bench", default="build/release/bench/sphray_bench")
    ap.add_argument("--min-time", default="0.3")
    ap.add_argument("--only", choices=["rays", "points"],
                    help="run the ray rows (double/, double-tree/) or the point rows alone")
    args = ap.parse_args()
    rows = {None: "^double(-tree|-points)?/", "rays": "^double(-tree)?/",
            "points": "^double-points/"}[args.only]
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        subprocess.run([args.bench, f"--benchmark_filter={rows}",
                        f"--benchmark_min_time={args.min_time}",
                        f"--benchmark_out={out.name}", "--benchmark_out_format=json"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        report = json.load(open(out.name))
    rates = {}
    for b in report["benchmarks"]:
        if "error_occurred" in b and b["error_occurred"]:
            raise SystemExit(f"{b['name']}: {b.get('error_message')}")
        group, scene, kind, isa, precision = b["name"].split("/")[:5]
        rates[(group, scene, kind, isa, precision)] = b["items_per_second"] / 1e6
    if args.only != "points":
        print_ray_tables(rates)
    if args.only != "rays":
        print_point_table(rates)


def print_ray_tables(rates):
    print("Brute force:\n")
    print("| scene | rays | instruction set | float Mrays/s | double Mrays/s | double/float |")
    print("|---|---|---|---:|---:|---:|")
    for (group, scene, kind, isa, precision), f in rates.items():
        if group != "double" or precision != "float":
            continue
        d = rates[(group, scene, kind, isa, "double")]
        print(f"| {scene} | {kind} | {isa} | {f:.2f} | {d:.2f} | {d / f:.2f}x |")
    print("\nTrees (auto: the instruction set a tree built without one gets):\n")
    print("| scene | rays | instruction set | float Mrays/s | double Mrays/s | double/float "
          "| Embree Mrays/s | double/Embree |")
    print("|---|---|---|---:|---:|---:|---:|---:|")
    for (group, scene, kind, isa, precision), f in rates.items():
        if group != "double-tree" or precision != "float" or isa == "embree":
            continue
        d = rates[(group, scene, kind, isa, "double")]
        e = rates.get((group, scene, kind, "embree", "float"))
        embree = f"| {e:.2f} | {d / e:.2f}x |" if e else "| - | - |"
        print(f"| {scene} | {kind} | {isa} | {f:.2f} | {d:.2f} | {d / f:.2f}x {embree}")


def print_point_table(rates):
    print("\nThe nearest sphere to a point, through a tree (points: the incoherent rays' "
          "origins):\n")
    print("| scene | float Mpoints/s | double Mpoints/s | double/float |")
    print("|---|---:|---:|---:|")
    for (group, scene, kind, isa, precision), f in rates.items():
        if group != "double-points" or precision != "float":
            continue
        d = rates[(group, scene, kind, isa, "double")]
        print(f"| {scene} | {f:.2f} | {d:.2f} | {d / f:.2f}x |")


if __name__ == "__main__":
    main()
