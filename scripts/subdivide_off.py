#!/usr/bin/env python3
"""Splits every triangle of an OFF mesh into four at its edge midpoints (shared midpoints, so a
closed mesh stays closed): a larger test mesh of the same shape, e.g. the ~100k-triangle input of
docs/lodgen.md's cluster-hierarchy timing. Standard library only.

Usage: python3 scripts/subdivide_off.py IN.off OUT.off [TIMES]
"""
import sys


def read_off(path):
    words = []
    with open(path) as f:
        for line in f:
            words += line.split("#", 1)[0].split()
    if not words or words[0] != "OFF":
        raise SystemExit(f"{path}: not an OFF file")
    nv, nf = int(words[1]), int(words[2])
    at = 4
    vertices = [tuple(float(x) for x in words[at + 3 * i:at + 3 * i + 3]) for i in range(nv)]
    at += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(words[at])
        ids = [int(x) for x in words[at + 1:at + 1 + n]]
        faces += [(ids[0], ids[k], ids[k + 1]) for k in range(1, n - 1)]  # fan-triangulated
        at += 1 + n
    return vertices, faces


def subdivide(vertices, faces):
    vertices = list(vertices)
    midpoint = {}

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in midpoint:
            midpoint[key] = len(vertices)
            vertices.append(tuple((p + q) / 2 for p, q in zip(vertices[a], vertices[b])))
        return midpoint[key]

    out = []
    for a, b, c in faces:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return vertices, out


def main():
    if len(sys.argv) not in (3, 4):
        raise SystemExit(__doc__)
    vertices, faces = read_off(sys.argv[1])
    for _ in range(int(sys.argv[3]) if len(sys.argv) == 4 else 1):
        vertices, faces = subdivide(vertices, faces)
    with open(sys.argv[2], "w") as f:
        f.write(f"OFF\n{len(vertices)} {len(faces)} 0\n")
        f.writelines(f"{x!r} {y!r} {z!r}\n" for x, y, z in vertices)
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in faces)
    print(f"{sys.argv[2]}: {len(vertices)} vertices, {len(faces)} triangles")


if __name__ == "__main__":
    main()
