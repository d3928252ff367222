#!/usr/bin/env python3
"""Writes buckminsterfullerene, C60, as a PDB file: 60 carbon atoms at the vertices of a
truncated icosahedron whose edges (the C-C bonds) are 1.4 angstroms, as HETATM records with the
element in columns 77-78. Standard library only.

    python3 docs/gallery/make_c60_pdb.py c60.pdb
    sphray render -s c60.pdb -m shaded -o c60.png

The vertices are the even permutations of (0, +-1, +-3 phi), (+-1, +-(2 + phi), +-2 phi) and
(+-phi, +-2, +-(2 phi + 1)), phi the golden ratio: a truncated icosahedron of edge 2, scaled
here by 0.7.
"""
import itertools
import math
import sys

PHI = (1 + math.sqrt(5)) / 2
BOND = 1.4  # angstroms


def even_permutations(v):
    """The three cyclic permutations of v: the even ones of three coordinates."""
    return [(v[0], v[1], v[2]), (v[1], v[2], v[0]), (v[2], v[0], v[1])]


def vertices():
    points = set()
    for base in ((0, 1, 3 * PHI), (1, 2 + PHI, 2 * PHI), (PHI, 2, 2 * PHI + 1)):
        for signs in itertools.product((1, -1), repeat=3):
            signed = tuple(s * c for s, c in zip(signs, base))
            for p in even_permutations(signed):
                points.add(tuple(round(c * BOND / 2, 9) + 0.0 for c in p))  # + 0.0: no -0.0
    return sorted(points)


def check(points):
    """60 atoms, each bonded to exactly three others at BOND."""
    assert len(points) == 60, len(points)
    for p in points:
        bonded = [q for q in points if q != p and abs(math.dist(p, q) - BOND) < 1e-6]
        assert len(bonded) == 3, (p, len(bonded))


def pdb(points):
    lines = ["HEADER    FULLERENE C60 (TRUNCATED ICOSAHEDRON, C-C 1.4 A)"]
    for i, (x, y, z) in enumerate(points, 1):
        # PDB v3.3 columns: record 1-6, serial 7-11, name 13-16, residue 18-20, chain 22,
        # residue number 23-26, x y z 31-54, occupancy 55-60, B 61-66, element 77-78.
        lines.append(f"HETATM{i:5d}  C{i:<3d}C60 A   1    "
                     f"{x:8.3f}{y:8.3f}{z:8.3f}  1.00  0.00           C")
    lines.append("END")
    return "\n".join(lines) + "\n"


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "c60.pdb"
    points = vertices()
    check(points)
    with open(out, "w", encoding="ascii") as f:
        f.write(pdb(points))


if __name__ == "__main__":
    main()
