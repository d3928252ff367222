#!/usr/bin/env python3
"""Writes the kernel fuzzer's seed corpus (corpus/kernel/) in the byte format kernel_fuzzer.cpp
decodes: a head byte (ray count, misalignment, padded view), a sphere count, the rays, the
spheres, the padding's radii, then per ray whether it starts on a sphere's surface; the PDB
fuzzer's (corpus/pdb/): small PDB files; the PLY fuzzer's (corpus/ply/): a first byte
choosing the radius given ('@' none), then a PLY file; and the .sphp fuzzer's (corpus/sphp/):
binary particle files. Run from tests/fuzz/; the output is committed."""
import random
import struct
from pathlib import Path


def num(x):
    """An ordinary value (selector 9): 1/256 steps in [-128, 128)."""
    v = max(-32768, min(32767, round(x * 256)))
    return bytes([0x09]) + struct.pack(">h", v)


def special(kind, sign=False):
    sel = {"zero": 0, "nan": 1, "inf": 2, "denormal": 3, "huge": 4, "tiny": 5, "max": 8}[kind]
    extra = {"denormal": b"\x00\x00\x12\x34", "huge": b"\x80\x3f", "tiny": b"\x40\x02"}
    return bytes([sel | (0x80 if sign else 0)]) + extra.get(kind, b"")


def ray(o, d, tmin=None, tmax=None):
    out = b"".join(num(c) if isinstance(c, (int, float)) else c for c in (*o, *d))
    bounds = (1 if tmin is not None else 0) | (2 if tmax is not None else 0)
    out += bytes([bounds])
    for t in (tmin, tmax):
        if t is not None:
            out += num(t) if isinstance(t, (int, float)) else t
    return out


def sphere(c, r):
    out = b"".join(num(v) if isinstance(v, (int, float)) else v for v in c)
    return out + (num(r) if isinstance(r, (int, float)) else r) + b"\x00"  # keep the sign


def on_surface(sphere_index, tangent=False, tilt_exponent=None, inward=False):
    """Moves a ray's origin onto a sphere, towards its decoded origin from the centre; tangent
    turns its direction tangent there, tilted by 2^-tilt_exponent (out, or inward) if given."""
    how = 1 | (2 if tangent else 0) | (4 if tilt_exponent is None else 0) | (8 if inward else 0)
    return bytes([how, sphere_index]) + (bytes([tilt_exponent]) if tilt_exponent else b"")


def seed(rays, spheres, misalign=0, padded=False, surface=()):
    head = (len(rays) - 1) | (misalign << 2) | (0x40 if padded else 0)
    return (bytes([head, len(spheres)]) + b"".join(rays) + b"".join(spheres) + bytes(16) +
            b"".join(surface))


def main():
    out = Path("corpus/kernel")
    out.mkdir(parents=True, exist_ok=True)
    book = sphere((0, 0, -1), 0.5)
    seeds = {
        "book-centre-ray": seed([ray((0, 0, 0), (0, 0, -1))], [book]),
        "book-corner-rays": seed([ray((0, 0, 0), (-1.777, 1, -1)), ray((0, 0, 0), (1.777, -1, -1)),
                                  ray((0, 0, 0), (0, 0, 1)), ray((0, 0, -1), (0, 1, 0))], [book]),
        "inside-far-root": seed([ray((0, 0, -1), (0, 0, -2), 0.1, 3)], [book], misalign=3),
        "tangent": seed([ray((0.5, 0, 0), (0, 0, -1)), ray((0, 0.5, 5), (0, 0, -0.25))],
                        [book, sphere((0, 0, -1), 0.5)], padded=True),
        "specials": seed([ray((special("nan"), 0, 0), (0, 0, -1)),
                          ray((0, 0, 0), (special("zero"), special("zero"), special("zero"))),
                          ray((0, 0, 0), (special("denormal"), 0, special("tiny"))),
                          ray((0, 0, 0), (0, 0, -1), special("inf", True), special("inf"))],
                         [book, sphere((special("inf"), 0, 0), 1), sphere((0, 0, -3), special("nan")),
                          sphere((0, 0, -2), special("zero")), sphere((0, 0, -4), -1),
                          sphere((special("huge"), 0, 0), special("huge")),
                          sphere((0, special("tiny"), -5), special("tiny")),
                          sphere((special("max"), 0, 0), special("max"))], misalign=7),
    }
    # Issue 17: rays leaving a sphere of radius 0.1 tangentially from its surface, in a view of
    # 33 (the others radius 0, so that the SIMD kernels run).
    small = [sphere((0, 0, 0), 0.1)] + [sphere((0, 0, 0), 0)] * 32
    seeds["grazing-from-surface"] = seed(
        [ray((0, -1, 0), (1, 0, 0)), ray((0, -1, 0), (1, 0, 0)), ray((1, 1, 0), (1, -1, 2)),
         ray((0, 1, 0), (3, 0, 1), 0)], small,
        surface=[on_surface(0, True, 30), on_surface(0, True, 23), on_surface(0, True),
                 on_surface(0, True, 20, inward=True)])
    rng = random.Random(20261122)
    for n in (7, 8, 9, 16, 17, 33, 40):
        spheres = [sphere([rng.uniform(-10, 10) for _ in range(3)], rng.uniform(0.3, 3))
                   for _ in range(n)]
        rays = [ray([rng.uniform(-12, 12) for _ in range(3)], [rng.uniform(-2, 2) for _ in range(3)])
                for _ in range(4)]
        seeds[f"random-{n}"] = seed(rays, spheres, misalign=n % 16, padded=n % 2 == 1)
    for n in (5, 17):
        spheres = [sphere([rng.uniform(-10, 10) for _ in range(3)], rng.uniform(0.3, 3))
                   for _ in range(n)]
        rays = [ray([rng.uniform(-1, 1) for _ in range(3)], [rng.uniform(-2, 2) for _ in range(3)])
                for _ in range(4)]
        surface = [on_surface(rng.randrange(n), tangent=i > 0, tilt_exponent=rng.choice([None, 24, 12]))
                   for i in range(4)]
        seeds[f"surface-{n}"] = seed(rays, spheres, surface=surface)
    for name, data in seeds.items():
        (out / name).write_bytes(data)
    pdb_seeds()


def pdb_atom(record, serial, name, x, y, z, element):
    """An ATOM or HETATM record in the PDB v3.3 columns (x y z 31-54, element 77-78)."""
    return (f"{record:<6}{serial:5d} {name:<4} RES A{serial:4d}    {x:8.3f}{y:8.3f}{z:8.3f}"
            f"  1.00  0.00          {element:>2}")


def pdb_seeds():
    out = Path("corpus/pdb")
    out.mkdir(parents=True, exist_ok=True)
    water = [pdb_atom("ATOM", 1, " O", 0, 0, 0, "O"), pdb_atom("ATOM", 2, " H1", 0.757, 0.586, 0, "H"),
             pdb_atom("ATOM", 3, " H2", -0.757, 0.586, 0, "")]
    seeds = {
        "water": "HEADER    WATER\n" + "\n".join(water) + "\nEND\n",
        "hetatm_names": "\n".join([pdb_atom("HETATM", 1, "FE", 1, 2, 3, ""),
                                   pdb_atom("HETATM", 2, "CA", -1, 0, 0, "  "),
                                   pdb_atom("HETATM", 3, "HG21", 0, 1, 0, ""),
                                   pdb_atom("HETATM", 4, "1HB", 0, 0, 1, ""),
                                   pdb_atom("HETATM", 5, "CL1", 2, 2, 2, "cl")]) + "\n",
        "models": "MODEL        1\r\n" + "\r\n".join(water) + "\r\nENDMDL\r\nMODEL        2\r\n"
                  + pdb_atom("ATOM", 4, " C", 9, 9, 9, "C") + "\r\nENDMDL\r\n",
        "short_lines": "ATOM      1  CA  ALA A   1       1.000   2.000   3.000\nATOM      2  N\n",
        "bad_element": pdb_atom("ATOM", 1, " X", 0, 0, 0, "XX") + "\n",
        "specials": pdb_atom("ATOM", 1, " C", 0, 0, 0, "C").replace("   0.000", "     nan", 1)
                    + "\n" + pdb_atom("ATOM", 2, " C", 0, 0, 0, "C").replace("   0.000", "    1e18", 1)
                    + "\n",
        "no_atoms": "HEADER    NOTHING\nREMARK   1\nEND\n",
    }
    for name, text in seeds.items():
        (out / name).write_bytes(text.encode("ascii"))


def ply_header(fmt, elements):
    """A PLY header: elements is a list of (name, count, [property lines])."""
    lines = ["ply", f"format {fmt} 1.0", "comment a seed"]
    for name, count, props in elements:
        lines.append(f"element {name} {count}")
        lines += [f"property {p}" for p in props]
    return ("\n".join(lines) + "\nend_header\n").encode()


def ply_seeds():
    out = Path("corpus/ply")
    out.mkdir(parents=True, exist_ok=True)
    xyzr = ["float x", "float y", "float z", "float radius"]
    rgb = ["uchar red", "uchar green", "uchar blue"]
    face = ("face", 2, ["list uchar int vertex_indices"])
    seeds = {
        "ascii-radius-colours": b"@" + ply_header("ascii", [("vertex", 3, xyzr + rgb), face]) +
        b"0 0 0 0.5 255 0 0\n1 0 0 0.25 0 255 0\n0 1 0 1 0 0 255\n3 0 1 2\n0\n",
        "ascii-no-radius": b"r" + ply_header("ascii", [("vertex", 2, ["double x", "double y",
                                                                        "double z"])]) +
        b"1.5 -2 3e2\n0 0 0\n",
        "ascii-bad-value": b"@" + ply_header("ascii", [("vertex", 1, xyzr)]) + b"1 2 nan 1\n",
    }
    # The same two vertices in both byte orders, after a face element with a list and with
    # properties of every width among theirs.
    props = ["short x", "uint8 y", "float64 z", "list ushort float normals", "float32 scale",
             "float red", "float green", "float blue", "int id"]
    for fmt, order in (("binary_little_endian", "<"), ("binary_big_endian", ">")):
        body = struct.pack(order + "BiiiBii", 3, 0, 1, 2, 2, 0, 1)
        for x, y, z, r in ((-3, 200, 0.5, 0.75), (7, 0, -1e3, 2.0)):
            body += struct.pack(order + "hBdH", x, y, z, 2) + struct.pack(order + "ff", 0, 1)
            body += struct.pack(order + "ffffi", r, 0.5, 0.25, 1.0, 9)
        seeds[f"{fmt}-types"] = b"@" + ply_header(fmt, [face, ("vertex", 2, props)]) + body
    written = struct.pack("<" + "ffffBBB" * 2, 0, 0, 0, 1, 255, 128, 0, 2, 0, 0, 0.5, 0, 0, 255)
    seeds["written-by-sphray"] = b"@" + ply_header("binary_little_endian",
                                                   [("vertex", 2, xyzr + rgb)]) + written
    seeds["truncated"] = seeds["written-by-sphray"][:-5]
    for name, data in seeds.items():
        (out / name).write_bytes(data)


def sphp_seeds():
    """The .sphp fuzzer's (corpus/sphp/): binary particle files, good and broken."""
    out = Path("corpus/sphp")
    out.mkdir(parents=True, exist_ok=True)

    def sphp(records, count=None):
        count = len(records) if count is None else count
        body = b"".join(struct.pack("<4f", *r) for r in records)
        return b"SPHRAYP\0" + struct.pack("<IIQQ", 1, 0, count, 0) + body

    three = [(0, 0, 0, 1), (2.5, -1, 0.5, 0.25), (1e17, -1e17, 0, 1e17)]
    seeds = {
        "three": sphp(three),
        "empty": sphp([]),
        "truncated": sphp(three)[:-5],
        "count-too-large": sphp(three, count=4),
        "nan": sphp([(0, 0, float("nan"), 1)]),
        "zero-radius": sphp([(1, 2, 3, 0)]),
        "version-2": sphp(three).replace(b"\1\0\0\0", b"\2\0\0\0", 1),
    }
    for name, data in seeds.items():
        (out / name).write_bytes(data)


if __name__ == "__main__":
    main()
    ply_seeds()
    sphp_seeds()
