#!/usr/bin/env python3
"""How many irregular vertices could purely local moves remove from a quad cage? (issue 13)

    python3 bench/valence_moves.py CAGE.obj [CAGE.obj ...]

Reads a pure-quad OBJ (e.g. `build/bench_quad MESH --target N --no-m --no-fit --obj PREFIX`) and
applies, greedily and on the topology only (no geometric check, so an upper bound of what the
simplifier's checked moves could do), until none is left:
  - edge rotations (the simplifier's swap: the two quads of an edge re-split along the other
    diagonal of their hexagon) that lower the summed valence defect |valence - regular|;
  - vertex rotations (every edge at an interior vertex turned one step around it: the edge
    neighbours lose a face, the diagonal ones gain one) that lower it.
Prints irregular vertices and the valence histogram before and after each kind of move.
Regular valence: 4 inside, 3 on the boundary (valence = faces + 1 there).
"""
import collections
import sys


def load(path):
    faces = []
    for line in open(path):
        if line.startswith("f "):
            faces.append([int(t.split("/")[0]) - 1 for t in line.split()[1:]])
    if any(len(f) != 4 for f in faces):
        sys.exit(f"{path}: not a pure-quad mesh")
    return faces


def topology(faces):
    edges, vf = {}, collections.defaultdict(list)
    for fi, q in enumerate(faces):
        for k in range(4):
            edges[(q[k], q[(k + 1) % 4])] = (fi, k)
            vf[q[k]].append(fi)
    boundary = {v for (a, b) in edges if (b, a) not in edges for v in (a, b)}
    return edges, vf, boundary


def irregular(faces):
    _, vf, boundary = topology(faces)
    hist, n = collections.Counter(), 0
    for v, fs in vf.items():
        val = len(fs) + (v in boundary)
        n += val != (3 if v in boundary else 4)
        hist[val] += 1
    return n, dict(sorted(hist.items()))


def greedy(faces, one_move):
    """Applies `one_move` (which finds and applies one improving move, or returns False) until none
    is left; the topology is rebuilt after each move. Returns the number of moves."""
    moves = 0
    while True:
        edges, vf, boundary = topology(faces)
        val = lambda v: len(vf[v]) + (v in boundary)
        reg = lambda v: 3 if v in boundary else 4
        if not one_move(faces, edges, vf, boundary, val, reg):
            return moves
        moves += 1


def edge_rotation(faces, edges, vf, boundary, val, reg):
    for fi in range(len(faces)):
        for k in range(4):
            q = faces[fi]
            u, v, a, b = q[k], q[(k + 1) % 4], q[(k + 2) % 4], q[(k + 3) % 4]
            if (v, u) not in edges:
                continue
            gi, kg = edges[(v, u)]
            g = faces[gi]
            if g[kg] != v or gi == fi:
                continue
            c, d = g[(kg + 2) % 4], g[(kg + 3) % 4]
            hexagon = [u, v, a, b, c, d]
            if len(set(hexagon)) < 6:
                continue
            best, best_var = 0, -1
            for var in (0, 1):
                dv = [-1, -1, 1, 0, 1, 0] if var == 0 else [-1, -1, 0, 1, 0, 1]
                if any(val(x) + dx < 3 and x not in boundary for x, dx in zip(hexagon, dv)):
                    continue
                delta = sum(abs(val(x) + dx - reg(x)) - abs(val(x) - reg(x)) for x, dx in zip(hexagon, dv))
                if delta < best:
                    best, best_var = delta, var
            if best_var < 0:
                continue
            nf, ng = ([a, b, u, c], [c, d, v, a]) if best_var == 0 else ([b, u, c, d], [d, v, a, b])
            new = [(nf[i], nf[(i + 1) % 4]) for i in range(4)] + [(ng[i], ng[(i + 1) % 4]) for i in range(4)]
            old = {(q[i], q[(i + 1) % 4]) for i in range(4)} | {(g[i], g[(i + 1) % 4]) for i in range(4)}
            if any(e in edges and e not in old for e in new):
                continue
            faces[fi], faces[gi] = nf, ng
            return True
    return False


def vertex_rotation(faces, edges, vf, boundary, val, reg):
    for v in list(vf):
        if v in boundary:
            continue
        fan = {}
        for fi in vf[v]:
            q = faces[fi]
            k = q.index(v)
            fan[q[(k + 1) % 4]] = (q[(k + 2) % 4], q[(k + 3) % 4], fi)
        n = len(vf[v])
        if len(fan) != n:
            continue
        xs, ys, fis = [next(iter(fan))], [], []
        while True:
            y, xn, fi = fan[xs[-1]]
            ys.append(y)
            fis.append(fi)
            if xn == xs[0] or xn not in fan or len(xs) > n:
                break
            xs.append(xn)
        if len(xs) != n or len(set(xs) | set(ys)) != 2 * n:
            continue
        if any(val(x) - 1 < 3 and x not in boundary for x in xs):
            continue
        if any((v, y) in edges or (y, v) in edges for y in ys):
            continue
        before = sum(abs(val(x) - reg(x)) for x in xs + ys)
        after = sum(abs(val(x) - 1 - reg(x)) for x in xs) + sum(abs(val(y) + 1 - reg(y)) for y in ys)
        if after >= before:
            continue
        for i in range(n):
            faces[fis[i]] = [v, ys[i - 1], xs[i], ys[i]]
        return True
    return False


def check(faces):
    """The moves keep a manifold, consistently oriented quad mesh: every directed edge once, no
    face repeating a vertex."""
    seen = set()
    for q in faces:
        if len(set(q)) != 4:
            sys.exit(f"internal error: face {q} repeats a vertex")
        for k in range(4):
            e = (q[k], q[(k + 1) % 4])
            if e in seen:
                sys.exit(f"internal error: directed edge {e} twice")
            seen.add(e)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for path in sys.argv[1:]:
        faces = load(path)
        print(f"{path}: {len(faces)} quads, irregular {irregular(faces)}")
        swaps = greedy(faces, edge_rotation)
        print(f"  after {swaps} edge rotations: irregular {irregular(faces)}")
        rotations = greedy(faces, vertex_rotation)
        print(f"  after {rotations} vertex rotations: irregular {irregular(faces)}")
        swaps = greedy(faces, edge_rotation)
        print(f"  after {swaps} more edge rotations: irregular {irregular(faces)}")
        check(faces)


if __name__ == "__main__":
    main()
