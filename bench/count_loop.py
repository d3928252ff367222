#!/usr/bin/env python3
"""Counts the instructions of the kernel's inner loop and derives a cycles-per-batch bound.

    bench/count_loop.py BUILD_DIR [--write]

Disassembles (objdump -d) each per-ISA kernel object in BUILD_DIR
(kernel/CMakeFiles/sphray_kernel.dir/src/isa_*.cpp.o), finds the loop over sphere batches of
BruteForce<A>::intersect (the loop whose pass holds per-batch early-out tests: a mask
test and a branch), follows one pass of it twice, once with every batch skipped (no lane's
discriminant non-negative) and once with every batch live, classifies every instruction, and prints per ISA a bound for each path from its
busiest resource. --write stores the result in bench/kernel_bounds.json, which report.py puts
in docs/performance.md next to the measured cycles per batch.

The machine model (MODEL below) is a Golden Cove-class core (Sapphire Rapids); the divider
figures are what the `clock/...` benchmarks of sphray_bench measure on the machine itself.
"""

import argparse
import json
import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

# Per vector width: ports that take any vector ALU op, the subset that multiplies (mul, FMA,
# the square-root and divide set-up), and the cycles one square root and one divide occupy the
# divider (its reciprocal throughput). Golden Cove runs 256-bit ops on ports 0, 1, 5 with
# FMA on 0 and 1; 512-bit ops on ports 0 (fused 0+1) and 5, with FMA on both on server parts.
MODEL = {
    "ymm": {"vector_ports": 3, "mul_ports": 2, "sqrt": 6.0, "div": 5.0},
    "zmm": {"vector_ports": 2, "mul_ports": 2, "sqrt": 12.0, "div": 10.0},
    "xmm": {"vector_ports": 3, "mul_ports": 2, "sqrt": 3.0, "div": 3.0},
}
ISSUE_WIDTH = 6  # uops renamed per cycle
LOAD_PORTS = 3

OBJECTS = {
    "sse4.2": ("isa_sse4_2.cpp.o", "xmm", 4),
    "avx2": ("isa_avx2.cpp.o", "ymm", 8),
    "avx512": ("isa_avx512.cpp.o", "zmm", 16),
}

LINE = re.compile(r"^\s*([0-9a-f]+):\s+(\S+)\s*(.*)$")
BRANCH = re.compile(r"^j[a-z]+$")
MUL_CLASS = re.compile(r"^v?(mul|fmadd|fmsub|fnmadd|fnmsub)")
DIVIDER = re.compile(r"^v?(sqrt|div)p")


def disassemble(obj):
    return subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-C", str(obj)],
                          check=True, capture_output=True, text=True).stdout


def intersect_body(text):
    """The instructions of BruteForce<A>::intersect as (address, mnemonic, operands)."""
    body, inside = [], False
    for line in text.splitlines():
        if line.endswith(">:"):
            inside = "BruteForce<" in line and ">::intersect(" in line
            continue
        m = LINE.match(line) if inside else None
        if m:
            body.append((int(m.group(1), 16), m.group(2), m.group(3).split("#")[0].strip()))
    return body


def target(operands):
    m = re.match(r"^([0-9a-f]+)\b", operands)
    return int(m.group(1), 16) if m else None


EARLY_OUT_TESTS = ("vtestps", "vptest", "ktestw", "kortestw", "ktestb", "kortestb", "ptest", "movmskps", "vmovmskps")


def is_early_out(body, k):
    """A conditional branch right after a mask test: the per-batch 'no lane can hit' check."""
    mnem = body[k][1]
    if not BRANCH.match(mnem) or mnem == "jmp":
        return False
    prev = [body[j][1] for j in range(max(0, k - 2), k)]
    return any(p in EARLY_OUT_TESTS for p in prev)


def walk(body, head, live):
    """The instructions one pass of the loop starting at `head` runs when every batch is live
    (live=True) or every batch is skipped. Other conditional branches are taken only when they
    return to head (the next iteration). Returns (instructions, batches) or None."""
    index = {addr: k for k, (addr, _, _) in enumerate(body)}
    k = index.get(head)
    path, batches = [], 0
    while k is not None and k < len(body) and len(path) < 2000:
        addr, mnem, ops = body[k]
        path.append(body[k])
        t = target(ops) if BRANCH.match(mnem) else None
        if t is None:
            k += 1
            continue
        if t == head:
            return path, batches
        if mnem == "jmp":
            k = index.get(t)
            continue
        if is_early_out(body, k):
            batches += 1
            skip_is_taken = mnem == "je"  # ZF set: the mask is all zero, no lane live
            taken = skip_is_taken != live
            k = index.get(t) if taken else k + 1
            continue
        k += 1  # any other conditional branch: fall through (stay in the loop)
    return None


def batch_loop(body):
    """The loop over sphere batches: of the backward branches whose pass has early-out tests,
    the one handling the most batches per pass. Returns (skip path, live path, batches)."""
    best = None
    for addr, mnem, ops in body:
        t = target(ops) if BRANCH.match(mnem) else None
        if t is None or t >= addr:
            continue
        skip, live = walk(body, t, False), walk(body, t, True)
        if skip is None or live is None or skip[1] == 0:
            continue
        if not any(i[1].startswith(("vsqrtp", "sqrtp")) for i in live[0]):
            continue
        # One square root per batch: a pass may test several batches at once before the roots.
        batches = sum(1 for i in live[0] if i[1].startswith(("vsqrtp", "sqrtp")))
        if best is None or batches > best[2]:
            best = (skip[0], live[0], batches)
    return best


def eliminated(mnem, ops):
    """Register moves and zeroing idioms: renamed away, no execution port."""
    regs = [r.strip() for r in ops.split(",")]
    if re.match(r"^v?mov(aps|ups|dqa|dqu)", mnem) and "(" not in ops and "{" not in ops:
        return True
    return bool(re.match(r"^v?p?xor", mnem)) and len(regs) >= 2 and len(set(regs[-2:] if len(regs) == 2 else regs[:2])) == 1


def classify(path, reg):
    counts = {"instructions": len(path), "loads": 0, "vector": 0, "mul_class": 0, "sqrt": 0, "div": 0,
              "scalar": 0, "eliminated": 0}
    for _, mnem, ops in path:
        if "(" in ops and not mnem.startswith("lea"):
            counts["loads"] += 1  # a memory operand (folded or a plain load)
        if DIVIDER.match(mnem):
            counts["sqrt" if "sqrt" in mnem else "div"] += 1
            counts["vector"] += 1
        elif eliminated(mnem, ops):
            counts["eliminated"] += 1
        elif mnem.startswith("v") or mnem.startswith("k") or any(r in ops for r in ("%xmm", "%ymm", "%zmm")):
            # Plain loads and broadcasts from memory use a load port only.
            load_only = re.match(r"^v?(mov|broadcast)", mnem) and "(" in ops and "{" not in ops
            if not load_only:
                counts["vector"] += 2 if "blendv" in mnem else 1  # blendv: 2 uops
            if MUL_CLASS.match(mnem):
                counts["mul_class"] += 1
        else:
            counts["scalar"] += 1
    return counts


def bound(counts, reg):
    """Cycles per batch from the busiest resource, and which one it is."""
    m = MODEL[reg]
    # Branch and loop-counter instructions fuse in pairs (cmp+jcc), so count them at half.
    uops = counts["instructions"] - counts["scalar"] / 2
    candidates = {
        "issue": uops / ISSUE_WIDTH,
        "vector ports": counts["vector"] / m["vector_ports"],
        "multiply ports": counts["mul_class"] / m["mul_ports"],
        "divider": counts["sqrt"] * m["sqrt"] + counts["div"] * m["div"],
        "loads": counts["loads"] / LOAD_PORTS,
    }
    limit = max(candidates, key=candidates.get)
    return round(candidates[limit], 2), limit, {k: round(v, 2) for k, v in candidates.items()}


def analyse(build_dir):
    src = Path(build_dir) / "kernel/CMakeFiles/sphray_kernel.dir/src"
    result = {}
    for isa, (name, reg, width) in OBJECTS.items():
        obj = src / name
        if not obj.exists():
            continue
        found = batch_loop(intersect_body(disassemble(obj)))
        if found is None:
            print(f"{isa}: no batch loop with an early-out test found in {obj}", file=sys.stderr)
            continue
        skip, live, batches = found
        entry = {"width": width, "register": reg, "batches_per_pass": batches}
        for label, path in (("early_out", skip), ("full", live)):
            counts = classify(path, reg)
            cycles, limit, all_limits = bound(counts, reg)
            entry[label] = {"counts": {k: v / batches for k, v in counts.items()},
                            "cycles_per_batch": round(cycles / batches, 2), "limited_by": limit,
                            "per_resource": {k: round(v / batches, 2) for k, v in all_limits.items()}}
            entry[label + "_listing"] = [f"{mnem} {ops}".strip() for _, mnem, ops in path]
        result[isa] = entry
    return result


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build_dir", help="a configured and built sphray build directory")
    ap.add_argument("--write", action="store_true", help="store the result in bench/kernel_bounds.json")
    args = ap.parse_args(argv)
    result = analyse(args.build_dir)
    if not result:
        sys.exit("no kernel objects found")
    for isa, e in result.items():
        for label in ("early_out", "full"):
            p = e[label]
            c = p["counts"]
            print(f"{isa:7} {label:9} per batch ({e['batches_per_pass']} per pass): {c['instructions']:g} instructions, "
                  f"{c['vector']:g} vector ({c['mul_class']:g} multiply-class, {c['sqrt']:g} sqrt, {c['div']:g} div), {c['loads']:g} loads: "
                  f"bound {p['cycles_per_batch']} cycles/batch ({p['limited_by']})")
    if args.write:
        out = {"model": {"issue_width": ISSUE_WIDTH, "load_ports": LOAD_PORTS, **MODEL}, "kernels": result}
        (HERE / "kernel_bounds.json").write_text(json.dumps(out, indent=1) + "\n")
        print(f"wrote {HERE / 'kernel_bounds.json'}")


if __name__ == "__main__":
    main(sys.argv[1:])
