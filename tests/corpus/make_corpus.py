#!/usr/bin/env python3
"""Writes the bad / edge-case input corpus of issue 16 ("every input a user can load: a valid
result or a clear error, never a crash, hang or silent garbage").

    tests/corpus/make_corpus.py OUTDIR

Writes ~55 small mesh files (OFF mostly; some ASCII PLY, OBJ, binary and ASCII STL) and
OUTDIR/manifest.json: per file its name, kind, a description and, per filter (fitmaps,
pipeline, pipeline_budget, loop_refine, loop_curvature), the expected verdict class:
  "valid"  - must produce a valid result;
  "error"  - must fail with a clear message containing every keyword ("a|b": either word);
  "either" - a valid result or a clear error (keywords, if any, apply to the error).
Optional per-file checks: "log_keywords" (the log must mention them whatever the verdict),
"accept_valid_if_log" (a valid result is fine when MeshLab's loader logged this repair),
"report_max" (upper bounds for report.json numbers of the pipeline without a budget).
Python 3 standard library only; the output is byte-for-byte deterministic. Every generated
mesh is checked with topology() (also used by run_corpus.py) against what its kind claims.
"""
import json
import math
import os
import random
import struct
import sys
from collections import defaultdict

# pipeline_budget: the whole pipeline with `--patches 200` (BUDGET): the budget ladder, the
# budget's start rules and the fit on every input (issue 13)
FILTERS = ["fitmaps", "pipeline", "pipeline_budget", "loop_refine", "loop_curvature"]
BUDGET = 200


# ----------------------------------------------------------------------------- topology check
def topology(V, F):
    """Counts of what makes a polygon mesh hard: non-manifold edges / vertices, edges whose two
    faces disagree in orientation, orientability, degenerate faces, unreferenced vertices."""
    edges = defaultdict(list)  # undirected edge -> [(face, forward?)]
    degenerate = 0
    for fi, f in enumerate(F):
        if len(set(f)) < len(f):
            degenerate += 1
            continue
        for k in range(len(f)):
            a, b = f[k], f[(k + 1) % len(f)]
            edges[(min(a, b), max(a, b))].append((fi, a < b))
    nm_edges = sum(1 for u in edges.values() if len(u) > 2)
    misoriented = sum(1 for u in edges.values() if len(u) == 2 and u[0][1] == u[1][1])
    # orientability: propagate a flip bit per face across manifold edges, look for a conflict
    adj = defaultdict(list)
    for u in edges.values():
        if len(u) == 2:
            (f, d), (g, e) = u
            adj[f].append((g, int(d == e)))
            adj[g].append((f, int(d == e)))
    flip, orientable = {}, True
    for s in range(len(F)):
        if s in flip:
            continue
        flip[s], stack = 0, [s]
        while stack:
            f = stack.pop()
            for g, rel in adj[f]:
                want = flip[f] ^ rel
                if g not in flip:
                    flip[g] = want
                    stack.append(g)
                elif flip[g] != want:
                    orientable = False
    # non-manifold vertices: the faces around a vertex form more than one edge-connected fan
    vfaces = defaultdict(list)
    for fi, f in enumerate(F):
        if len(set(f)) == len(f):
            for v in f:
                vfaces[v].append(fi)
    nm_verts = 0
    for v, fs in vfaces.items():
        parent = {f: f for f in fs}

        def root(x):
            while parent[x] != x:
                parent[x] = parent[parent[x]]
                x = parent[x]
            return x
        by_edge = defaultdict(list)
        for f in fs:
            n = len(F[f])
            k = F[f].index(v)
            for w in (F[f][(k + 1) % n], F[f][k - 1]):
                by_edge[w].append(f)
        for group in by_edge.values():
            for g in group[1:]:
                parent[root(g)] = root(group[0])
        if len({root(f) for f in fs}) > 1:
            nm_verts += 1
    return {"faces": len(F), "vertices": len(V), "non_manifold_edges": nm_edges,
            "non_manifold_vertices": nm_verts, "misoriented_edges": misoriented,
            "orientable": orientable, "degenerate_faces": degenerate,
            "boundary_edges": sum(1 for u in edges.values() if len(u) == 1),
            "unreferenced_vertices": len(V) - len(vfaces)}


def read_off(path):
    """(V, F) of an OFF file (COFF/NOFF/... headers, comments; extra per-vertex numbers ignored).
    Raises ValueError on a malformed file."""
    with open(path, errors="replace") as fh:
        lines = [l.split("#")[0].split() for l in fh]
    lines = [l for l in lines if l]
    if not lines or not lines[0][0].endswith("OFF"):
        raise ValueError("no OFF header")
    head = lines[0][1:] or lines[1]
    rest = lines[1:] if lines[0][1:] else lines[2:]
    nv, nf = int(head[0]), int(head[1])
    V = [tuple(float(x) for x in l[:3]) for l in rest[:nv]]
    F = [tuple(int(x) for x in l[1:1 + int(l[0])]) for l in rest[nv:nv + nf]]
    if len(V) < nv or len(F) < nf:
        raise ValueError("truncated")
    return V, F


# ----------------------------------------------------------------------------- geometry
def add(a, b): return (a[0] + b[0], a[1] + b[1], a[2] + b[2])
def sub(a, b): return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
def mul(a, s): return (a[0] * s, a[1] * s, a[2] * s)
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def unit(a): return mul(a, 1.0 / math.sqrt(dot(a, a)))


def tetrahedron():
    return [(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)], [(0, 1, 2), (0, 2, 3), (0, 3, 1), (1, 3, 2)]


def octahedron():
    V = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    F = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    return V, F


def icosahedron():
    t = (1 + math.sqrt(5)) / 2
    V = [unit(p) for p in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                           (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
         (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return V, F


def midpoint_subdivide(V, F, project=True):
    V, mid, out = list(V), {}, []
    def m(a, b):
        k = (min(a, b), max(a, b))
        if k not in mid:
            p = mul(add(V[a], V[b]), 0.5)
            V.append(unit(p) if project else p)
            mid[k] = len(V) - 1
        return mid[k]
    for a, b, c in F:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return V, out


def icosphere(level, r=1.0, c=(0, 0, 0)):
    V, F = icosahedron()
    for _ in range(level):
        V, F = midpoint_subdivide(V, F)
    return [add(mul(p, r), c) for p in V], F


def grid_faces(rows, cols, idx, quads=False, wrap_u=False):
    """Faces of a (rows+1) x (cols+1) vertex grid addressed by idx(i, j) (i along rows)."""
    F = []
    for i in range(rows):
        for j in range(cols):
            a, b, c, d = idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j)
            F += [(a, b, c, d)] if quads else [(a, b, c), (a, c, d)]
    return F


def torus(nu=32, nv=16, R=1.0, r=0.35, quads=False):
    V = [((R + r * math.cos(2 * math.pi * j / nv)) * math.cos(2 * math.pi * i / nu),
          (R + r * math.cos(2 * math.pi * j / nv)) * math.sin(2 * math.pi * i / nu),
          r * math.sin(2 * math.pi * j / nv)) for i in range(nu) for j in range(nv)]
    return V, [f[::-1] for f in grid_faces(nu, nv, lambda i, j: (i % nu) * nv + j % nv, quads)]


def uv_sphere(n_lon, n_lat, quads=False, hemisphere=False):
    """Poles as single vertices (valence n_lon); quads or triangles in between."""
    rings = n_lat // 2 if hemisphere else n_lat - 1
    V = [(0, 0, 1)]
    for k in range(1, rings + 1):
        th = math.pi * k / n_lat
        V += [(math.sin(th) * math.cos(2 * math.pi * i / n_lon), math.sin(th) * math.sin(2 * math.pi * i / n_lon),
               math.cos(th)) for i in range(n_lon)]
    ring = lambda k, i: 1 + (k - 1) * n_lon + i % n_lon
    F = [(0, ring(1, i), ring(1, i + 1)) for i in range(n_lon)]
    F += [f[::-1] for f in grid_faces(rings - 1, n_lon, lambda k, i: ring(k + 1, i), quads)]
    if not hemisphere:
        V.append((0, 0, -1))
        F += [(len(V) - 1, ring(rings, i + 1), ring(rings, i)) for i in range(n_lon)]
    return V, F


def cylinder(n=24, m=40, r=0.1, h=10.0, capped=False, z_rings=None):
    zs = z_rings or [h * k / m for k in range(m + 1)]
    V = [(r * math.cos(2 * math.pi * i / n), r * math.sin(2 * math.pi * i / n), z) for z in zs for i in range(n)]
    idx = lambda k, i: k * n + i % n
    F = grid_faces(len(zs) - 1, n, idx)
    if capped:
        V += [(0, 0, zs[0]), (0, 0, zs[-1])]
        b, t = len(V) - 2, len(V) - 1
        F += [(b, idx(0, i + 1), idx(0, i)) for i in range(n)]
        F += [(t, idx(len(zs) - 1, i), idx(len(zs) - 1, i + 1)) for i in range(n)]
    return V, F


def cone(n, closed=False, apex=(0, 0, 0), direction=1):
    """Apex + ring of n vertices at z = -direction (outward orientation); optional base fan."""
    V = [apex] + [add(apex, (0.5 * math.cos(2 * math.pi * i / n), 0.5 * math.sin(2 * math.pi * i / n), -direction))
                  for i in range(n)]
    F = [(0, 1 + i, 1 + (i + 1) % n) for i in range(n)]
    if closed:
        V.append(add(apex, (0, 0, -direction)))
        F += [(len(V) - 1, 1 + (i + 1) % n, 1 + i) for i in range(n)]
    if direction < 0:
        F = [f[::-1] for f in F]
    return V, F


def disk(rings=8, segs=24):
    V = [(0, 0, 0)] + [(k / rings * math.cos(2 * math.pi * i / segs), k / rings * math.sin(2 * math.pi * i / segs), 0)
                       for k in range(1, rings + 1) for i in range(segs)]
    idx = lambda k, i: 0 if k == 0 else 1 + (k - 1) * segs + i % segs
    F = [(0, idx(1, i + 1), idx(1, i)) for i in range(segs)]
    return V, F + grid_faces(rings - 1, segs, lambda k, i: idx(k + 1, i))


def plane(n=20):
    V = [(j / n, i / n, 0) for i in range(n + 1) for j in range(n + 1)]
    return V, grid_faces(n, n, lambda i, j: i * (n + 1) + j)


def mobius(nu=60, nv=6):
    V = []
    for i in range(nu):
        u = 2 * math.pi * i / nu
        for j in range(nv + 1):
            w = j / nv - 0.5
            r = 1 + w * math.cos(u / 2)
            V.append((r * math.cos(u), r * math.sin(u), w * math.sin(u / 2)))
    # after a full turn the strip comes back upside down: row nu is row 0 reversed
    idx = lambda i, j: (i * (nv + 1) + j) if i < nu else (nv - j)
    return V, grid_faces(nu, nv, idx)


def voxels(cells, k=1, quads=False, scale=(1, 1, 1)):
    """Boundary of a set of unit voxels, each face split k x k; outward orientation."""
    ids, V, F = {}, [], []
    def vid(p):
        if p not in ids:
            ids[p] = len(V)
            V.append(tuple(p[a] / k * scale[a] for a in range(3)))
        return ids[p]
    for c in sorted(cells):
        for a in range(3):
            for s in (-1, 1):
                nb = list(c); nb[a] += s
                if tuple(nb) in cells:
                    continue
                u, v = (a + 1) % 3, (a + 2) % 3
                for i in range(k):
                    for j in range(k):
                        corners = []
                        for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                            p = [x * k for x in c]
                            p[a] += k if s > 0 else 0
                            p[u] += i + du; p[v] += j + dv
                            corners.append(vid(tuple(p)))
                        q = corners if s > 0 else corners[::-1]
                        F += [tuple(q)] if quads else [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    return V, F


def smooth(V, F, iters=4, lam=0.5):
    nbr = defaultdict(set)
    for f in F:
        for k in range(len(f)):
            nbr[f[k]].add(f[k - 1]); nbr[f[k - 1]].add(f[k])
    for _ in range(iters):
        V = [add(mul(V[i], 1 - lam), mul(mul(tuple(map(sum, zip(*(V[j] for j in nbr[i])))), 1 / len(nbr[i])), lam))
             for i in range(len(V))]
    return V


def merge(*meshes):
    V, F = [], []
    for mv, mf in meshes:
        F += [tuple(i + len(V) for i in f) for f in mf]
        V += list(mv)
    return V, F


def two_spheres_sharing_an_edge():
    V, F = icosphere(1)  # convex: the plane through an edge between its faces' normals supports it
    a, b, c = F[0]
    other = next(f for f in F[1:] if a in f and b in f)
    n = unit(add(unit(cross(sub(V[b], V[a]), sub(V[c], V[a]))),
                 unit(cross(sub(V[other[1]], V[other[0]]), sub(V[other[2]], V[other[0]])))))
    refl = [sub(p, mul(n, 2 * dot(sub(p, V[a]), n))) for p in V]
    keep = [i for i in range(len(V)) if i not in (a, b)]
    remap = {i: len(V) + k for k, i in enumerate(keep)}
    remap.update({a: a, b: b})
    return V + [refl[i] for i in keep], F + [tuple(remap[i] for i in f[::-1]) for f in F]


def separately_gridded_box(cells):
    """The unit cube's six faces, face i gridded cells[i] x cells[i] with its own vertices (a CAD
    body exported face by face): where two faces' grids differ, T-junctions along their edge."""
    V, F = [], []
    for face, n in enumerate(cells):
        axis, plus = face // 2, face % 2 == 0
        u, v = (axis + 1) % 3, (axis + 2) % 3
        if not plus:
            u, v = v, u
        base = len(V)
        for i in range(n + 1):
            for j in range(n + 1):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = (1.0 if plus else 0.0), i / n, j / n
                V.append(tuple(p))
        idx = lambda i, j: base + i * (n + 1) + j
        for i in range(n):
            for j in range(n):
                F += [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)), (idx(i, j), idx(i + 1, j + 1), idx(i, j + 1))]
    return V, F


def t_seam(V, F):
    """Two halves meshed separately along the seam x = median: each triangle of the x > median side
    with one edge on the seam is split at that edge's midpoint, its neighbour keeps the edge."""
    cx = sorted(v[0] for v in V)[len(V) // 2]
    side = [sum(V[i][0] for i in f) / 3 > cx for f in F]
    faces_of = {}
    for fi, f in enumerate(F):
        for k in range(3):
            faces_of.setdefault(frozenset((f[k], f[(k + 1) % 3])), []).append(fi)
    seam = {e for e, fs in faces_of.items() if len(fs) == 2 and side[fs[0]] != side[fs[1]]}
    V, out = list(V), []
    for fi, f in enumerate(F):
        on = [k for k in range(3) if frozenset((f[k], f[(k + 1) % 3])) in seam]
        if not side[fi] or len(on) != 1:
            out.append(f)
            continue
        a, b, c = f[on[0]], f[(on[0] + 1) % 3], f[(on[0] + 2) % 3]
        V.append(mul(add(V[a], V[b]), 0.5))
        out += [(a, len(V) - 1, c), (len(V) - 1, b, c)]
    return V, out


def seam_copies(V, F, jitter, rng):
    """Two halves exported separately and put back together: the x > median half gets its own
    copies of the seam's vertices, each coordinate moved by up to `jitter`."""
    cx = sorted(v[0] for v in V)[len(V) // 2]
    side = [sum(V[i][0] for i in f) / 3 > cx for f in F]
    used = [set(), set()]
    for fi, f in enumerate(F):
        used[side[fi]].update(f)
    V, copy = list(V), {}
    for v in sorted(used[0] & used[1]):
        V.append(tuple(c + rng.uniform(-jitter, jitter) for c in V[v]))
        copy[v] = len(V) - 1
    return V, [tuple(copy.get(i, i) for i in f) if side[fi] else f for fi, f in enumerate(F)]


def triangle_soup(V, F):
    return [V[i] for f in F for i in f], [(3 * k, 3 * k + 1, 3 * k + 2) for k in range(len(F))]


# ----------------------------------------------------------------------------- writers
def fmt(x, prec=9):
    return ("%.*g" % (prec, x)) if isinstance(x, float) else str(x)


def off_text(V, F, prec=9):
    out = ["OFF", "%d %d 0" % (len(V), len(F))]
    out += [" ".join(fmt(float(c), prec) for c in p) for p in V]
    out += ["%d %s" % (len(f), " ".join(map(str, f))) for f in F]
    return "\n".join(out) + "\n"


def ply_text(V, F):
    head = ["ply", "format ascii 1.0", "element vertex %d" % len(V), "property float x", "property float y",
            "property float z", "element face %d" % len(F), "property list uchar int vertex_indices", "end_header"]
    return "\n".join(head + [" ".join(fmt(float(c)) for c in p) for p in V] +
                     ["%d %s" % (len(f), " ".join(map(str, f))) for f in F]) + "\n"


def obj_text(V, F):
    return "".join("v %s\n" % " ".join(fmt(float(c)) for c in p) for p in V) + \
           "".join("f %s\n" % " ".join(str(i + 1) for i in f) for f in F)


def facet_normal(V, f):
    n = cross(sub(V[f[1]], V[f[0]]), sub(V[f[2]], V[f[0]]))
    l = math.sqrt(dot(n, n))
    return mul(n, 1 / l) if l > 0 else (0.0, 0.0, 0.0)


def stl_binary(V, F):
    out = [b"corpus binary STL".ljust(80, b" "), struct.pack("<I", len(F))]
    for f in F:
        out.append(struct.pack("<12fH", *facet_normal(V, f), *V[f[0]], *V[f[1]], *V[f[2]], 0))
    return b"".join(out)


def stl_ascii(V, F):
    out = ["solid corpus"]
    for f in F:
        out += ["facet normal %s" % " ".join(fmt(c) for c in facet_normal(V, f)), "outer loop"]
        out += ["vertex %s" % " ".join(fmt(float(c)) for c in V[i]) for i in f]
        out += ["endloop", "endfacet"]
    return "\n".join(out + ["endsolid corpus"]) + "\n"


# ----------------------------------------------------------------------------- the corpus
def expect(verdict, keywords=()):
    return {f: {"verdict": verdict, "keywords": list(keywords)} for f in FILTERS}


VALID = expect("valid")


def corpus():
    """Yields (name, kind, description, content, expectation, extra, (V, F) or None, claims)."""
    rnd = random.Random(16)
    sphere = icosphere(3)  # 642 vertices, 1280 triangles
    ok = {"manifold": True, "consistent": True}

    def off(name, kind, desc, mesh, exp=VALID, claims=ok, prec=9, **extra):
        return name, kind, desc, off_text(*mesh, prec=prec), exp, extra, mesh, claims

    # --- manifold, consistently oriented triangle meshes: valid
    yield off("tetra.off", "closed-manifold", "tetrahedron (4 triangles)", tetrahedron())
    yield off("octa.off", "closed-manifold", "octahedron", octahedron())
    yield off("icosa.off", "closed-manifold", "icosahedron", icosahedron())
    yield off("cube12.off", "closed-manifold", "cube of 12 triangles", voxels({(0, 0, 0)}))
    yield off("box.off", "closed-manifold", "2 x 1 x 0.5 box, 4x2x1 grid faces",
              voxels({(i, j, 0) for i in range(4) for j in range(2)}, scale=(0.5, 0.5, 0.5)))
    yield off("sphere.off", "closed-manifold", "icosphere, 1280 triangles", sphere)
    yield off("inward.off", "closed-manifold", "icosphere oriented inwards (consistently)",
              (sphere[0], [f[::-1] for f in sphere[1]]))
    yield off("torus.off", "closed-manifold", "torus 32 x 16", torus())
    holes = {(1, 1, 0), (3, 1, 0), (5, 1, 0)}
    g3 = voxels({(i, j, 0) for i in range(7) for j in range(3)} - holes, k=2, scale=(1, 1, 0.6))
    yield off("genus3.off", "closed-manifold", "genus-3 slab with three holes, smoothed", (smooth(*g3), g3[1]))
    # the coverage guard's area trigger (docs/robustness.md "Flat open shapes"): the cage reaches the rim
    yield off("disk.off", "open-manifold", "flat open disk", disk(), report_max={"unprojectable_pct": 1.0})
    yield off("plane.off", "open-manifold", "flat 20 x 20 plane grid", plane())
    yield off("hemi.off", "open-manifold", "hemisphere (open)", uv_sphere(32, 16, hemisphere=True))
    yield off("cyl_open.off", "open-manifold", "thin cylinder z=0..10, r=0.1, open", cylinder())
    # the coverage guard (docs/robustness.md "Closed thin shapes"): the cage covers the tube
    yield off("cyl_capped.off", "closed-manifold", "thin cylinder z=0..10, r=0.1, capped", cylinder(capped=True),
              report_max={"unprojectable_pct": 1.0, "rms_limit_permille": 5.0})
    # Very high valence: every filter gives a result in seconds (the Loop filters up to valence
    # 2048, LoopSurfaceParams::maxValence; the pipeline starts from an isotropic remesh).
    high_valence = VALID
    yield off("poles500.off", "closed-manifold", "UV sphere with poles of valence 500", uv_sphere(500, 8),
              exp=high_valence)
    yield off("cone2000.off", "open-manifold", "open cone of 2000 triangles around one vertex", cone(2000),
              exp=high_valence)
    yield off("midsub.off", "closed-manifold", "icosphere(2) midpoint-subdivided once, not projected",
              midpoint_subdivide(*icosphere(2), project=False))
    yield off("tri1.off", "open-manifold", "a single triangle", ([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 2)]),
              exp=expect("either"))

    # --- polygonal files: valid
    yield off("quadcube.off", "polygonal", "pure-quad cube, 4x4 quads per side", voxels({(0, 0, 0)}, k=4, quads=True))
    n = 12
    prism = ([(math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), z) for z in (0, 1) for i in range(n)],
             [tuple(range(n - 1, -1, -1)), tuple(range(n, 2 * n))] +
             [(i, (i + 1) % n, n + (i + 1) % n, n + i) for i in range(n)])
    yield off("ngon_prism.off", "polygonal", "prism with 12-gon caps and quad sides", prism)
    star = ([((1 if i % 2 else 0.45) * math.cos(math.pi * i / 5), (1 if i % 2 else 0.45) * math.sin(math.pi * i / 5), z)
             for z in (0, 0.4) for i in range(10)],
            [tuple(range(9, -1, -1)), tuple(range(10, 20))] +
            [(i, (i + 1) % 10, 10 + (i + 1) % 10, 10 + i) for i in range(10)])
    yield off("star_prism.off", "polygonal", "prism with concave 10-gon star caps", star)
    yield off("mixed.off", "polygonal", "UV sphere: quads, triangle fans at the poles", uv_sphere(24, 12, quads=True))
    tq = torus(24, 12, quads=True)
    yield "torus_quads.obj", "polygonal", "quad torus as OBJ", obj_text(*tq), VALID, {}, tq, ok
    yield "torus_quads.ply", "polygonal", "quad torus as ASCII PLY", ply_text(*tq), VALID, {}, tq, ok
    yield "sphere.obj", "closed-manifold", "icosphere as OBJ (triangles)", obj_text(*sphere), VALID, {}, sphere, ok
    yield "sphere.ply", "closed-manifold", "icosphere as ASCII PLY", ply_text(*sphere), VALID, {}, sphere, ok

    # --- triangle soups, unreferenced vertices, orientation
    soup_claims = {"manifold": True, "consistent": True, "soup": True}
    yield ("soup_sphere.stl", "soup", "binary STL of the icosphere (every facet its own vertices)",
           stl_binary(*sphere), VALID, {}, None, None)
    yield ("soup_torus_ascii.stl", "soup", "ASCII STL of a torus", stl_ascii(*torus(24, 12)), VALID, {}, None, None)
    yield off("soup.off", "soup", "icosphere, every face with its own 3 vertices", triangle_soup(*sphere),
              claims=soup_claims)
    # the same soup with every corner moved by up to 5e-7 (rounded face by face, so nothing is an
    # exact duplicate): welded within 1e-6 of the diagonal, so the icosphere's few patches, not one
    # per triangle (1 280 unwelded)
    jr = random.Random(18)
    rounded = triangle_soup(*sphere)
    rounded = ([tuple(c + jr.uniform(-5e-7, 5e-7) for c in p) for p in rounded[0]], rounded[1])
    yield off("soup_rounded.off", "soup", "icosphere soup, every corner rounded on its own (no exact duplicates)",
              rounded, claims=soup_claims, prec=17, report_max={"patches": 200})
    stray_max = {"rms_limit_permille": 20, "max_limit_permille": 100, "rms_displaced_permille": 20}
    strays = [(rnd.uniform(-1, 1) * 100, rnd.uniform(-1, 1) * 100, rnd.uniform(50, 100)) for _ in range(200)]
    yield off("strays.off", "unreferenced", "icosphere + 200 unreferenced vertices 50..100 away",
              (sphere[0] + strays, sphere[1]),
              report_max=stray_max)
    yield off("farvertex.off", "unreferenced", "icosphere + one unreferenced vertex at x = 1000",
              (sphere[0] + [(1000.0, 0.0, 0.0)], sphere[1]), report_max=stray_max)
    flipped = set(rnd.sample(range(len(sphere[1])), len(sphere[1]) // 2))
    yield off("flipped_half.off", "inconsistent-orientation", "icosphere, a random half of the faces flipped",
              (sphere[0], [f[::-1] if i in flipped else f for i, f in enumerate(sphere[1])]),
              claims={"manifold": True, "consistent": False, "orientable": True})
    yield off("mobius.off", "non-orientable", "Moebius strip", mobius(), exp=expect("error", ["orient"]),
              claims={"manifold": True, "orientable": False})

    # --- non-manifold: valid. Along an edge the working copy separates the triangles (the two that
    # continue each other keep the edge, the others come off it); at a vertex it splits the vertex
    # (input_prep.h)
    nm_edge = {"non_manifold_edges": True}
    yield off("nm_fin3.off", "non-manifold-edge", "three triangles on one edge",
              ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)], [(0, 1, 2), (1, 0, 3), (0, 1, 4)]),
              claims=nm_edge)
    a, b, c = sphere[1][0]
    fin = (sphere[0] + [mul(add(sphere[0][a], sphere[0][b]), 0.75)], sphere[1] + [(a, b, len(sphere[0]))])
    yield off("nm_sphere_fin.off", "non-manifold-edge", "icosphere + a fin triangle on one of its edges", fin,
              claims=nm_edge)
    yield off("nm_2spheres.off", "non-manifold-edge", "two convex spheres sharing one edge",
              two_spheres_sharing_an_edge(), claims=nm_edge)
    up, down = cone(32, True, direction=1), cone(32, True, direction=-1)
    tips = (up[0] + down[0][1:], up[1] + [tuple(i + len(up[0]) - 1 if i else 0 for i in f) for f in down[1]])
    yield off("nm_cones.off", "non-manifold-vertex", "two closed cones touching at their tips", tips,
              claims={"non_manifold_vertices": True})
    yield off("nm_bowtie.off", "non-manifold-vertex", "bowtie: two triangles sharing one vertex",
              ([(0, 0, 0), (1, 0.5, 0), (1, -0.5, 0), (-1, 0.5, 0), (-1, -0.5, 0)], [(0, 2, 1), (0, 3, 4)]),
              claims={"non_manifold_vertices": True})

    # --- broken files: an error, never a crash
    sv, sf = sphere
    bad = sf[:-1] + [(sf[-1][0], sf[-1][1], len(sv) + 5)]
    yield ("bad_index.off", "bad-index", "a face corner refers to vertex n+5", off_text(sv, bad),
           expect("error", ["range|index|not exist"]), {}, None, None)
    yield ("neg_index.off", "bad-index", "a face corner is -1", off_text(sv, sf[:-1] + [(sf[-1][0], sf[-1][1], -1)]),
           expect("error", ["range|index|not exist"]), {}, None, None)
    text = off_text(*sphere)
    yield ("truncated.off", "truncated", "icosphere OFF cut off in the middle of the faces",
           text[: len(text) * 3 // 4], expect("error"), {}, None, None)
    nonfin = {"accept_valid_if_log": ["nan coords"]}
    for name, val, desc in (("nan.off", "nan nan nan", "one vertex has NaN coordinates"),
                            ("nan1.off", "0.5 nan 0.5", "one vertex has one NaN coordinate"),
                            ("inf.off", "inf 0 0", "one vertex has an infinite coordinate"),
                            ("huge.off", "1e39 0 0", "one vertex overflows float (1e39)")):
        lines = text.split("\n")
        lines[2 + 7] = val
        yield (name, "non-finite", desc, "\n".join(lines), expect("error", ["nan|infinite|finite"]),
               nonfin if "nan" in val else {}, None, None)
    plines = ply_text(*sphere).split("\n")
    plines[9 + 3] = "nan 0 0"
    yield ("nan.ply", "non-finite", "ASCII PLY, one vertex x = nan", "\n".join(plines),
           expect("error", ["nan|infinite|finite"]), nonfin, None, None)

    # --- components
    balls = merge(*[icosphere(1, 0.4, (1.0 * (i % 10), 1.0 * (i // 10), 0)) for i in range(50)])
    yield off("comps50.off", "components", "50 small spheres", balls)
    tiny = merge(sphere, *[([(3 + 0.05 * k, 0, 0), (3 + 0.05 * k + 0.02, 0, 0), (3 + 0.05 * k, 0.02, 0)], [(0, 1, 2)])
                           for k in range(5)])
    yield off("tinycomps.off", "components", "icosphere + 5 isolated tiny triangles", tiny)

    # --- what raw scans come with (synthetic: no third-party meshes): valid results
    scan = icosphere(4)  # 2562 vertices, 5120 triangles, radius 1
    nv_ = [mul(v, 1 + rnd.gauss(0, 0.01)) for v in scan[0]]  # 1 % radial noise
    yield off("scan_noisy.off", "scan", "icosphere(4) with 1 % radial noise on every vertex", (nv_, scan[1]))
    sv_ = list(scan[0])
    for i in rnd.sample(range(len(sv_)), 20):  # outlier vertices: spikes of 30 % of the radius
        sv_[i] = mul(sv_[i], 1.3)
    yield off("scan_spikes.off", "scan", "icosphere(4) with 20 vertices pushed out 30 % (spikes)", (sv_, scan[1]))
    # a scanner's wild point kept by the reconstruction: one vertex 1 000 diagonals away, at the tip
    # of six needles; the quad pipeline refuses it (far_spikes.h), the Loop filters take it as it is
    wild = list(scan[0])
    wild[100] = add(wild[100], (2000.0, 600.0, 400.0))
    wild_exp = dict(expect("error", ["far from the rest of the surface"]))
    wild_exp.update({f: {"verdict": "valid", "keywords": []} for f in ("loop_refine", "loop_curvature")})
    yield off("scan_wild_vertex.off", "scan", "icosphere(4) with one vertex flung 1 000 diagonals away (a wild point)",
              (wild, scan[1]), exp=wild_exp)
    specks = [([add(c, (0, 0, 0)), add(c, (0.01, 0, 0)), add(c, (0.01, 0.01, 0.005)), add(c, (0, 0.01, 0))],
               [(0, 1, 2), (0, 2, 3)])
              for c in [(rnd.uniform(-1.4, 1.4), rnd.uniform(-1.4, 1.4), rnd.uniform(-1.4, 1.4)) for _ in range(100)]]
    yield off("scan_debris.off", "scan", "icosphere(4) + 100 specks of 2 triangles around it (debris)",
              merge(scan, *specks))
    # 30 holes: the faces around 30 vertices far apart removed (occlusion holes)
    centres = []
    for i in rnd.sample(range(len(scan[0])), 400):
        if all(dot(sub(scan[0][i], scan[0][j]), sub(scan[0][i], scan[0][j])) > 0.09 for j in centres):
            centres.append(i)
        if len(centres) == 30:
            break
    holed = [f for f in scan[1] if not any(c in f for c in centres)]
    yield off("scan_holes.off", "scan", "icosphere(4) with 30 one-ring holes", (scan[0], holed))
    yield off("scan_double.off", "scan", "two nested icospheres 0.2 % apart (a doubled wall of merged scans)",
              merge(scan, icosphere(4, 1.002)))
    # 10 flaps standing on chains of two sphere edges (a wall of 4 triangles each, 10 % of the
    # radius high): 20 edges of three triangles, the flaps to come off and the sphere to stay whole
    nbr = {}
    for f in scan[1]:
        for k in range(3):
            nbr.setdefault(f[k], set()).update((f[(k + 1) % 3], f[(k + 2) % 3]))
    walls, used = [], set()
    for a in random.Random(17).sample(range(len(scan[0])), 200):  # (rnd left as it was for what follows)
        b = min(nbr[a])
        c = max(x for x in nbr[b] if x != a and x not in nbr[a])
        if used & {a, b, c}:
            continue
        used |= {a, b, c} | nbr[a] | nbr[b] | nbr[c]
        top = [len(scan[0]) + 3 * len(walls) + k for k in range(3)]
        walls.append(([mul(scan[0][x], 1.1) for x in (a, b, c)],
                      [(a, b, top[1]), (a, top[1], top[0]), (b, c, top[2]), (b, top[2], top[1])]))
        if len(walls) == 10:
            break
    flaps = (scan[0] + [p for w in walls for p in w[0]], scan[1] + [f for w in walls for f in w[1]])
    yield off("scan_fins.off", "scan", "icosphere(4) with 10 flaps standing on chains of its edges (20 edges of 3 triangles)",
              flaps, claims={"non_manifold_edges": True})
    # T-junctions: separately meshed parts of one surface (closed by the working copy)
    yield off("tjunction_box.off", "t-junctions", "unit cube, its six faces gridded 3..11 cells a side each on its own",
              separately_gridded_box([3, 5, 7, 8, 11, 4]), report_max={"patches": 150})
    yield off("scan_tseam.off", "scan", "icosphere(4) whose halves were meshed separately (T-junctions on the seam)",
              t_seam(*scan), claims={"non_manifold_vertices": True}, report_max={"patches": 30})
    yield off("scan_seam_copies.off", "scan", "icosphere(4) whose halves have their own copies of the seam's vertices, "
              "1e-7 apart", seam_copies(*scan, 1e-7, random.Random(23)), claims=None, prec=12,
              report_max={"patches": 30})
    yield off("scan_overlap.off", "scan", "two icospheres overlapping by half a radius (unmerged, they intersect)",
              merge(scan, icosphere(4, 1.0, (1.5, 0, 0))))

    # --- precision: unit sphere at x = 1e7 (float has ~1 unit resolution there)
    yield off("far1e7.off", "far-from-origin", "unit icosphere centred at x = 1e7", icosphere(3, 1.0, (1e7, 0, 0)),
              exp=expect("error", ["shape is lost"]), prec=17)
    yield off("far1e4.off", "far-from-origin", "unit icosphere centred at x = 1e4 (float keeps ~1e-3)",
              icosphere(3, 1.0, (1e4, 0, 0)), prec=17)
    # Embree's ray-triangle test works in float with its determinant clamped below 1e-18: on a
    # mesh a few 1e-8 across every hit came back at a corner, and the simplification refused
    # every collapse (a cage of all the start's quads, an RMS error of 0); beyond ~1e15 no ray
    # hit. EmbreeScene scales its float copy by a power of two: the same cage as at radius 1.
    yield off("scale1e-9.off", "tiny-coordinates", "icosphere of radius 1e-9", icosphere(3, 1e-9), prec=17,
              report_max={"patches": 30})
    yield off("scale1e15.off", "huge-coordinates", "icosphere of radius 1e15 (below the 1e17 limit)",
              icosphere(3, 1e15), prec=17, report_max={"patches": 30})
    # finite in float but beyond what Embree's rays represent (1.844e18; it aborts on them)
    yield off("scale1e20.off", "huge-coordinates", "icosphere of radius 1e20 (finite floats)",
              icosphere(2, 1e20), exp=expect("error", ["beyond 1e17|scale"]), prec=9)

    # --- degenerate geometry: no crash, finite results (valid or a clear error)
    any_ = expect("either")
    dv = list(sv)
    for i in range(12, 40, 4):  # move a few vertices onto a neighbour: zero-area faces, coincident vertices
        f = next(f for f in sf if i in f)
        dv[i] = dv[f[(f.index(i) + 1) % 3]]
    yield off("zero_area.off", "degenerate", "icosphere, 7 vertices moved onto a neighbour", (dv, sf), exp=any_)
    yield off("repeat_idx.off", "degenerate", "icosphere + 5 faces repeating a vertex index",
              (sv, sf + [(i, i, i + 1) for i in range(5)]), exp=any_, claims=None)
    rings = [0, 0.5, 1.0, 1.0 + 1e-6, 1.5, 2.0]
    yield off("slivers.off", "degenerate", "capped cylinder with two rings 1e-6 apart (slivers)",
              cylinder(24, r=1.0, capped=True, z_rings=rings), exp=any_)
    yield off("dup_faces.off", "degenerate", "icosphere with 10 faces duplicated", (sv, sf + sf[:10]), exp=any_,
              claims=None)
    cv, cf = list(sv), list(sf)
    for t in range(0, 40, 8):  # T-junction: split one face at an edge midpoint + the zero-area (a, b, m)
        a, b, c = cf[t]
        cv.append(mul(add(cv[a], cv[b]), 0.5))
        m = len(cv) - 1
        cf[t] = (a, m, c)
        cf += [(m, b, c), (a, b, m)]
    yield off("collinear.off", "degenerate", "icosphere with 5 triangles of three collinear vertices", (cv, cf),
              exp=any_)

    # --- nothing to work on: an error
    empty = expect("error", ["empty|no faces|point cloud|no vertices"])
    yield "empty.off", "empty", "a zero-byte file", "", empty, {}, None, None
    yield "empty_hdr.off", "empty", "OFF header with 0 vertices, 0 faces", "OFF\n0 0 0\n", empty, {}, None, None
    pts = [(rnd.uniform(-1, 1), rnd.uniform(-1, 1), rnd.uniform(-1, 1)) for _ in range(300)]
    yield "points.off", "point-cloud", "300 vertices, no faces", off_text(pts, []), empty, {}, None, None
    yield "points.ply", "point-cloud", "ASCII PLY, 300 vertices, no faces", ply_text(pts, []), empty, {}, None, None


def check_claims(name, mesh, claims):
    t = topology(*mesh)
    def need(cond, what):
        if not cond:
            raise SystemExit("make_corpus: %s is not %s: %s" % (name, what, t))
    if claims.get("manifold"):
        need(t["non_manifold_edges"] + t["non_manifold_vertices"] + t["degenerate_faces"] == 0, "manifold")
    if "consistent" in claims and not claims.get("soup"):
        need((t["misoriented_edges"] == 0) == claims["consistent"], "as consistently oriented as claimed")
    if "orientable" in claims:
        need(t["orientable"] == claims["orientable"], "as orientable as claimed")
    if claims.get("non_manifold_edges"):
        need(t["non_manifold_edges"] > 0, "non-manifold along an edge")
    if claims.get("non_manifold_vertices"):
        need(t["non_manifold_vertices"] > 0 and t["non_manifold_edges"] == 0, "non-manifold at a vertex only")
    return t


def main():
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    files = []
    for name, kind, desc, content, exp, extra, mesh, claims in corpus():
        entry = {"name": name, "kind": kind, "description": desc, "expect": exp}
        if mesh is not None and claims is not None:
            t = check_claims(name, mesh, claims)
            entry["topology"] = {k: t[k] for k in ("vertices", "faces", "boundary_edges")}
        entry.update(extra)
        data = content.encode() if isinstance(content, str) else content
        with open(os.path.join(out, name), "wb") as fh:
            fh.write(data)
        files.append(entry)
    with open(os.path.join(out, "manifest.json"), "w") as fh:
        json.dump({"issue": 16, "filters": FILTERS, "files": files}, fh, indent=1, sort_keys=True)
        fh.write("\n")
    print("make_corpus: wrote %d files + manifest.json to %s" % (len(files), out))


if __name__ == "__main__":
    main()
