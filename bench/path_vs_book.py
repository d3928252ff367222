#!/usr/bin/python3
"""Path mode against the book's way (issue 33): `sphray render -m path` on one thread against
the same path tracer written the way Ray Tracing in One Weekend writes it (sphray_book_path,
bench/book_path_tracer.cpp), on `three` and render/scenes/materials.json.

Both programs render each scene at 160x90, 512 samples a pixel, on one thread (sphray with
`--threads 1`), three runs each, interleaved (sphray, book, sphray, book, ...) so that a change
in the machine's load touches both; the best rate of each counts. The rates are those the two
summary lines print: camera and bounce rays, every ray each program intersects with the scene,
over the tracing time alone. It prints the section "Path mode against the book's way" of
docs/performance.md (the table, the target of 8x, the exact commands) and, with --write-docs,
replaces that section of the page (bench/run.sh keeps it as it stands).

It builds nothing. Run from the repository root after
    cmake --build build/release --target sphray sphray_book_path
on a quiet machine (well under a minute, most of it the book's way):
    /usr/bin/python3 bench/path_vs_book.py --write-docs
    /usr/bin/python3 bench/path_vs_book.py --spp 8    # a quick check that it runs
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HEADING = "## Path mode against the book's way"
# The section goes after "Bounce rays" on a page without it (bench/report.py keeps it there).
BEFORE = "## Queries beyond the closest hit"
SCENES = ["three", "render/scenes/materials.json"]
TARGET = 8.0
# The frame the issue names: --write-docs refuses any other, so that a quick check never lands
# on the page.
ISSUE_FRAME = {"width": 160, "height": 90, "spp": 512}
SUMMARY = re.compile(r"wrote .*?, (?P<seconds>[\d.]+) s, (?P<rate>[\d.]+) Mrays/s "
                     r"\((?P<camera>\d+) camera \+ (?P<bounce>\d+) bounce")


def commands(args, scene, out_dir):
    frame = ["-W", str(args.width), "-H", str(args.height), "--spp", str(args.spp)]
    sphray = [args.sphray, "render", "-m", "path", "--threads", "1", "-s", scene] + frame + [
        "-o", os.path.join(out_dir, "sphray.png")]
    book = [args.book, "-s", scene] + frame + ["-o", os.path.join(out_dir, "book.png")]
    return {"sphray": sphray, "book": book}


def run(command):
    done = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
    if done.returncode != 0:
        sys.exit("failed (%d): %s\n%s%s" % (done.returncode, " ".join(command), done.stdout,
                                            done.stderr))
    m = SUMMARY.search(done.stdout)
    if not m:
        sys.exit("no summary line in the output of %s:\n%s" % (" ".join(command), done.stdout))
    return {"mrays": float(m["rate"]), "seconds": float(m["seconds"]),
            "camera": int(m["camera"]), "bounce": int(m["bounce"])}


def shown(command):
    """The command as the page shows it: the programs and scenes by their paths in the
    repository, the image in the current folder."""
    out = []
    for part in command:
        if part.endswith(".png"):
            part = os.path.basename(part)
        elif os.path.isabs(part) and part.startswith(ROOT + os.sep):
            part = os.path.relpath(part, ROOT)
        out.append(part)
    return " ".join(out)


def measure(args):
    results = []
    with tempfile.TemporaryDirectory(prefix="path-vs-book-") as out_dir:
        for scene in args.scenes:
            cmds = commands(args, scene, out_dir)
            runs = {"sphray": [], "book": []}
            for _ in range(args.runs):
                for who in ("sphray", "book"):
                    runs[who].append(run(cmds[who]))
                    print("%s, %s: %.2f Mrays/s" % (scene, who, runs[who][-1]["mrays"]),
                          file=sys.stderr)
            best = {who: max(r, key=lambda x: x["mrays"]) for who, r in runs.items()}
            results.append({"scene": scene, "runs": runs, "best": best,
                            "commands": {who: shown(c) for who, c in cmds.items()}})
    return results


def name(scene):
    return "`%s`" % (os.path.basename(scene) if scene.endswith(".json") else scene)


def table(results):
    lines = ["| scene | sphray Mrays/s | book's way Mrays/s | ratio | target >= %gx "
             "| rays per path: sphray, book's way |" % TARGET,
             "|---|---|---|---|---|---|"]
    for r in results:
        s, b = r["best"]["sphray"], r["best"]["book"]
        ratio = s["mrays"] / b["mrays"] if b["mrays"] > 0 else float("inf")
        per_path = ["%.3f" % ((x["camera"] + x["bounce"]) / x["camera"]) for x in (s, b)]
        lines.append("| %s | %.2f | %.2f | %.2fx | %s | %s, %s |" % (
            name(r["scene"]), s["mrays"], b["mrays"], ratio, "met" if ratio >= TARGET else "missed",
            per_path[0], per_path[1]))
    return "\n".join(lines)


INTRO = """Issue 33: `sphray render -m path` on one thread against the same path tracer written
the way *Ray Tracing in One Weekend* writes it, `sphray_book_path` (`bench/book_path_tracer.cpp`):
double precision, a `hittable` base class whose virtual `hit()` a `hittable_list` calls for every
sphere, one ray at a time, a recursive `ray_color`, the book's Lambertian, metal and dielectric
materials behind a virtual `scatter`, one `std::mt19937_64`. It renders what path mode renders, by
the same rules (the book's camera, each sample jittered in its pixel, the scene's materials and
sky, at most 50 rays a path, the mean of the samples, gamma 2), taking only the scene loader and
the image writer from sphray; `tests/render/book_path_test.cpp` checks that the two images agree
in expectation and that their paths trace as many rays. Both count every ray they intersect with
the scene (camera and bounce rays) and give the rate over the tracing alone. The scenes: `three`
(three Lambertian spheres, no ground) and `render/scenes/materials.json` (11 spheres: a ground,
glass of index 1.5 and 1.8, a mirror and a fuzzed metal, six Lambertian colours), at %dx%d, %d
samples a pixel, best of %d runs of each program, interleaved. Target: sphray at least %gx the
book's way on both. Regenerate this section with `bench/path_vs_book.py --write-docs`;
`bench/run.sh` keeps it as it stands."""


def loadavg():
    with open("/proc/loadavg") as f:
        return f.read().split()[:3]


def section(results, frame, when, load):
    cmds = []
    for r in results:
        cmds.append("`%s`" % r["commands"]["sphray"])
        cmds.append("`%s`" % r["commands"]["book"])
    return "\n".join([
        HEADING, "",
        INTRO % (frame["width"], frame["height"], frame["spp"], frame["runs"], TARGET), "",
        "Measured %s on the machine above, load average %s at the end. Commands: %s." % (
            when, ", ".join(load), ", ".join(cmds)),
        "", table(results)])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sphray", default=os.path.join(ROOT, "build/release/render/sphray"))
    p.add_argument("--book", default=os.path.join(ROOT, "build/release/bench/sphray_book_path"))
    p.add_argument("--scenes", nargs="+", default=SCENES)
    p.add_argument("--width", type=int, default=ISSUE_FRAME["width"])
    p.add_argument("--height", type=int, default=ISSUE_FRAME["height"])
    p.add_argument("--spp", type=int, default=ISSUE_FRAME["spp"])
    p.add_argument("--runs", type=int, default=3, help="runs of each program per scene")
    p.add_argument("--out", help="also write the measurements as JSON")
    p.add_argument("--write-docs", action="store_true",
                   help="replace the section of docs/performance.md (the issue's frame only)")
    args = p.parse_args()
    frame = {"width": args.width, "height": args.height, "spp": args.spp, "runs": args.runs}
    issue_frame = (all(frame[k] == v for k, v in ISSUE_FRAME.items()) and args.runs >= 3
                   and args.scenes == SCENES)
    if args.write_docs and not issue_frame:
        p.error("--write-docs takes the issue's frame only: the default scenes, size, samples "
                "and at least 3 runs")
    for program in (args.sphray, args.book):
        if not os.access(program, os.X_OK):
            sys.exit("%s: not built (cmake --build build/release --target sphray sphray_book_path)"
                     % program)
    results = measure(args)
    when, load = time.strftime("%Y-%m-%d"), loadavg()
    text = section(results, frame, when, load)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            json.dump({"date": when, "load_average": load, "frame": frame, "results": results}, f,
                      indent=1)
    if args.write_docs:
        sys.path.insert(0, os.path.join(ROOT, "bench"))
        from report import update_section  # needs matplotlib, only here
        update_section(Path(ROOT) / "docs", HEADING, text, before=BEFORE)


if __name__ == "__main__":
    main()
