#!/usr/bin/env python3
"""Writes seed inputs for fuzz_mesh (tests/fuzz/fuzz_mesh.cpp; byte layout documented there):
small valid meshes and typical bad inputs, so the fuzzer starts past the decoder's error paths.

    tests/fuzz/make_seeds.py OUTDIR
"""
import os
import sys

ALLOW_POLY, KEEP_DEGEN, RAW, FITMAPS, FITMAPS_RAW, DELETED, FAR, REFERENCE = (1 << k for k in range(8))
SCALE_ONE = 120  # scale byte: 2^(120 - 120) = 1
NAN, INF = 0xF8, 0xF9


def coord(x):
    """Grid coordinate -124..123 -> byte."""
    assert -124 <= x <= 123
    return x + 124


def seed(verts, faces, flags=0, faux=None, params=(9, 3, 25, 0, 0, 40, 1, 0), deleted_mask=None, scale=SCALE_ONE):
    out = bytearray([len(verts), len(faces), flags, scale])
    if flags & DELETED:
        out.append(deleted_mask or 0)
    for v in verts:
        out += bytes(c if isinstance(c, int) and c >= 0xF8 else coord(c) for c in v)
    for i, f in enumerate(faces):
        out += bytes(f) + bytes([faux[i] if faux else 0])
    out += bytes(params)
    return bytes(out)


def grid(n):
    verts = [(i, j, (i * j) % 3) for j in range(n + 1) for i in range(n + 1)]
    faces = []
    for j in range(n):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            faces += [(a, b, c), (a, c, d)]
    return verts, faces


TETRA = ([(0, 0, 0), (4, 0, 0), (0, 4, 0), (0, 0, 4)], [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)])
OCTA = ([(4, 0, 0), (-4, 0, 0), (0, 4, 0), (0, -4, 0), (0, 0, 4), (0, 0, -4)],
        [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)])
CUBE_V = [(x, y, z) for z in (0, 4) for y in (0, 4) for x in (0, 4)]
CUBE_F = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
          (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]


def seeds():
    g3v, g3f = grid(3)
    g5v, g5f = grid(5)
    yield "tetra", seed(*TETRA)
    yield "tetra_fitmaps", seed(*TETRA, flags=FITMAPS)
    yield "octa_fitmaps_ref", seed(*OCTA, flags=FITMAPS | REFERENCE)
    yield "cube_fitmaps_raw", seed(CUBE_V, CUBE_F, flags=FITMAPS | FITMAPS_RAW)
    yield "grid3", seed(g3v, g3f, flags=FITMAPS)
    yield "grid5_decimate", seed(g5v, g5f, flags=FITMAPS, params=(9, 3, 25, 140, 0, 40, 1, 0))
    # quads as faux-edge pairs (diagonal a-c is edge 2 of (a,b,c) and edge 0 of (a,c,d))
    yield "grid3_polygonal", seed(g3v, g3f, flags=ALLOW_POLY, faux=[4 if k % 2 == 0 else 1 for k in range(len(g3f))])
    # an unwelded soup: every triangle with its own copies of the vertices
    sv, sf = [], []
    for f in OCTA[1]:
        sf.append(tuple(range(len(sv), len(sv) + 3)))
        sv += [OCTA[0][i] for i in f]
    yield "octa_soup", seed(sv, sf, flags=FITMAPS)
    # three triangles on one edge (non-manifold), a flipped face, a repeated face
    yield "nonmanifold_edge", seed([(0, 0, 0), (4, 0, 0), (2, 4, 0), (2, -4, 0), (2, 0, 4)],
                                   [(0, 1, 2), (1, 0, 3), (0, 1, 4)], flags=FITMAPS | FITMAPS_RAW)
    # a T-junction: two squares meshed apart, the right one with a vertex on the left one's edge
    yield "t_junction", seed([(0, 0, 0), (4, 0, 0), (4, 4, 0), (0, 4, 0),
                              (4, 0, 0), (8, 0, 0), (8, 4, 0), (4, 4, 0), (4, 2, 0), (8, 2, 0)],
                             [(0, 1, 2), (0, 2, 3), (4, 5, 9), (4, 9, 8), (8, 9, 6), (8, 6, 7)], flags=FITMAPS)
    yield "flipped_repeated", seed(OCTA[0], [(4, 2, 0)] + OCTA[1][1:] + [OCTA[1][1]])
    yield "nan_vertex", seed([(0, 0, 0), (4, 0, 0), (NAN, 4, 0)], [(0, 1, 2)])
    yield "inf_vertex", seed([(0, 0, 0), (INF, 0, 0), (0, 4, 0)], [(0, 1, 2)])
    yield "past_end", seed([(0, 0, 0), (4, 0, 0), (0, 4, 0)], [(0, 1, 0xFC)])
    yield "deleted_vertex", seed(*TETRA, flags=DELETED, deleted_mask=1)
    yield "far_away", seed(*OCTA, flags=FAR | FITMAPS)
    yield "tiny_scale", seed(*TETRA, flags=FITMAPS, scale=0)
    yield "huge_scale", seed(*TETRA, flags=FITMAPS, scale=240)
    yield "degenerate_keep", seed([(0, 0, 0), (4, 0, 0), (8, 0, 0), (0, 4, 0)], [(0, 1, 2), (0, 1, 3), (1, 1, 3)],
                                  flags=KEEP_DEGEN | FITMAPS | FITMAPS_RAW)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for name, data in seeds():
        with open(os.path.join(out, "seed_" + name), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
