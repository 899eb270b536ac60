"""Shared fixtures of the PyMeshLab tests (issue 14): the plugin for MeshLab's 2022.02+ interface,
built in build-2025 and installed into .venv's PyMeshLab by scripts/setup_pymeshlab.sh.
Run: .venv/bin/python -m pytest tests/python (ctest does, as PyMeshLab.pytest)."""
import os
import pathlib

import numpy as np
import pymeshlab
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("FITMAP_DATA_DIR", REPO / ".deps" / "data" / "meshes"))
SCRIPTS = REPO / "meshlab_scripts"

# The public API: filter name -> PyMeshLab function (issue 14's table).
PYTHON_NAMES = {
    "Compute Fitmaps": "compute_scalar_by_fitmaps_per_vertex",
    "Fitmap Quad Simplification": "generate_fitmap_quad_simplification",
    "Fit Catmull-Clark Surface and Bake Displacement": "generate_catmull_clark_fit_and_displacement_bake",
    "Loop Surrogate: Refine Surface": "generate_loop_surrogate_refinement",
    "Loop Surrogate: Snap Points": "apply_loop_surrogate_snap_points",
    "Loop Surrogate: Curvature": "compute_scalar_by_loop_surrogate_curvature_per_vertex",
}


def icosphere(level, radius=1.0):
    """Icosahedron with `level` 1:4 subdivisions projected onto the sphere (20 * 4^level triangles)."""
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
             (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    V = [np.array(v, float) / np.linalg.norm(v) for v in verts]
    for _ in range(level):
        mids, new = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in mids:
                m = V[a] + V[b]
                V.append(m / np.linalg.norm(m))
                mids[key] = len(V) - 1
            return mids[key]

        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return pymeshlab.Mesh(vertex_matrix=np.array(V) * radius, face_matrix=np.array(faces, dtype=np.int32))


def scaled_icosphere_meshset(axes, level=4, offset=0.0, name="ellipsoid"):
    """A MeshSet with one layer `name`: the icosphere of `level` scaled by `axes` (x, y, z factors)
    and moved by `offset` along every axis."""
    ms = pymeshlab.MeshSet()
    m = icosphere(level)
    V = m.vertex_matrix() * np.array(axes, float) + offset
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=m.face_matrix()), name)
    return ms


def layers_snapshot(ms):
    """Every layer's vertices, faces and scalar, to check that a failed filter changed nothing."""
    out = []
    for i in range(ms.mesh_number()):
        m = ms.mesh(i)
        out.append((m.vertex_matrix().copy(), m.face_matrix().copy(),
                    m.vertex_scalar_array().copy() if m.has_vertex_scalar() else None))
    return out


def assert_layers_equal(a, b):
    assert len(a) == len(b)
    for (va, fa, qa), (vb, fb, qb) in zip(a, b):
        np.testing.assert_array_equal(va, vb)
        np.testing.assert_array_equal(fa, fb)
        assert (qa is None) == (qb is None)
        if qa is not None:
            np.testing.assert_array_equal(qa, qb)


@pytest.fixture
def bunny_path():
    p = DATA / "bunny00.off"
    assert p.exists(), f"{p} missing: run scripts/setup.sh (it fetches the libcgal-demo scans)"
    return p


@pytest.fixture(scope="module")
def bunny_pipeline(tmp_path_factory):
    """Fitmaps -> quad simplification -> fit and bake on bunny00 with the defaults (pipeline.mlx's
    values), outputs in a scratch folder. Returns (MeshSet, output folder)."""
    p = DATA / "bunny00.off"
    assert p.exists(), f"{p} missing: run scripts/setup.sh"
    out = tmp_path_factory.mktemp("bunny_pipeline")
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(p))
    ms.compute_scalar_by_fitmaps_per_vertex()
    ms.generate_fitmap_quad_simplification()
    ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0, outputdir=str(out))
    return ms, out
