#!/usr/bin/env python3
"""Turns the JSON of a sphray_bench run into docs/performance.md and its plots.

    bench/report.py RUN.json [--command "how the run was made"] [--docs docs]

Needs Python 3 and matplotlib (Debian: python3-matplotlib). Reads bench/kernel_analysis.md
(the hand count of the kernel's inner loop) and bench/kernel_bounds.json (its bounds) from
beside this script and puts them in the page next to the measured cycles per batch.
"""

import argparse
import json
import statistics
import sys
from dataclasses import dataclass, field
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

HERE = Path(__file__).resolve().parent
KINDS = ("coherent", "incoherent")
# Issue 12: the rays a path-traced frame traces after the camera's, on these scenes.
BOUNCE_KIND = "bounce"
BOUNCE_SCENES = ("rtiow-final", "random:65536")
BOUNCE_OVER_INTERSECT1 = 1.2
BOUNCE_OVER_INTERSECT8 = 1.0
KIND_TITLES = {
    "coherent": "Coherent rays (a 512 x 512 pinhole camera framing the scene)",
    "incoherent": "Incoherent rays (random origins in the scene box, uniform directions)",
}
ISAS = ("sse4.2", "avx2", "avx512", "neon")
# The targets, restated where they are checked.
TARGET_SPEEDUP = {"avx2": 6.0, "avx512": 9.0}
TARGET_SPEEDUP_SCENES = (512, 65536)
TINY_SCENES = (1, 8)
SMALL_SCENES = (1, 64)
TARGET_OVER_EMBREE = 3.0
TARGET_THREAD_SCALING = 1.8
TARGET_BOUND_FACTOR = 1.5
# Issue 5: the BVH against Embree's sphere BVH.
BVH_SCENES = ("rtiow-final", "random:4096", "random:65536", "random:1048576")
BVH_OVER_INTERSECT1 = 1.2
BVH_OVER_INTERSECT8 = 1.0
BVH_BUILD_FACTOR = 0.8
BVH_REFIT_SPEEDUP = 5.0
BVH_BYTES_PER_SPHERE = 40.0
BVH_BUILD_SCENE = "random:1048576"
# Issue 35: the every-crossing queries against Embree's filter idiom on the same rays.
EVERY_HIT_SCENES = ("rtiow-final", "random:4096", "random:65536")
ALL16_OVER_FILTER = 1.5
COUNT_OVER_FILTER = 2.0
SIMD_FLAGS = ("sse4_2", "avx", "avx2", "fma", "avx512f", "avx512dq", "avx512bw", "avx512vl",
              "avx512_fp16", "amx_tile", "neon", "asimd")


@dataclass
class Row:
    """One benchmark's result."""

    group: str  # "rays", "build" or "clock"
    scene: str = ""
    kind: str = ""
    impl: str = ""
    threads: int = 1
    values: dict = field(default_factory=dict)
    error: str = ""

    def get(self, key, default=None):
        return self.values.get(key, default)


def parse_name(name):
    """'rays/<scene>/<kind>/<impl>/threads:<n>/real_time' and 'build/<scene>/<builder>/threads:<n>/...'."""
    parts = [p for p in name.split("/") if p not in ("real_time", "manual_time")]
    threads = 1
    if parts and parts[-1].startswith("threads:"):
        threads = int(parts.pop()[len("threads:"):])
    if parts[0] == "rays" and len(parts) == 4:
        return Row("rays", scene=parts[1], kind=parts[2], impl=parts[3], threads=threads)
    if parts[0] == "build" and len(parts) == 3:
        return Row("build", scene=parts[1], impl=parts[2], threads=threads)
    if parts[0] == "clock" and len(parts) == 2:
        return Row("clock", impl=parts[1])
    if parts[0] == "queries" and len(parts) == 4:
        return Row("queries", scene=parts[1], kind=parts[2], impl=parts[3], threads=threads)
    if parts[0] == "every_hit" and len(parts) == 4:
        return Row("every_hit", scene=parts[1], kind=parts[2], impl=parts[3], threads=threads)
    return None


def load_rows(data):
    """The rows of a run; with repetitions, their medians."""
    by_name = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        name = b.get("run_name", b["name"])
        row = parse_name(name)
        if row is None:
            continue
        row.values = b
        row.error = b.get("error_message", "") if b.get("error_occurred") else ""
        # A median replaces the repetitions it summarises; errors always stay.
        if b.get("run_type") == "aggregate" or name not in by_name or row.error:
            by_name[name] = row
    return list(by_name.values())


class Results:
    def __init__(self, rows, context):
        self.rows = rows
        self.tsc_mhz = float(context.get("mhz_per_cpu", 0))
        self.rays = {(r.scene, r.kind, r.impl, r.threads): r for r in rows if r.group == "rays"}
        self.builds = [r for r in rows if r.group == "build"]
        self.clock = {r.impl: r for r in rows if r.group == "clock" and not r.error}
        self.queries = {(r.scene, r.kind, r.impl): r for r in rows if r.group == "queries"}
        self.every_hit = {(r.scene, r.kind, r.impl): r for r in rows if r.group == "every_hit"}
        self.scenes = []
        for r in rows:
            if r.group == "rays" and r.scene not in self.scenes:
                self.scenes.append(r.scene)
        self.spheres = {}
        for r in rows:
            if r.group == "rays" and r.get("spheres") is not None:
                self.spheres[r.scene] = int(r.get("spheres"))
        self.all_threads = max((r.threads for r in rows if r.group == "rays"), default=1)

    def row(self, scene, kind, impl, threads=1):
        r = self.rays.get((scene, kind, impl, threads))
        return r if r is not None and not r.error else None

    def rate(self, scene, kind, impl, threads=1, key="items_per_second"):
        r = self.row(scene, kind, impl, threads)
        return r.get(key) if r is not None else None

    def isas(self):
        present = {r.impl for r in self.rays.values()}
        return [i for i in ISAS if i in present]

    def has(self, impl, threads=1):
        return any(k[2] == impl and k[3] == threads for k in self.rays)

    def random_scenes(self):
        return [s for s in self.scenes if s.startswith("random:")]

    def scenes_between(self, lo, hi, random_only=False):
        pool = self.random_scenes() if random_only else self.scenes
        return [s for s in pool if lo <= self.spheres.get(s, 0) <= hi]

    def core_per_tsc(self):
        core = self.clock.get("core")
        return core.get("core_cycles_per_tsc_tick") if core is not None else None

    def instruction_cycles(self, name):
        """Measured reciprocal throughput of an instruction, in core cycles."""
        r, k = self.clock.get(name), self.core_per_tsc()
        return r.get("tsc_per_instruction") * k if r is not None and k is not None else None


def ratio(a, b):
    return a / b if a is not None and b not in (None, 0) else None


def fmt_rate(x):
    """Rays per second with a unit prefix and three significant digits."""
    if x is None:
        return "–"
    for scale, prefix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if x >= scale:
            return f"{x / scale:.3g} {prefix}"
    return f"{x:.3g}"


def fmt_ratio(x):
    return "–" if x is None else f"{x:.2f}x"


def fmt_num(x, digits=3):
    return "–" if x is None else f"{x:.{digits}g}"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


# --- columns -------------------------------------------------------------------------------

def columns(res):
    """(label, impl, threads) of every implementation a rays table shows, in reading order."""
    cols = [("scalar", "scalar", 1)]
    cols += [(isa, isa, 1) for isa in res.isas()]
    cols += [("dispatch", "dispatch", 1), ("dispatch stream", "dispatch-stream", 1)]
    n = res.all_threads
    if n > 1:
        cols.append((f"dispatch stream, {n} threads", "dispatch-stream", n))
    for impl in ("bvh", "bvh-stream", "bvh-arrays"):
        if res.has(impl):
            cols.append((impl.replace("-", " "), impl, 1))
    if n > 1 and res.has("bvh-stream", n):
        cols.append((f"bvh stream, {n} threads", "bvh-stream", n))
    if res.has("embree-intersect1"):
        cols.append(("Embree rtcIntersect1", "embree-intersect1", 1))
        if n > 1:
            cols.append((f"Embree rtcIntersect1, {n} threads", "embree-intersect1", n))
    if res.has("embree-intersect8"):
        cols.append(("Embree rtcIntersect8", "embree-intersect8", 1))
        if n > 1:
            cols.append((f"Embree rtcIntersect8, {n} threads", "embree-intersect8", n))
    return [c for c in cols if res.has(c[1], c[2])]


def scene_label(res, scene):
    return f"{scene} ({res.spheres.get(scene, '?')})"


def brute_rays(res, scene, kind):
    r = res.row(scene, kind, "scalar")
    return int(r.get("rays")) if r is not None else None


# --- sections ------------------------------------------------------------------------------

def machine_section(ctx, command):
    flags = set(ctx.get("cpu_flags", "").split())
    simd = " ".join(f for f in SIMD_FLAGS if f in flags) or "none of note"
    caches = ", ".join(
        f"L{c['level']} {c['type'].lower()} {c['size'] // 1024} KiB" + (f" (shared by {c['num_sharing']})" if c.get("num_sharing", 1) > 1 else "")
        for c in ctx.get("caches", []))
    load = ", ".join(f"{x:.2f}" for x in ctx.get("load_avg", []))
    lines = [
        "## The machine and the run",
        "",
        f"- CPU: {ctx.get('cpu_model', 'unknown')} (family/model/stepping {ctx.get('cpu_signature', '?')}), "
        f"{ctx.get('num_cpus', '?')} logical CPUs, time stamp counter {ctx.get('mhz_per_cpu', '?')} MHz",
        f"- SIMD flags: {simd}",
        f"- Caches: {caches}",
        f"- sphray kernels this machine runs: {ctx.get('sphray_isas', '?')} (dispatched: {ctx.get('sphray_active_isa', '?')}); "
        f"\"all threads\" = {ctx.get('threads_all', '?')}",
        f"- Intel Embree: {ctx.get('embree_version', 'not built in')}",
        f"- Run: {ctx.get('date', '?')}, load average at start {load}",
        f"- Command: `{command}`",
    ]
    cpus = ctx.get("num_cpus", 0)
    busy = ctx.get("load_avg", [0])[0]
    if cpus and busy > 0.5 * cpus:
        lines += ["", f"**This run shared the machine with other work** (load average {busy:.1f} on {cpus} CPUs when it",
                  "started): absolute rates and, above all, the scaling to more threads are understated and noisy.",
                  "Re-run `bench/run.sh` on a quiet machine before quoting them; the cycles-per-batch figures",
                  "are measured so that time taken by other processes does not count."]
    return "\n".join(lines)


def rays_tables(res):
    cols = columns(res)
    out = ["## Rays per second", "",
           "Closest hit per ray, rays per second (k = 10^3, M = 10^6). Brute force traces fewer rays on",
           "large scenes (column \"brute rays\"); the other columns trace all 262,144. Single thread unless",
           "the column says otherwise. A dash: not run, or failed its check (see Failures)."]
    for kind in KINDS:
        out += ["", f"### {KIND_TITLES[kind]}", ""]
        header = ["scene (spheres)", "brute rays"] + [c[0] for c in cols] + ["hit fraction"]
        rows = []
        for scene in res.scenes:
            hit = res.rate(scene, kind, "scalar", key="hit_fraction")
            rows.append([scene_label(res, scene), brute_rays(res, scene, kind) or "–"]
                        + [fmt_rate(res.rate(scene, kind, impl, t)) for _, impl, t in cols]
                        + [fmt_num(hit, 2)])
        out.append(table(header, rows))
    return "\n".join(out)


def ratio_tables(res):
    n = res.all_threads
    out = ["## Ratios", "",
           "Speed-up over the scalar reference is in sphere tests per second (brute force, one thread);",
           "\"dispatch / Embree\" compares the dispatched query per ray with rtcIntersect1, both on one",
           "thread; the thread columns divide the rate on all threads by the rate on one."]
    for kind in KINDS:
        header = ["scene (spheres)"] + [f"{isa} / scalar" for isa in res.isas()] + ["dispatch / scalar"]
        if res.has("embree-intersect1"):
            header.append("dispatch / Embree")
            if res.has("bvh"):
                header.append("bvh / Embree")
        if n > 1:
            header.append(f"stream {n} threads / 1")
            if res.has("embree-intersect1", n):
                header.append(f"Embree {n} threads / 1")
        rows = []
        for scene in res.scenes:
            tests = lambda impl: res.rate(scene, kind, impl, key="sphere_tests_per_second")  # noqa: E731
            row = [scene_label(res, scene)]
            row += [fmt_ratio(ratio(tests(isa), tests("scalar"))) for isa in res.isas()]
            row.append(fmt_ratio(ratio(tests("dispatch"), tests("scalar"))))
            if res.has("embree-intersect1"):
                embree = res.rate(scene, kind, "embree-intersect1")
                row.append(fmt_ratio(ratio(res.rate(scene, kind, "dispatch"), embree)))
                if res.has("bvh"):
                    row.append(fmt_ratio(ratio(res.rate(scene, kind, "bvh"), embree)))
            if n > 1:
                row.append(fmt_ratio(ratio(res.rate(scene, kind, "dispatch-stream", n),
                                           res.rate(scene, kind, "dispatch-stream", 1))))
                if res.has("embree-intersect1", n):
                    row.append(fmt_ratio(ratio(res.rate(scene, kind, "embree-intersect1", n),
                                               res.rate(scene, kind, "embree-intersect1", 1))))
            rows.append(row)
        out += ["", f"### {kind.capitalize()} rays", "", table(header, rows)]
    return "\n".join(out)


def stream_table(res):
    """Each instruction set's own stream entry point next to its per-ray query."""
    out = ["## Per-ray query and stream entry point", "",
           "Each kernel's `intersect_stream` (one thread) divided by its per-ray `intersect` on the same",
           "rays: the stream saves only the call per ray, so this stays near 1.", ""]
    header = ["scene (spheres)"] + [f"{isa} {kind}" for kind in KINDS for isa in res.isas()]
    rows = []
    for scene in res.scenes:
        rows.append([scene_label(res, scene)] + [
            fmt_ratio(ratio(res.rate(scene, kind, f"{isa}-stream"), res.rate(scene, kind, isa)))
            for kind in KINDS for isa in res.isas()])
    return "\n".join(out + [table(header, rows)])


def build_table(res):
    if not res.builds:
        return ""
    out = ["## Build times", "",
           "Time to build what an implementation needs before tracing, per scene, and the memory it",
           "holds (for Embree: the bytes its memory monitor reports, its own float4 copy of the spheres",
           "included). Brute force needs nothing built.", ""]
    header = ["scene (spheres)", "structure", "threads", "time", "spheres per second", "bytes per sphere"]
    rows = []
    for r in res.builds:
        if r.error:
            rows.append([scene_label(res, r.scene), r.impl, r.threads, "failed", "–", "–"])
            continue
        ms = r.get("real_time") if r.get("time_unit") == "ms" else None
        rows.append([scene_label(res, r.scene), r.impl, r.threads,
                     f"{ms:.3g} ms" if ms is not None else "–",
                     fmt_rate(r.get("items_per_second")), fmt_num(r.get("bytes_per_sphere"))])
    return "\n".join(out + [table(header, rows)])


def load_bounds():
    path = HERE / "kernel_bounds.json"
    return json.loads(path.read_text()).get("kernels", {}) if path.exists() else {}


def batch_cycles(res, isa, scenes, bounds):
    """Per (scene, kind): measured core cycles per batch of isa (TSC ticks per sphere x width x
    core cycles per tick) and the bound for that workload: the early-out and full paths'
    bounds blended by the fraction of batches that cannot be skipped."""
    k = res.core_per_tsc()
    b = bounds.get(isa)
    out = {}
    for scene in scenes:
        for kind in KINDS:
            r = res.row(scene, kind, isa)
            if r is None or r.get("tsc_per_sphere") is None or k is None:
                continue
            measured = r.get("tsc_per_sphere") * r.get("width") * k
            live = r.get("live_batch_fraction")
            bound = None
            if b is not None and live is not None:
                bound = live * b["full"]["cycles_per_batch"] + (1 - live) * b["early_out"]["cycles_per_batch"]
            out[(scene, kind)] = (measured, live, bound)
    return out


def cycles_section(res):
    bounds = load_bounds()
    scenes = res.scenes_between(*TARGET_SPEEDUP_SCENES, random_only=True)
    k = res.core_per_tsc()
    out = ["## Cycles per batch", ""]
    if k is None:
        return "\n".join(out + ["(no clock measurement in this run)"])
    out += ["The `clock/core` benchmark times a chain of dependent multiplies (3 cycles each): the core ran",
            f"{k:.3f} cycles per time stamp counter tick (about {k * res.tsc_mhz / 1000:.2f} GHz with the TSC at {res.tsc_mhz / 1000:.2f} GHz)",
            "(the fastest of many short samples, so descheduled samples do not count). Cycles per batch below =",
            "TSC ticks per sphere test x batch width x that factor, single thread, per-ray query, on the",
            "brute-force rays of each workload, cut into chunks of about 2^14 tests, each chunk timed in",
            "three passes and its fastest pass counted (so time lost to other processes does not count).",
            "AVX-512 code may run at a lower clock than the chain, which makes its figure a slight overestimate."]
    dividers = [(name, res.instruction_cycles(f"{name}")) for name in
                ("vsqrtps-ymm", "vdivps-ymm", "vsqrtps-zmm", "vdivps-zmm")]
    dividers = [(n, c) for n, c in dividers if c is not None]
    if dividers:
        out += ["", "Divider throughput measured by the `clock/...` benchmarks (eight independent instructions per",
                "loop), in core cycles per instruction: " + ", ".join(f"{n} {c:.1f}" for n, c in dividers) + "."]
    if bounds:
        out += ["", "Bounds from the instruction mix of the inner loop (`bench/count_loop.py`, see below):", ""]
        header = ["kernel", "path", "instructions", "vector uops", "multiply-class", "sqrt + div", "loads", "bound (cycles/batch)", "limited by"]
        rows = []
        for isa, b in bounds.items():
            for path in ("early_out", "full"):
                c = b[path]["counts"]
                rows.append([isa, path.replace("_", "-")]
                            + [f"{x:g}" for x in (c["instructions"], c["vector"], c["mul_class"], c["sqrt"] + c["div"], c["loads"])]
                            + [b[path]["cycles_per_batch"], b[path]["limited_by"]])
        out += [table(header, rows)]
    out += ["", "Measured against the bound for each workload (the two paths' bounds weighted by the fraction",
            "of batches in which some lane's discriminant is non-negative, \"live\"):", ""]
    header = ["kernel", "scene", "rays", "live batches", "measured", "bound", "measured / bound"]
    rows = []
    for isa in res.isas():
        for (scene, kind), (measured, live, bound) in batch_cycles(res, isa, scenes, bounds).items():
            rows.append([isa, scene_label(res, scene), kind, fmt_num(live, 2), fmt_num(measured), fmt_num(bound),
                         fmt_ratio(ratio(measured, bound))])
    out.append(table(header, rows))
    analysis = HERE / "kernel_analysis.md"
    if analysis.exists():
        out += ["", analysis.read_text().strip()]
    return "\n".join(out)


# --- targets -------------------------------------------------------------------------------

def verdict(ok):
    return "met" if ok else "**missed**"


def targets_section(res):
    n = res.all_threads
    lines = ["## Targets", "",
             "Checked on this run's figures (the machine's noise moves single ratios by several percent).", ""]
    header = ["target", "worst case in this run", "verdict"]
    rows = []
    scenes = res.scenes_between(*TARGET_SPEEDUP_SCENES, random_only=True)
    for isa, want in TARGET_SPEEDUP.items():
        vals = [(ratio(res.rate(s, kd, isa, key="sphere_tests_per_second"),
                       res.rate(s, kd, "scalar", key="sphere_tests_per_second")), s, kd)
                for s in scenes for kd in KINDS]
        vals = [v for v in vals if v[0] is not None]
        if vals:
            worst = min(vals)
            rows.append([f"{isa} >= {want:g}x scalar per sphere test, {TARGET_SPEEDUP_SCENES[0]}–{TARGET_SPEEDUP_SCENES[1]} spheres",
                         f"{worst[0]:.2f}x ({worst[1]}, {worst[2]})", verdict(worst[0] >= want)])
    bounds = load_bounds()
    for isa in ("avx2", "avx512"):
        cyc = [(m / bd, m, bd, s, kd) for (s, kd), (m, _, bd) in batch_cycles(res, isa, scenes, bounds).items() if bd]
        if cyc:
            worst = max(cyc)
            rows.append([f"{isa} cycles per batch <= {TARGET_BOUND_FACTOR}x the instruction-mix bound",
                         f"{worst[1]:.3g} vs {worst[2]:.3g} = {worst[0]:.2f}x ({worst[3]}, {worst[4]})",
                         verdict(worst[0] <= TARGET_BOUND_FACTOR)])
    for label, impl in (("dispatched query per ray", "dispatch"), ("dispatched stream", "dispatch-stream")):
        vals = [(ratio(res.rate(s, kd, impl), res.rate(s, kd, "scalar")), s, kd)
                for s in res.scenes_between(*TINY_SCENES) for kd in KINDS]
        vals = [v for v in vals if v[0] is not None]
        if vals:
            worst = min(vals)
            rows.append([f"{label} never slower than scalar, {TINY_SCENES[0]}–{TINY_SCENES[1]} spheres",
                         f"{worst[0]:.2f}x ({worst[1]}, {worst[2]})", verdict(worst[0] >= 1.0)])
    if res.has("embree-intersect1"):
        vals = [(ratio(res.rate(s, kd, "dispatch"), res.rate(s, kd, "embree-intersect1")), s, kd)
                for s in res.scenes_between(*SMALL_SCENES) for kd in KINDS]
        vals = [v for v in vals if v[0] is not None]
        if vals:
            worst = min(vals)
            rows.append([f"dispatched query >= {TARGET_OVER_EMBREE:g}x Embree rtcIntersect1, {SMALL_SCENES[0]}–{SMALL_SCENES[1]} spheres",
                         f"{worst[0]:.2f}x ({worst[1]}, {worst[2]})", verdict(worst[0] >= TARGET_OVER_EMBREE)])
    if n > 1:
        vals = [(ratio(res.rate(s, kd, "dispatch-stream", n), res.rate(s, kd, "dispatch-stream", 1)), s, kd)
                for s in res.scenes for kd in KINDS]
        vals = [v for v in vals if v[0] is not None]
        if vals:
            worst = min(vals)
            med = statistics.median(v[0] for v in vals)
            rows.append([f"stream on {n} threads >= {TARGET_THREAD_SCALING}x one thread",
                         f"{worst[0]:.2f}x ({worst[1]}, {worst[2]}); median {med:.2f}x", verdict(worst[0] >= TARGET_THREAD_SCALING)])
    rows += bvh_target_rows(res)
    return "\n".join(lines + [table(header, rows)])


def bvh_pairs(res):
    """(label, ours, Embree's, threads) of every BVH comparison issue 5 names."""
    n = res.all_threads
    pairs = [("tree per ray / rtcIntersect1", "bvh", "embree-intersect1", 1),
             ("tree stream / rtcIntersect1", "bvh-stream", "embree-intersect1", 1),
             ("tree per ray / rtcIntersect8", "bvh", "embree-intersect8", 1),
             ("tree stream / rtcIntersect8", "bvh-stream", "embree-intersect8", 1)]
    if n > 1:
        pairs += [(f"tree stream / rtcIntersect1, {n} threads", "bvh-stream", "embree-intersect1", n),
                  (f"tree stream / rtcIntersect8, {n} threads", "bvh-stream", "embree-intersect8", n)]
    return [p for p in pairs if res.has(p[1], p[3]) and res.has(p[2], p[3])]


def bvh_ratio(res, scene, kind, ours, theirs, threads):
    return ratio(res.rate(scene, kind, ours, threads), res.rate(scene, kind, theirs, threads))


def build_row(res, scene, impl, threads):
    for r in res.builds:
        if r.scene == scene and r.impl == impl and r.threads == threads and not r.error:
            return r
    return None


def build_ms(r):
    return r.get("real_time") if r is not None and r.get("time_unit") == "ms" else None


def bvh_target_rows(res):
    rows = []
    scenes = [s for s in BVH_SCENES if s in res.scenes]
    for label, ours, theirs, threads in bvh_pairs(res):
        want = BVH_OVER_INTERSECT1 if theirs == "embree-intersect1" else BVH_OVER_INTERSECT8
        vals = [(bvh_ratio(res, s, kd, ours, theirs, threads), s, kd) for s in scenes for kd in KINDS]
        vals = [v for v in vals if v[0] is not None]
        if vals:
            worst = min(vals)
            rows.append([f"{label} >= {want:g}x ({', '.join(scenes)})",
                         f"{worst[0]:.2f}x ({worst[1]}, {worst[2]})", verdict(worst[0] >= want)])
    n = res.all_threads
    ours, theirs = build_ms(build_row(res, BVH_BUILD_SCENE, "bvh", n)), build_ms(build_row(res, BVH_BUILD_SCENE, "embree", n))
    refit = build_ms(build_row(res, BVH_BUILD_SCENE, "bvh-refit", n))
    if ours and theirs:
        rows.append([f"tree build <= {BVH_BUILD_FACTOR:g}x rtcCommitScene ({BVH_BUILD_SCENE}, {n} threads)",
                     f"{ours:.3g} vs {theirs:.3g} ms = {ours / theirs:.2f}x", verdict(ours <= BVH_BUILD_FACTOR * theirs)])
    if ours and refit:
        rows.append([f"refit >= {BVH_REFIT_SPEEDUP:g}x faster than the tree build ({BVH_BUILD_SCENE}, {n} threads)",
                     f"{refit:.3g} vs {ours:.3g} ms = {ours / refit:.1f}x", verdict(ours >= BVH_REFIT_SPEEDUP * refit)])
    mem = [(build_row(res, s, "bvh", 1).get("bytes_per_sphere"), s) for s in scenes if build_row(res, s, "bvh", 1)]
    if mem:
        worst = max(mem)
        rows.append([f"tree and spheres <= {BVH_BYTES_PER_SPHERE:g} bytes per sphere ({', '.join(scenes)})",
                     f"{worst[0]:.3g} ({worst[1]})", verdict(worst[0] <= BVH_BYTES_PER_SPHERE)])
    return rows


def crossover_rows(res, kind):
    rows = []
    for s in sorted(res.random_scenes(), key=lambda s: res.spheres.get(s, 0)):
        tree, brute = res.rate(s, kind, "bvh"), res.rate(s, kind, "dispatch")
        if tree is not None and brute is not None:
            rows.append((s, brute, tree))
    return rows


def crossover(res, kind):
    """(the last random scene where dispatched brute force beats the tree per ray, the first
    after it), each as (scene, brute rate, tree rate): from the second on the tree stays ahead.
    The tree can also win on tiny scenes below a range where brute force leads."""
    rows = crossover_rows(res, kind)
    behind = [i for i, r in enumerate(rows) if r[2] <= r[1]]
    if not behind:
        return None, rows[0] if rows else None
    last = behind[-1]
    return rows[last], rows[last + 1] if last + 1 < len(rows) else None


def bvh_section(res):
    pairs = bvh_pairs(res)
    scenes = [s for s in BVH_SCENES if s in res.scenes]
    if not pairs or not scenes:
        return ""
    out = ["## The BVH against Embree", "",
           "Issue 5's comparison: `sphray::SphereBVH` against Embree's sphere BVH on the same spheres",
           "and rays, our rays per second over Embree's (rates in the tables above), coherent /",
           "incoherent. Embree's packets (`rtcIntersect8`) on several threads are split across them",
           "the same way as our stream.", ""]
    header = ["scene (spheres)"] + [p[0] for p in pairs]
    rows = []
    for s in scenes:
        row = [scene_label(res, s)]
        for _, ours, theirs, threads in pairs:
            row.append(" / ".join(fmt_ratio(bvh_ratio(res, s, kd, ours, theirs, threads)) for kd in KINDS))
        rows.append(row)
    out.append(table(header, rows))
    out += ["", "Build, refit and memory (the build table below has every scene):", ""]
    header = ["scene (spheres)", "threads", "tree build", "refit", "rtcCommitScene", "build / Embree's",
              "tree bytes per sphere", "Embree's"]
    rows = []
    for s in scenes:
        for threads in sorted({r.threads for r in res.builds if r.scene == s}):
            ours, refit, theirs = (build_row(res, s, impl, threads) for impl in ("bvh", "bvh-refit", "embree"))
            fmt_ms = lambda r: f"{build_ms(r):.3g} ms" if build_ms(r) else "–"  # noqa: E731
            rows.append([scene_label(res, s), threads, fmt_ms(ours), fmt_ms(refit), fmt_ms(theirs),
                         fmt_ratio(ratio(build_ms(ours), build_ms(theirs))),
                         fmt_num(ours.get("bytes_per_sphere")) if ours else "–",
                         fmt_num(theirs.get("bytes_per_sphere")) if theirs else "–"])
    out.append(table(header, rows))
    out += ["", "Crossover: the sphere count above which the tree, one ray at a time, stays ahead of the",
            "dispatched brute force on the random scenes (one thread; `sphray render` switches at 128",
            "spheres):", ""]
    for kind in KINDS:
        behind, ahead = crossover(res, kind)
        n_of = lambda r: res.spheres.get(r[0], "?")  # noqa: E731
        if ahead is None:
            out.append(f"- {kind}: brute force is still ahead on the largest random scene of this run")
        elif behind is None:
            out.append(f"- {kind}: the tree is ahead on every random scene of this run")
        else:
            text = (f"- {kind}: between {n_of(behind)} and {n_of(ahead)} spheres (brute force "
                    f"{fmt_rate(behind[1])} vs tree {fmt_rate(behind[2])} rays/s at {n_of(behind)}, "
                    f"{fmt_rate(ahead[1])} vs {fmt_rate(ahead[2])} at {n_of(ahead)})")
            tiny = [r for r in crossover_rows(res, kind) if r[2] > r[1] and res.spheres.get(r[0], 0) < n_of(behind)]
            if tiny:
                text += f"; the tree also leads on {', '.join(r[0] for r in tiny)}, a single leaf read directly"
            out.append(text)
    return "\n".join(out)


def bounce_impls(res):
    """(label, impl, threads) of the bounce table: brute force's stream, the tree, Embree."""
    n = res.all_threads
    cols = [("brute force stream", "dispatch-stream", 1), ("tree per ray", "bvh", 1),
            ("tree stream", "bvh-stream", 1), ("tree stream, arrays", "bvh-arrays", 1),
            ("Embree rtcIntersect1", "embree-intersect1", 1),
            ("Embree rtcIntersect8", "embree-intersect8", 1)]
    if n > 1:
        cols += [(f"brute force stream, {n} threads", "dispatch-stream", n),
                 (f"tree stream, {n} threads", "bvh-stream", n),
                 (f"Embree rtcIntersect1, {n} threads", "embree-intersect1", n),
                 (f"Embree rtcIntersect8, {n} threads", "embree-intersect8", n)]
    return cols


def best_sphray(res, scene, threads=1):
    """sphray's fastest way on a scene's bounce rays: brute force where it wins, else the tree."""
    rates = [(res.rate(scene, BOUNCE_KIND, impl, threads), impl)
             for impl in ("dispatch-stream", "bvh", "bvh-stream")]
    rates = [r for r in rates if r[0] is not None]
    return max(rates) if rates else (None, None)


def bounce_section(res):
    scenes = [s for s in BOUNCE_SCENES if any(k[0] == s and k[1] == BOUNCE_KIND for k in res.rays)]
    if not scenes:
        return ""
    out = ["## Bounce rays", "",
           "Issue 12's workload: the rays `sphray render -m path` traces after the camera's, recorded",
           "from a 512 x 512 frame at 1 sample (bounces 1 to 3, that is depth 2 to 4 with the camera ray",
           "as 1), each starting on a sphere at `sphray::spawn()`, in the order the renderer traces them",
           "(per 16 x 16 tile, one wavefront per bounce). Every implementation traces exactly these rays",
           "(brute force an evenly spread subset on large scenes) and is checked against the scalar",
           "reference first. Rays per second:", ""]
    cols = [c for c in bounce_impls(res) if any(res.rate(s, BOUNCE_KIND, c[1], c[2]) for s in scenes)]
    header = ["scene (spheres)", "rays"] + [c[0] for c in cols]
    rows = []
    for s in scenes:
        r = res.row(s, BOUNCE_KIND, "bvh")
        count = int(r.get("rays")) if r is not None else "–"
        rows.append([scene_label(res, s), count]
                    + [fmt_rate(res.rate(s, BOUNCE_KIND, impl, t)) for _, impl, t in cols])
    out.append(table(header, rows))
    out += ["", "sphray's fastest way (brute force where it wins, else the tree per ray or as a stream)",
            "against Embree on one thread, the issue's targets:", ""]
    rows = []
    for s in scenes:
        best, impl = best_sphray(res, s)
        for theirs, want in (("embree-intersect1", BOUNCE_OVER_INTERSECT1),
                             ("embree-intersect8", BOUNCE_OVER_INTERSECT8)):
            x = ratio(best, res.rate(s, BOUNCE_KIND, theirs))
            rows.append([scene_label(res, s), f"{impl} / {theirs} >= {want:g}x", fmt_ratio(x),
                         verdict(x is not None and x >= want)])
    out.append(table(["scene (spheres)", "target", "measured", ""], rows))
    return "\n".join(out)


QUERY_ROWS = [
    ("closest", "rays", "`intersect`: the closest hit (the yardstick)"),
    ("closest_masked", "rays", "`intersect` with masks: half the spheres hidden from the rays"),
    ("occluded", "rays", "`occluded`: any hit"),
    ("count_hits", "rays", "`count_hits`: every crossing, counted"),
    ("intersect_all16", "rays", "`intersect_all` into 16 slots: the nearest crossings, sorted"),
    ("nearest", "points", "`nearest`: the sphere nearest a point"),
    ("inside", "points", "`inside`: occupancy"),
    ("overlapping", "points", "`overlapping` with the median radius, 16 slots"),
]


def queries_section(res):
    """The queries beyond the closest hit (docs/queries.md), per second, one thread."""
    if not res.queries:
        return ""
    cols = []
    for scene in ("random:4096", "random:65536"):
        for how in ("tree", "brute"):
            if any((scene, q, how) in res.queries for q, _, _ in QUERY_ROWS):
                cols.append((scene, how))

    def rate(scene, query, how):
        r = res.queries.get((scene, query, how))
        if r is None or r.error:
            return None
        return r.get("items_per_second")

    rows = []
    for query, unit, label in QUERY_ROWS:
        cells = [label]
        for scene, how in cols:
            x = rate(scene, query, how)
            base = rate(scene, "closest", how)
            cells.append("" if x is None else
                         f"{fmt_rate(x)} ({fmt_ratio(ratio(x, base))})" if query != "closest" else fmt_rate(x))
        rows.append(cells)
    out = ["## Queries beyond the closest hit", "",
           "Queries per second on one thread (`queries/...` benchmarks, bench/query_benchmarks.cpp): the "
           "incoherent rays of each scene, and 65,536 points uniform in its box (fewer for brute force). "
           "In brackets, the rate against the closest hit's on the same scene and structure. Each query is "
           "checked against the scalar reference on a sample first. Contracts: [queries.md](queries.md).", ""]
    out.append(table(["query"] + [f"{s} {h}" for s, h in cols], rows))
    out += ["", "The every-crossing queries walk the whole segment where the closest hit stops at the first "
            "sphere, so their cost grows with the spheres along the ray; the point queries walk the same tree "
            "by distance."]
    return "\n".join(out)


EVERY_HIT_HEADING = "## Every crossing against Embree's filter"


def every_hit_section(res):
    """sphray's every-crossing queries against Embree's multi-hit filter, rays per second."""
    if not res.every_hit:
        return ""

    def rate(scene, kind, impl):
        r = res.every_hit.get((scene, kind, impl))
        return None if r is None or r.error else r.get("items_per_second")

    rows, targets = [], []
    for scene in EVERY_HIT_SCENES:
        for kind in KINDS:
            if not any(k[:2] == (scene, kind) for k in res.every_hit):
                continue
            count = ratio(rate(scene, kind, "count_hits"), rate(scene, kind, "embree_filter_count"))
            all16 = ratio(rate(scene, kind, "intersect_all16"), rate(scene, kind, "embree_filter_all16"))
            r = res.every_hit.get((scene, kind, "count_hits"))
            label = f"{scene} ({int(r.get('spheres'))})" if r is not None and r.get("spheres") else scene
            rows.append([label, kind] + [fmt_rate(rate(scene, kind, impl)) for impl in
                                         ("count_hits", "embree_filter_count")]
                        + [fmt_ratio(count)]
                        + [fmt_rate(rate(scene, kind, impl)) for impl in
                           ("intersect_all16", "embree_filter_all16")]
                        + [fmt_ratio(all16), fmt_rate(rate(scene, kind, "intersect_nearest16"))])
            targets.append((count is not None and count >= COUNT_OVER_FILTER)
                           and (all16 is not None and all16 >= ALL16_OVER_FILTER))
    out = [EVERY_HIT_HEADING, "",
           "Issue 35: sphray's every-crossing queries through the tree against what an Embree user writes "
           "for the same answer (`every_hit/...` benchmarks, bench/query_benchmarks.cpp): "
           "`rtcIntersect1` on the spheres with an intersection filter that records each hit and rejects it, "
           "so the walk goes on (bench/embree_implementations.cpp). `embree_filter_all16` keeps the 16 nearest "
           "sorted by t then id and counts the rest, the answer of `intersect_all` into 16 slots; "
           "`embree_filter_count` only counts. Rays per second on one thread, the scene's camera "
           "(coherent) and incoherent rays; every row is checked first against the scalar reference's "
           "crossings on a sample (totals, and the 16 nearest up to float ties). Targets: "
           f"`count_hits` >= {COUNT_OVER_FILTER:g}x the counting filter, `intersect_all16` >= "
           f"{ALL16_OVER_FILTER:g}x the collecting filter. `intersect_nearest16` (the 16 nearest without "
           "the total, the walk pruned) for reference. `sphray bench -s SCENE --query every-hit` times "
           "the same rows and checks the filters against sphray's lists on every ray "
           "(docs/queries.md, \"Against Embree's filter\").", ""]
    out.append(table(["scene (spheres)", "rays", "count_hits", "embree_filter_count", "ratio",
                      "intersect_all16", "embree_filter_all16", "ratio", "intersect_nearest16"], rows))
    out += ["", f"Both targets met on {sum(targets)} of {len(targets)} scene and ray sets in this run."]
    return "\n".join(out)


def failures_section(res):
    failed = [r for r in res.rows if r.error]
    ties = [r for r in res.rays.values() if not r.error and (r.get("id_ties") or 0) > 0]
    lines = ["## Agreement with the scalar reference", "",
             "Before it is timed, every implementation traces a sample of up to 1,024 of the brute-force rays",
             "of its workload, and each hit is compared with the scalar reference's: both miss, or both hit",
             "the same sphere with t within 1e-3 x max(1, |t|). A disagreement marks the benchmark as an",
             "error, so it has no figure above."]
    if failed:
        lines += ["", "Failures in this run:", ""]
        lines += [f"- `{r.values['name']}`: {r.error}" for r in failed]
    else:
        lines += ["", "Every implementation agreed with the reference on every workload in this run."]
    if ties:
        lines += ["", "Equal-t hits on different spheres (ties decided by rounding, accepted):", ""]
        lines += [f"- `{r.values['name']}`: {int(r.get('id_ties'))}" for r in ties]
    return "\n".join(lines)


# --- plots ---------------------------------------------------------------------------------

def plot_rates(res, kind, path):
    scenes = res.random_scenes()
    x = [res.spheres[s] for s in scenes]
    fig, ax = plt.subplots(figsize=(8, 5))
    lines = [c for c in columns(res) if not (c[1] in ("dispatch", "dispatch-stream") and c[2] == 1)]
    colours = plt.cm.tab20.colors  # more distinct colours than the default cycle of ten
    for k, (label, impl, t) in enumerate(lines):  # dispatch on one thread: the best ISA's line
        y = [res.rate(s, kind, impl, t) for s in scenes]
        pts = [(a, b) for a, b in zip(x, y) if b is not None]
        if pts:
            style = "--" if "Embree" in label else "-"
            ax.plot(*zip(*pts), style, marker="o", label=label, color=colours[(2 * k) % 20 + (2 * k) // 20])
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("spheres (random:N scenes)")
    ax.set_ylabel("rays per second")
    ax.set_title(f"{kind.capitalize()} rays: closest hit, rays per second")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_speedup(res, path):
    scenes = res.random_scenes()
    x = [res.spheres[s] for s in scenes]
    fig, ax = plt.subplots(figsize=(8, 5))
    for isa in res.isas():
        for kind, style in zip(KINDS, ("-", "--")):
            y = [ratio(res.rate(s, kind, isa, key="sphere_tests_per_second"),
                       res.rate(s, kind, "scalar", key="sphere_tests_per_second")) for s in scenes]
            pts = [(a, b) for a, b in zip(x, y) if b is not None]
            if pts:
                ax.plot(*zip(*pts), style, marker="o", label=f"{isa}, {kind}")
    for isa, want in TARGET_SPEEDUP.items():
        if isa in res.isas():
            ax.axhline(want, color="grey", linestyle=":", linewidth=1)
            ax.annotate(f"{isa} target {want:g}x", (x[0], want), fontsize=7, va="bottom")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("spheres (random:N scenes)")
    ax.set_ylabel("sphere tests per second / scalar")
    ax.set_title("Speed-up over the scalar reference, one thread")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --- the Python module against numpy (bench/python_vs_numpy.py) --------------------------

NUMPY_TRACERS = [("numpy_rays_per_s", "numpy, vectorised quadratic (1 thread)"),
                 ("c_one_thread_rays_per_s", "sphray C API, sphray_intersect (1 thread)"),
                 ("module_rays_per_s", "sphray Python module, Scene.intersect (all threads)"),
                 ("c_parallel_rays_per_s", "sphray C API, sphray_intersect (all threads)")]


def numpy_section(data, plot):
    ctx, rows = data.get("context", {}), data.get("rows", [])
    if not rows:
        return ""
    out = ["## The Python module against numpy", "",
           "What a Python user can run here that finds the hits: numpy written the way a scientist",
           "vectorises the ray/sphere quadratic (every ray of a chunk against every sphere, the near",
           "root unless it lies behind the origin; numpy's element-wise operations run on one thread),",
           "against `sphray.Scene.intersect`, and against sphray's C stream calls on the same arrays",
           "through ctypes (one call: what the module adds to them is the binding's cost). Rays: "
           f"{ctx.get('rays', 0):,} random rays",
           "(origins uniform in the 100-unit box, directions uniform) into N random spheres (the `random:N`",
           "recipe); numpy is given 2^24 sphere tests a scene, so 2^24 / N of the same rays. Best of "
           f"{ctx.get('repeats', '?')};",
           f"Python {ctx.get('python', '?')}, numpy {ctx.get('numpy', '?')}, sphray on "
           f"{ctx.get('sphray_isa', '?')}, {ctx.get('threads', '?')} threads, {ctx.get('cpu', '?')}"
           + (f", load average {ctx['load_avg']:.1f} at the start (other work shares the cores:"
              " compare the columns, not the figures across runs)." if "load_avg" in ctx else "."),
           f"Command: `{ctx.get('command', 'bench/python_vs_numpy.py')}` ({ctx.get('date', '')}).", ""]
    header = ["spheres"] + [label for _, label in NUMPY_TRACERS] + [
        "module / numpy", "module / C parallel", "numpy agrees"]
    body = []
    for r in rows:
        body.append([f"{r['spheres']:,}"] + [fmt_rate(r[key]) for key, _ in NUMPY_TRACERS] + [
            fmt_ratio(r["module_rays_per_s"] / r["numpy_rays_per_s"]),
            fmt_ratio(r["module_rays_per_s"] / r["c_parallel_rays_per_s"]),
            f"{r['numpy_agreement']:.2%} of {r['numpy_rays']:,} rays"])
    out += [table(header, body), "",
            "numpy tests every sphere for every ray; the module and the C calls take sphray's tree",
            "from 128 spheres on, so the margin grows with the sphere count. The module's hits are the",
            "C API's, bit for bit (checked in the run). numpy's float32",
            "quadratic is not the kernel's precision-safe one: where they differ, it is on",
            "near-tangent rays and ties (the run fails below 99.9% agreement).", "",
            f"![sphray against numpy, rays per second]({plot})"]
    return "\n".join(out)


def plot_numpy(data, path):
    rows = data.get("rows", [])
    if not rows:
        return
    fig, ax = plt.subplots(figsize=(7, 4.4))
    width = 0.8 / len(NUMPY_TRACERS)
    for k, (key, label) in enumerate(NUMPY_TRACERS):
        ax.bar([i + k * width for i in range(len(rows))], [r[key] for r in rows], width, label=label)
    ax.set_yscale("log")
    ax.set_xticks([i + width * (len(NUMPY_TRACERS) - 1) / 2 for i in range(len(rows))])
    ax.set_xticklabels([f"{r['spheres']:,} spheres" for r in rows])
    ax.set_ylabel("rays per second")
    ax.set_title("Python: numpy's quadratic, sphray's module and its C calls")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, fontsize="small")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --- the Python module against Open3D (bench/python_vs_open3d.py) -------------------------

TARGET_OVER_OPEN3D = 10.0  # issue 14: at the coarsest tessellation


def open3d_rows(data):
    rows = data.get("rows", [])
    ours = {r["spheres"]: r for r in rows if r["impl"] == "sphray"}
    return ours, [r for r in rows if r["impl"] == "open3d"]


def fmt_ms(seconds):
    return f"{seconds:.3g} s" if seconds >= 1 else f"{seconds * 1e3:.3g} ms"


def open3d_target_line(theirs, coarsest, worst):
    line = (f"Target (issue 14): sphray at least {TARGET_OVER_OPEN3D:g}x Open3D's rate at the coarsest "
            f"tessellation ({coarsest} triangles a sphere): {worst:.1f}x")
    if all(o["open3d_hits"] == 0 for o in theirs):
        # A tracer that finds no hit has nothing to be compared with (docs/python.md, "Open3D on
        # Debian 12"): the ratio is printed, not judged.
        return line + (", **not a comparison**: this Open3D reported no hit for any ray (last "
                       "column), so its rate is that of traversals that found nothing.")
    return line + f", {verdict(worst >= TARGET_OVER_OPEN3D)}."


def open3d_section(data, plot):
    ctx = data.get("context", {})
    ours, theirs = open3d_rows(data)
    if not theirs:
        return ""
    coarsest = min(r["triangles_per_sphere"] for r in theirs)
    worst = min(r["sphray_speedup"] for r in theirs if r["triangles_per_sphere"] == coarsest)
    out = ["## The Python module against Open3D", "",
           f"`sphray.Scene.intersect` against Open3D {ctx.get('open3d', '?')}'s `RaycastingScene.cast_rays` "
           "(Debian's `python3-open3d`), both called from",
           f"Python {ctx.get('python', '?')} on the same numpy arrays, all {ctx.get('threads', '?')} threads: "
           f"{ctx.get('rays', 0):,} random rays",
           "(origins uniform in the 100-unit box, directions uniform) into N random spheres (the `random:N`",
           "recipe). Open3D traces each sphere as its own `TriangleMesh.create_sphere(r, resolution)`, merged",
           "into one mesh. Trace: best of "
           f"{ctx.get('repeats', '?')}; build: once (sphray: `Scene(...)`, its BVH; Open3D: `add_triangles`",
           "and the first `cast_rays`, which builds its BVH). sphray's instruction set: "
           f"{ctx.get('sphray_isa', '?')}.",
           f"Command: `{ctx.get('command', 'bench/python_vs_open3d.py')}` ({ctx.get('date', '')}).", "",
           open3d_target_line(theirs, coarsest, worst), ""]
    header = ["spheres", "tracer", "triangles", "rays per second", "build", "sphray / Open3D",
              "exact hits missed by the mesh", "distance error, median", "max", "Open3D hits reported"]
    rows = []
    for n, r in sorted(ours.items()):
        rows.append([f"{n:,}", "sphray (exact)", "–", fmt_rate(r["rays_per_s"]), fmt_ms(r["build_s"]),
                     "–", "–", "–", "–", "–"])
        for o in sorted((o for o in theirs if o["spheres"] == n), key=lambda o: o["triangles_per_sphere"]):
            rows.append([f"{n:,}", f"Open3D, resolution {o['resolution']}",
                         f"{o['triangles_per_sphere']} a sphere ({o['triangles_per_sphere'] * n / 1e6:.3g} M)",
                         fmt_rate(o["rays_per_s"]), fmt_ms(o["build_s"]), fmt_ratio(o["sphray_speedup"]),
                         f"{o['mesh_missed_fraction']:.1%}", f"{o['error_median_radii']:.3g} r",
                         f"{o['error_max_radii']:.3g} r", f"{o['open3d_hits']:,} of {o['exact_hits']:,}"])
    out += [table(header, rows), "",
            "The accuracy columns are those of the tessellation itself, whatever traces it: every ray",
            "sphray hits is tested exactly (float64 Möller-Trumbore) against its sphere's own triangles;",
            "the mesh lies inside the sphere, so rays near a silhouette miss it, and the others stop",
            "short or long of the surface by the distance shown, in radii (the largest, near 2 r, are rays",
            "starting between a mesh and its sphere: outside the one, so stopped at its near face, and",
            "inside the other, so stopped at its far side)."]
    if all(o["open3d_hits"] == 0 for o in theirs):
        out += ["Open3D's own answers could not be used for them: this `cast_rays` reported no hit for any",
                "ray (last column), a defect of this Open3D build, not of the rays (docs/python.md,",
                "\"Open3D on Debian 12\"); its rates are those of traversals that found nothing. A working",
                "build would stop each ray at its first hit and visit fewer nodes, so it may trace faster",
                "than measured here, by an amount this build cannot show."]
    out += ["",
            f"![sphray against Open3D, rays per second]({plot})"]
    return "\n".join(out)


def plot_open3d(data, path):
    ours, theirs = open3d_rows(data)
    if not theirs:
        return
    scenes = sorted(ours)
    labels = ["sphray (exact)"] + [f"Open3D, {t} triangles/sphere"
                                   for t in sorted({o["triangles_per_sphere"] for o in theirs})]
    fig, ax = plt.subplots(figsize=(7, 4.4))
    width = 0.8 / len(labels)
    for k, label in enumerate(labels):
        rates = []
        for n in scenes:
            if k == 0:
                rates.append(ours[n]["rays_per_s"])
            else:
                tri = sorted({o["triangles_per_sphere"] for o in theirs})[k - 1]
                match = [o for o in theirs if o["spheres"] == n and o["triangles_per_sphere"] == tri]
                rates.append(match[0]["rays_per_s"] if match else 0)
        ax.bar([i + k * width for i in range(len(scenes))], rates, width, label=label)
    ax.set_yscale("log")
    ax.set_xticks([i + width * (len(labels) - 1) / 2 for i in range(len(scenes))])
    ax.set_xticklabels([f"{n:,} spheres" for n in scenes])
    ax.set_ylabel("rays per second (all threads)")
    ax.set_title("Python: sphray.Scene.intersect against Open3D cast_rays")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=len(labels), fontsize="small")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --- page ----------------------------------------------------------------------------------

INTRO = """# Performance

Rays per second of every way sphray answers a closest-hit query, side by side with its scalar
reference and with Intel Embree 3, all in one process on the same spheres and rays. This page
is generated: `bench/run.sh` runs the benchmarks and `bench/report.py` writes this file and the
plots from their JSON. Absolute figures move with the machine (a shared virtual machine can
drift by 1.5x between runs); ratios taken within one run are the figures to compare.

## What is measured

- Scenes: the renderer's presets (`single`, `three`, `rtiow-final`, `random:N`), made by its own
  scene code, so the figures are for exactly the scenes `sphray render` draws.
- Coherent rays: the 262,144 camera rays of a 512 x 512 image with the scene's camera.
  Incoherent rays: as many rays with origins uniform in the scene box (the bounds of the
  spheres, leaving out any sphere over 10 times the median radius, such as a ground sphere)
  and directions uniform on the unit sphere. Both are made once, before any timing.
- Brute force (every sphere for every ray) traces at most 2^26 ray/sphere pairs per pass:
  on large scenes a smaller camera image (coherent) or the first rays of the random set
  (incoherent), never fewer spheres, and at least 256 rays.
- Bounce rays (`rtiow-final` and `random:65536`): the rays path mode traces after the camera's,
  recorded from the renderer (section "Bounce rays").
- Implementations: `scalar` is `sphray::scalar::intersect`; `sse4.2`, `avx2`, `avx512` are
  each instruction set's kernel forced through its internal entry-point table (`detail::find_entries(isa)`), per ray;
  `dispatch` is `sphray::intersect(view, ray)` and `dispatch stream` the span overload, split
  into chunks across a oneTBB arena of 1 or all threads by the caller; Embree is
  `RTC_GEOMETRY_TYPE_SPHERE_POINT` with one float4 (x, y, z, r) per sphere, `rtcIntersect1`
  per ray (chunks across threads the same way) and `rtcIntersect8` on packets of 8 consecutive
  rays.
- Timing: wall-clock time of whole passes over the ray set (Google Benchmark, real time)."""


# --- the batch overlap queries against SciPy's cKDTree (bench/python_vs_ckdtree.py) -------

CKDTREE_HEADING = "## The batch overlap queries against SciPy's cKDTree"


def ckdtree_section(data):
    ctx, rows = data.get("context", {}), data.get("rows", [])
    if not rows:
        return ""
    out = [CKDTREE_HEADING, "",
           "A simulation's broad phase in Python: `Scene.overlaps(points, 0)` (the spheres each point",
           "lies in) against `cKDTree.query_ball_point(points, R, workers=-1)` on the spheres' centres,",
           "and `Scene.overlapping_pairs()` against `cKDTree.query_pairs(2R, output_type='ndarray')`.",
           "N equal spheres of radius R = 0.5 (cKDTree's balls have one radius; sphray's may differ),",
           "centres uniform in a box of N unit volumes, and N points uniform in it; both on every core.",
           "Times are the calls alone, best of "
           f"{ctx.get('repeats', '?')}; the trees' builds apart. Python {ctx.get('python', '?')}, "
           f"SciPy {ctx.get('scipy', '?')}, sphray on {ctx.get('sphray_isa', '?')}, "
           f"{ctx.get('threads', '?')} threads, {ctx.get('cpu', '?')}"
           + (f", load average {ctx['load_avg']:.1f} at the start." if "load_avg" in ctx else "."),
           f"Command: `{ctx.get('command', 'bench/python_vs_ckdtree.py')}` ({ctx.get('date', '')}).", ""]
    header = ["spheres", "overlaps", "query_ball_point", "cKDTree / sphray", "rows agree",
              "overlapping_pairs", "query_pairs", "cKDTree / sphray", "pairs agree",
              "build: Scene", "build: cKDTree"]
    body = []
    for r in rows:
        body.append([f"{r['spheres']:,}", f"{r['overlaps_s']:.3f} s", f"{r['query_ball_point_s']:.3f} s",
                     fmt_ratio(r["query_ball_point_s"] / r["overlaps_s"]), f"{r['rows_agree']:.4%}",
                     f"{r['overlapping_pairs_s']:.3f} s", f"{r['query_pairs_s']:.3f} s",
                     fmt_ratio(r["query_pairs_s"] / r["overlapping_pairs_s"]),
                     f"{r['pairs_agree']:.4%} of {r['pairs']:,}",
                     f"{r['sphray_build_s']:.3f} s", f"{r['ckdtree_build_s']:.3f} s"])
    out += [table(header, body), "",
            "\"Agree\" counts the points whose lists are equal and the pairs both found: they differ only",
            "where a distance equals the radius exactly (cKDTree counts it in, sphray out).",
            "`overlaps` walks the tree once per ball, in the Morton order of the balls so that",
            "neighbouring queries find the nodes in the caches. `overlapping_pairs` walks the tree",
            "once per leaf, with the leaf's box, and tests the leaves it meets against it a leaf of",
            "spheres in the SIMD lanes at a time: each pair is found once, by the earlier of its two",
            "leaves (docs/queries.md, \"Overlapping pairs\")."]
    return "\n".join(out)


OPEN3D_HEADING = "## The Python module against Open3D"
OPEN3D_BEFORE = "## Cycles per batch"  # where main() places the section


NUMPY_HEADING = "## The Python module against numpy"


def section_span(page, heading):
    """(start, end) of the section of page under heading, up to the next one, or None."""
    start = page.find(heading)
    if start < 0:
        return None
    nxt = page.find("\n## ", start + len(heading))
    return start, nxt + 1 if nxt >= 0 else len(page)


def update_section(docs, heading, section, before=OPEN3D_BEFORE):
    """Replaces (or inserts before `before`) one section of an existing page: for a run of the
    Python comparisons alone (bench/run.sh --python-only)."""
    page_path = docs / "performance.md"
    page = page_path.read_text()
    span = section_span(page, heading)
    if span is None:
        start = page.find(before) if before in page else len(page)
        span = (start, start)
    start, end = span
    page_path.write_text(page[:start] + section + "\n\n" + page[end:].lstrip("\n"))
    print(f"updated \"{heading[3:]}\" in {page_path}")


# The rays-across crossover (the query plan's rule 9) is measured with its own commands, over
# more sphere counts than this run's scenes: a regeneration keeps the section as it stands.
ACROSS_HEADING = "## Rays across the lanes"
# Particle files at 1M to 100M spheres: bench/particles_scale.py measures and writes it.
PARTICLES_HEADING = "## Particles at scale"
# Path mode against the book's way (issue 33): bench/path_vs_book.py measures and writes it.
PATH_BOOK_HEADING = "## Path mode against the book's way"


def kept_section(docs, heading):
    page_path = docs / "performance.md"
    page = page_path.read_text() if page_path.exists() else ""
    span = section_span(page, heading)
    return page[span[0]:span[1]].rstrip() if span else None


def update_python_sections(docs, numpy_data, open3d_data, ckdtree_data=None):
    images = docs / "images"
    images.mkdir(parents=True, exist_ok=True)
    if numpy_data:
        plot_numpy(numpy_data, images / "perf-python-numpy.png")
        update_section(docs, NUMPY_HEADING, numpy_section(numpy_data, "images/perf-python-numpy.png"),
                       before=OPEN3D_HEADING)
    if open3d_data:
        plot_open3d(open3d_data, images / "perf-python-open3d.png")
        update_section(docs, OPEN3D_HEADING, open3d_section(open3d_data, "images/perf-python-open3d.png"))
    if ckdtree_data:
        update_section(docs, CKDTREE_HEADING, ckdtree_section(ckdtree_data),
                       before="## Earlier measurements")


# Measurements of single changes, each made with its own command (`sphray bench`, or sphray_bench
# with a filter), are dated history and live in docs/history.md, not on this generated page; the
# page names them so that a reference to "docs/performance.md, <section>" still finds its way.
HISTORY_POINTER = """## Earlier measurements

Runs of single changes, each with its own command and date, are history and live in
[history.md](history.md): "Packets for coherent rays", "Shadow rays: line packets", "Shadow
rays: packet leaves", "Small trees" (three rounds), "Small scenes against Embree: the targets
still missed", "Rays as arrays per quantity", and a sample output of `sphray bench` on
rtiow-final. This page holds the latest full run only."""


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("json", type=Path, nargs="?",
                    help="output of sphray_bench --benchmark_out=FILE --benchmark_out_format=json; without "
                         "it, --open3d alone rewrites only that section of the existing page")
    ap.add_argument("--docs", type=Path, default=HERE.parent / "docs", help="the docs folder to write into")
    ap.add_argument("--command", default="bench/run.sh", help="the command that made the run, for the page")
    ap.add_argument("--open3d", type=Path, help="output of bench/python_vs_open3d.py, for its section")
    ap.add_argument("--numpy", type=Path, help="output of bench/python_vs_numpy.py, for its section")
    ap.add_argument("--ckdtree", type=Path, help="output of bench/python_vs_ckdtree.py, for its section")
    args = ap.parse_args(argv)
    numpy_data = json.loads(args.numpy.read_text()) if args.numpy and args.numpy.exists() else {}
    open3d = json.loads(args.open3d.read_text()) if args.open3d and args.open3d.exists() else {}
    ckdtree = json.loads(args.ckdtree.read_text()) if args.ckdtree and args.ckdtree.exists() else {}
    if args.json is None:
        if not numpy_data and not open3d and not ckdtree:
            ap.error("give the sphray_bench JSON, or --numpy, --open3d and/or --ckdtree to update "
                     "those sections")
        update_python_sections(args.docs, numpy_data, open3d, ckdtree)
        return

    data = json.loads(args.json.read_text())
    res = Results(load_rows(data), data.get("context", {}))
    if not res.rays:
        sys.exit(f"{args.json}: no rays/ benchmarks in this file")
    images = args.docs / "images"
    images.mkdir(parents=True, exist_ok=True)
    for kind in KINDS:
        plot_rates(res, kind, images / f"perf-rays-{kind}.png")
    plot_speedup(res, images / "perf-speedup.png")
    plot_numpy(numpy_data, images / "perf-python-numpy.png")
    plot_open3d(open3d, images / "perf-python-open3d.png")

    sections = [
        INTRO,
        machine_section(data.get("context", {}), args.command),
        targets_section(res),
        rays_tables(res),
        "![Rays per second against sphere count, coherent](images/perf-rays-coherent.png)\n\n"
        "![Rays per second against sphere count, incoherent](images/perf-rays-incoherent.png)",
        ratio_tables(res),
        "![Speed-up over scalar per instruction set](images/perf-speedup.png)",
        stream_table(res),
        kept_section(args.docs, ACROSS_HEADING),
        bvh_section(res),
        bounce_section(res),
        kept_section(args.docs, PATH_BOOK_HEADING),
        queries_section(res),
        every_hit_section(res),
        build_table(res),
        kept_section(args.docs, PARTICLES_HEADING),
        numpy_section(numpy_data, "images/perf-python-numpy.png"),
        open3d_section(open3d, "images/perf-python-open3d.png"),
        ckdtree_section(ckdtree),
        HISTORY_POINTER,
        cycles_section(res),
        failures_section(res),
    ]
    page = "\n\n".join(s for s in sections if s) + "\n"
    (args.docs / "performance.md").write_text(page)
    print(f"wrote {args.docs / 'performance.md'} and {images}/perf-*.png")


if __name__ == "__main__":
    main(sys.argv[1:])
