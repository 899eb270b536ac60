"""Layers with a transformation matrix (MeshLab's Align tool or a Transform filter run without
freezing sets one; MeshLab draws the layer through it): the filters compute in the layer's own
coordinates, the layers they add carry its matrix, and two-layer filters bring one layer into the
other's coordinates (docs/robustness.md "Layer matrices")."""
import json

import numpy as np
import pymeshlab

from conftest import icosphere, scaled_icosphere_meshset

# A rigid motion: 30 degrees about z, then a translation.
C, S = np.cos(np.pi / 6), np.sin(np.pi / 6)
RIGID = np.array([[C, -S, 0, 3.0], [S, C, 0, -2.0], [0, 0, 1, 5.0], [0, 0, 0, 1]])


def ellipsoid_meshset(matrix=None):
    """One layer: the icosphere of level 4 scaled to the ellipsoid 1 x 0.6 x 0.4; with `matrix`, that
    matrix set on the layer and not frozen (the vertices stay as they are)."""
    ms = scaled_icosphere_meshset((1.0, 0.6, 0.4))
    if matrix is not None:
        ms.set_matrix(transformmatrix=matrix, freeze=False)
    return ms


def apply(matrix, V):
    return (V @ matrix[:3, :3].T) + matrix[:3, 3]


def pipeline(ms, outdir):
    ms.generate_fitmap_quad_simplification(targetpatches=60)
    r = ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0, outputdir=str(outdir))
    return r


def test_new_layers_carry_the_matrix_of_the_layer_they_come_from(tmp_path):
    plain, moved = ellipsoid_meshset(), ellipsoid_meshset(RIGID)
    rp = pipeline(plain, tmp_path / "plain")
    rm = pipeline(moved, tmp_path / "moved")
    assert rp == rm  # the same figures: computed in the layer's own coordinates
    assert plain.mesh_number() == moved.mesh_number() == 5  # input, quads, fitted, limit, displaced
    for i in range(plain.mesh_number()):
        np.testing.assert_array_equal(plain.mesh(i).vertex_matrix(), moved.mesh(i).vertex_matrix())
        np.testing.assert_array_equal(plain.mesh(i).transform_matrix(), np.eye(4))
        # every new layer shows where the input shows (before: the identity, the cage drawn away
        # from the scan)
        np.testing.assert_allclose(moved.mesh(i).transform_matrix(), RIGID, atol=1e-12)
    # Loop refinement: its layer too
    moved.set_current_mesh(0)
    moved.generate_loop_surrogate_refinement(targetfaces=12000, refinemode=1)
    np.testing.assert_allclose(moved.current_mesh().transform_matrix(), RIGID, atol=1e-12)


def test_fit_takes_a_control_layer_with_another_matrix_into_the_reference_coordinates(tmp_path):
    # Reference: the plain ellipsoid; its cage fitted as it is ...
    plain = ellipsoid_meshset()
    expected = pipeline(plain, tmp_path / "plain")
    fitted = plain.mesh(2).vertex_matrix()
    # ... and the same cage on a layer whose coordinates are the cage moved by RIGID^-1 with the
    # matrix RIGID (it shows in the same place): the fit must map it back into the reference's
    # coordinates first. Without that it fits a cage 6 units off the reference.
    ms = ellipsoid_meshset()
    ms.generate_fitmap_quad_simplification(targetpatches=60)
    ms.set_matrix(transformmatrix=np.linalg.inv(RIGID), freeze=True)  # coordinates moved ...
    ms.set_matrix(transformmatrix=RIGID, freeze=False)  # ... and shown back in place
    assert np.abs(ms.current_mesh().vertex_matrix() - plain.mesh(1).vertex_matrix()).max() > 1
    r = ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0, outputdir=str(tmp_path / "m"))
    # The same fit up to the round trip's rounding (the cage is read at float precision, as
    # MeshLab 2020.09 holds it: ~1e-7 of 6 units), which the least-squares fit passes on linearly.
    assert r["patches"] == expected["patches"]
    assert r["irregular_vertices"] == expected["irregular_vertices"]
    for k in ["rms_limit_permille", "rms_displaced_permille"]:
        assert abs(r[k] - expected[k]) <= 1e-3 * expected[k], k
    assert r["unprojectable_pct"] == expected["unprojectable_pct"] == 0
    # control points: within 1e-4 (4e-5 of the 2.5 diagonal; measured 2.1e-5 at two loosely held
    # points of 62, the rest below 1e-5); without the mapping they are ~6 off
    np.testing.assert_allclose(ms.mesh(2).vertex_matrix(), fitted, atol=1e-4)
    # the new layers (and the files) are in the reference's coordinates, with its matrix
    np.testing.assert_array_equal(ms.mesh(2).transform_matrix(), np.eye(4))
    rep = json.loads((tmp_path / "m" / "report.json").read_text())
    assert rep["patches"] == expected["patches"]


def test_snap_maps_the_points_into_the_nets_coordinates_and_back():
    # Net: an icosphere of level 1 (identity matrix); points: a sphere of radius 1.5 around it.
    # Snapped as plain coordinates ...
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(1), "net")
    ms.add_mesh(icosphere(2, radius=1.5), "points")
    ms.apply_loop_surrogate_snap_points(surfacemesh=0, creaseangle=0)
    expected = ms.current_mesh().vertex_matrix()
    # ... and as coordinates moved by RIGID^-1 on a layer with the matrix RIGID.
    ms2 = pymeshlab.MeshSet()
    ms2.add_mesh(icosphere(1), "net")
    p = icosphere(2, radius=1.5)
    ms2.add_mesh(pymeshlab.Mesh(vertex_matrix=apply(np.linalg.inv(RIGID), p.vertex_matrix()),
                                face_matrix=p.face_matrix()), "points")
    ms2.set_matrix(transformmatrix=RIGID, freeze=False)
    ms2.apply_loop_surrogate_snap_points(surfacemesh=0, creaseangle=0)
    m = ms2.current_mesh()
    np.testing.assert_allclose(m.transform_matrix(), RIGID, atol=1e-12)  # kept
    # where MeshLab draws them: onto the net's limit surface, as the plain points
    np.testing.assert_allclose(apply(RIGID, m.vertex_matrix()), expected, atol=1e-9)
    np.testing.assert_allclose(m.vertex_scalar_array(), ms.current_mesh().vertex_scalar_array(), atol=1e-9)


# The warning for a matrix that is not a similarity: tests/e2e/layer_matrix_test.cpp (meshlabserver's log).
