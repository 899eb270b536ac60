"""Each PyMeshLab function of the plugin on a small analytic mesh and on bunny00, outputs checked."""
import json

import numpy as np
import pymeshlab
import pytest

from conftest import PYTHON_NAMES, assert_layers_equal, icosphere, layers_snapshot, scaled_icosphere_meshset


def ellipsoid_meshset(level=4, offset=0.0):
    """A MeshSet with one layer: the icosphere of `level` scaled to the ellipsoid 1 x 0.6 x 0.4
    (the Fitmaps vary over it), moved by `offset` along every axis."""
    return scaled_icosphere_meshset((1.0, 0.6, 0.4), level, offset)


def test_every_filter_is_a_meshset_method_with_its_python_name():
    names = set(pymeshlab.filter_list())
    ms = pymeshlab.MeshSet()
    for filt, py in PYTHON_NAMES.items():
        assert py in names, f"{filt}: {py} not in pymeshlab.filter_list()"
        assert callable(getattr(ms, py, None)), f"{filt}: MeshSet.{py} missing"
    # the default names PyMeshLab would have made up must not exist
    assert "compute_fitmaps" not in names and "loop_surrogate_curvature" not in names


def test_fitmaps_on_a_sphere_are_uniform():
    # A sphere looks the same at every vertex: both Fitmaps are (nearly) constant.
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(3), "sphere")
    ms.compute_scalar_by_fitmaps_per_vertex()
    s = ms.current_mesh().vertex_scalar_array()
    assert s.shape == (642,) and np.all(np.isfinite(s)) and s.min() > 0
    assert (s.max() - s.min()) / np.median(s) < 0.1
    assert ms.current_mesh().has_vertex_color()
    ms.compute_scalar_by_fitmaps_per_vertex(channel=1)  # M-fitmap: a radius
    m = ms.current_mesh().vertex_scalar_array()
    assert np.all(np.isfinite(m)) and m.min() > 0
    diag = np.linalg.norm(np.ptp(ms.current_mesh().vertex_matrix(), axis=0))
    assert m.max() <= 0.25 * diag * 1.0001  # the largest radius is 25 % of the diagonal
    assert (m.max() - m.min()) / np.median(m) < 0.1


def test_fitmaps_on_bunny(bunny_path):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(bunny_path))
    n = ms.current_mesh().vertex_number()
    ms.compute_scalar_by_fitmaps_per_vertex(numradii=9, tau=1.0)
    s = ms.current_mesh().vertex_scalar_array()
    assert s.shape == (n,) and np.all(np.isfinite(s)) and s.min() > 0
    assert s.max() > 1.5 * s.min()  # varies over the surface (ears vs back): 0.88 .. 1.64 (1/length)
    assert 0.8 < np.median(s) < 1.6
    assert ms.mesh_number() == 1  # the input layer only: Fitmaps are attributes


def test_quad_simplification_on_a_sphere():
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(4), "sphere")
    ms.generate_fitmap_quad_simplification()
    assert ms.mesh_number() == 2 and ms.current_mesh_id() == 1
    quads = ms.current_mesh().polygonal_face_list()
    assert all(len(f) == 4 for f in quads)
    assert 6 <= len(quads) <= 200
    # a sphere's control mesh: closed, Euler characteristic 2 (V - E + F with E = 2F for quads)
    assert ms.current_mesh().vertex_number() - len(quads) == 2
    assert ms.mesh(0).face_number() == 5120  # input untouched


def test_loop_refine_on_an_icosahedron_meshes_the_limit_surface():
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(0), "icosahedron")
    ms.generate_loop_surrogate_refinement(targetfaces=2000, creaseangle=0, refinemode=1)
    assert ms.mesh_number() == 2
    m = ms.current_mesh()
    assert 1900 <= m.face_number() <= 2200
    r = np.linalg.norm(m.vertex_matrix(), axis=1)
    # Loop's limit point of a valence-5 vertex v: (1 - 5 chi) v + chi * (sum of the 5 neighbours),
    # chi = 1 / (3 / (8 beta) + 5), beta = (5/8 - (3/8 + cos(2 pi / 5) / 4)^2) / 5; the neighbours of
    # a unit icosahedron's vertex sum to 5 v / sqrt(5): radius 1 - 5 chi (1 - 1/sqrt(5)) = 0.70781.
    beta = (5 / 8 - (3 / 8 + np.cos(2 * np.pi / 5) / 4) ** 2) / 5
    chi = 1 / (3 / (8 * beta) + 5)
    r_vertex = 1 - 5 * chi * (1 - 1 / np.sqrt(5))
    assert abs(r_vertex - 0.70781) < 1e-5
    assert np.sum(np.abs(r - r_vertex) < 1e-6) >= 12  # the control vertices' limit points
    assert r.max() < r_vertex + 1e-6 and r.min() > 0.69  # the rest of the surface: slightly inside


def test_loop_snap_moves_points_onto_the_limit_surface():
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(1), "net")
    ms.generate_loop_surrogate_refinement(targetfaces=5000, creaseangle=0, refinemode=1)
    limit_r = np.linalg.norm(ms.current_mesh().vertex_matrix(), axis=1)
    ms.add_mesh(icosphere(2, radius=1.5), "points")
    ms.apply_loop_surrogate_snap_points(surfacemesh=0, creaseangle=0)
    m = ms.current_mesh()
    r = np.linalg.norm(m.vertex_matrix(), axis=1)
    assert r.min() >= limit_r.min() - 1e-3 and r.max() <= limit_r.max() + 1e-3
    d = m.vertex_scalar_array()  # distance moved
    np.testing.assert_allclose(d, 1.5 - r, atol=1e-3)


def test_loop_curvature_of_a_sphere_is_positive():
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(3, radius=2.0), "sphere")
    ms.compute_scalar_by_loop_surrogate_curvature_per_vertex(curvaturekind=0, creaseangle=0)
    h = ms.current_mesh().vertex_scalar_array()
    assert np.all(np.isfinite(h))
    # mean curvature of a radius-2 sphere: 1/2 (the limit surface is slightly inside the net: a bit
    # more); Loop's limit curvature at the 12 valence-5 vertices is known to be off (0.61 here)
    assert abs(np.median(h) - 0.5) < 0.01 and h.min() > 0.495 and h.max() < 0.65
    ms.compute_scalar_by_loop_surrogate_curvature_per_vertex(curvaturekind=1, creaseangle=0)
    k = ms.current_mesh().vertex_scalar_array()
    assert abs(np.median(k) - 0.25) < 0.01 and k.min() > 0.24  # Gaussian: 1/4


def test_loop_curvature_on_bunny(bunny_path):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(bunny_path))
    ms.compute_scalar_by_loop_surrogate_curvature_per_vertex()
    h = ms.current_mesh().vertex_scalar_array()
    assert np.all(np.isfinite(h))
    assert np.median(h) > 0  # a closed-ish blob curves outwards on the whole
    assert ms.current_mesh().has_vertex_color()


def test_bunny_pipeline_layers_files_and_report(bunny_pipeline):
    ms, out = bunny_pipeline
    labels = [ms.mesh(i).label() for i in range(ms.mesh_number())]
    assert labels == ["bunny00.off", "bunny00.off quads tau=1%", "bunny00.off quads tau=1% fitted",
                      "bunny00.off quads tau=1% limit", "bunny00.off quads tau=1% displaced"]
    assert ms.mesh(0).has_vertex_scalar()  # Fitmaps as the input's scalar
    control = ms.mesh(1).polygonal_face_list()
    assert all(len(f) == 4 for f in control)
    rep = json.loads((out / "report.json").read_text())
    assert rep["patches"] == len(control)
    assert 300 <= rep["patches"] <= 500
    assert 0 < rep["rms_limit_permille"] < 2.5 and 0 < rep["rms_displaced_permille"] < 0.15
    for f in ["displacement.png", "displacement.json", "control.obj", "control.mtl", "control.ply", "report.json"]:
        assert (out / f).stat().st_size > 0, f
    fitted = ms.mesh(2)
    assert fitted.has_wedge_tex_coord() and fitted.texture_number() == 1
    assert list(fitted.textures().keys()) == ["displacement.png"]
    limit = ms.mesh(3)
    assert limit.face_number() == 2 * 64 * rep["patches"] and limit.has_vertex_scalar()


def test_fitted_layer_saves_with_its_texture(bunny_pipeline, tmp_path):
    ms, _ = bunny_pipeline
    ms.set_current_mesh(2)
    # MeshLab 2025.07's polygonal OBJ export drops per-wedge UVs and the map_Kd (save_polygonal=True
    # wrote 3 'vt' lines for a whole layer): triangles keep them. control.obj has the real quads.
    ms.save_current_mesh(str(tmp_path / "fitted.obj"), save_polygonal=False)
    obj = (tmp_path / "fitted.obj").read_text()
    assert obj.count("\nvt ") >= 3 * 2 * len(ms.mesh(1).polygonal_face_list()) // 2
    assert (tmp_path / "displacement.png").stat().st_size > 0
    assert "map_Kd displacement.png" in (tmp_path / "fitted.obj.mtl").read_text()


@pytest.mark.parametrize("call, message", [
    (lambda ms: ms.compute_scalar_by_fitmaps_per_vertex(tau=200), "tau must be in [0, 100] percent"),
    (lambda ms: ms.compute_scalar_by_fitmaps_per_vertex(numradii=1), "number of radii must be in [2, 64]"),
    (lambda ms: ms.generate_fitmap_quad_simplification(usemfitmap=False),
     "without the M-fitmap test a target patch count is needed (it would collapse everything)"),
    (lambda ms: ms.generate_fitmap_quad_simplification(regularity=-1), "the regularity weight must be in [0, 100]"),
    (lambda ms: ms.generate_fitmap_quad_simplification(layouttrials=0), "the layout trials must be in [1, 5]"),
    (lambda ms: ms.generate_fitmap_quad_simplification(swapsweep=6), "the swap sweep must be in [0, 5] swaps per chain"),
    (lambda ms: ms.generate_fitmap_quad_simplification(swapsweep=3, sweeptolerance=2000),
     "the swap sweep tolerance must be at most 1000 percent"),
    (lambda ms: ms.generate_fitmap_quad_simplification(firstworkingfaces=-1),
     "the first start of a dense input must be >= 0 triangles"),
    (lambda ms: ms.generate_fitmap_quad_simplification(closeholes=-1),
     "close small holes must be in [0, 100] percent"),
    (lambda ms: ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0),
     "the reference layer must be another layer than the control mesh (the current layer)"),
    (lambda ms: ms.apply_loop_surrogate_snap_points(surfacemesh=0),
     "the control net must be another layer than the points (the current layer)"),
    (lambda ms: ms.generate_loop_surrogate_refinement(targetfaces=0), "target triangles must be in [1, 5e7]"),
    (lambda ms: ms.compute_scalar_by_loop_surrogate_curvature_per_vertex(creaseangle=200),
     "crease angle must be in [0, 180] degrees"),
])
def test_bad_input_raises_the_message_and_leaves_the_layers(call, message):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(2), "sphere")
    before = layers_snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException) as e:
        call(ms)
    assert str(e.value).endswith("Details: " + message), str(e.value)
    assert_layers_equal(before, layers_snapshot(ms))


def test_a_layer_too_large_for_the_memory_is_refused(monkeypatch):
    # FITMAP_MAX_MEMORY_MB stands in for a small machine (core/pipeline_memory.h): the Fitmaps of
    # 5 120 triangles are estimated at 44 MB; refused before anything is allocated, the layer
    # untouched, as from meshlabserver (tests/e2e RunPipeline.ScanTooLargeForTheMemory...)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(4), "sphere")
    before = layers_snapshot(ms)
    monkeypatch.setenv("FITMAP_MAX_MEMORY_MB", "20")
    with pytest.raises(pymeshlab.PyMeshLabException) as e:
        ms.compute_scalar_by_fitmaps_per_vertex()
    assert ("Details: Compute Fitmaps: a layer of 5120 triangles would need about 44 MB of memory, more than the "
            "20 MB allowed: decimate the layer first") in str(e.value), str(e.value)
    assert_layers_equal(before, layers_snapshot(ms))
    monkeypatch.setenv("FITMAP_MAX_MEMORY_MB", "50")
    ms.compute_scalar_by_fitmaps_per_vertex()
    assert np.all(np.isfinite(ms.current_mesh().vertex_scalar_array()))


def test_fit_on_triangles_fails_with_the_importer_message():
    # the control layer must be quads; a triangle layer is refused, the document is unchanged
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(2), "scan")
    ms.add_mesh(icosphere(1), "not quads")
    before = layers_snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException) as e:
        ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0)
    assert "Failed to apply filter: generate_catmull_clark_fit_and_displacement_bake\nDetails: " in str(e.value)
    assert "quad" in str(e.value)
    assert_layers_equal(before, layers_snapshot(ms))


def test_fit_subdivides_a_quad_dominant_cage_once(tmp_path):
    # a cube cage with one side as two triangles, a polygonal layer (PyMeshLab's polygon
    # constructor marks the polygons' inner edges faux, as the importers do): subdivided once by
    # Catmull-Clark, one patch per polygon corner (5 quads x 4 + 2 triangles x 3), fitted; the
    # control layer is left as it was. (Not loaded from a polygonal PLY: PyMeshLab 2025.7's
    # load_new_mesh writes into the log of a deleted MeshSet whose filter had raised -- any
    # filter's, MeshLab's own included -- and crashes; earlier tests leave such MeshSets.)
    corners = np.array([(x, y, z) for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], dtype=float)
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7), (1, 7, 5)]
    ms = pymeshlab.MeshSet()
    ms.add_mesh(icosphere(4), "scan")
    ms.add_mesh(pymeshlab.Mesh(corners, [np.array(f, dtype=np.uint32) for f in faces]), "cage")
    before = layers_snapshot(ms)
    r = ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0, outputdir=str(tmp_path / "out"))
    assert r["patches"] == 26, r
    # 26 patches of a cube-like cage fit the unit sphere to 0.2 per mille of its diagonal; the
    # unfitted limit of the cube lies ~10 % of the radius off
    assert r["rms_limit_permille"] < 1, r
    assert_layers_equal(before, layers_snapshot(ms)[:2])


def test_filters_return_their_figures(tmp_path):
    # PyMeshLab 2022.02+ returns a dict per filter: the pipeline filters give their figures, which
    # must equal the layers' and report.json's.
    ms = pymeshlab.MeshSet()
    m = icosphere(4)
    V = m.vertex_matrix() * np.array([1.0, 0.6, 0.4])  # an ellipsoid: the Fitmaps vary
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=m.face_matrix()), "ellipsoid")
    f = ms.compute_scalar_by_fitmaps_per_vertex()
    assert f["vertices"] == ms.mesh(0).vertex_number()
    assert 0 < f["min_radius"] < f["max_radius"] and f["seconds"] >= 0
    q = ms.generate_fitmap_quad_simplification()
    control = ms.mesh(1).polygonal_face_list()
    assert q["patches"] == len(control) and 0 < q["patches"] < q["initial_patches"]
    assert q["count_patches"] > 0  # the equalized layout's count pass ran (docs/quad.md "Layout")
    assert 0 <= q["irregular_vertices"] <= ms.mesh(1).vertex_number()
    # the coverage guard's area trigger measured the kept cage: a closed cage leaves nothing
    # beyond its outline (docs/robustness.md "Flat and open shapes")
    assert q["cage_unprojectable_pct"] == 0 and q["coverage_relayouts"] == 0
    r = ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0, outputdir=str(tmp_path))
    rep = json.loads((tmp_path / "report.json").read_text())
    for k in ["patches", "irregular_vertices", "rms_limit_permille", "max_limit_permille",
              "rms_displaced_permille", "unprojectable_pct"]:
        assert r[k] == pytest.approx(rep[k], rel=1e-6, abs=1e-9), k
    assert r["warnings"] == len(rep["warnings"])


def test_regularity_weight_gives_fewer_irregular_vertices_at_a_budget():
    # the filter's "regularity" (QuadSimplifyParams::valenceWeight): at one budget the cage of an
    # ellipsoid has fewer irregular vertices with it than without (the same as run_pipeline.sh
    # --regularity; docs/quad.md "Regularity")
    irregular = []
    for w in (0.0, 1.0):
        ms = ellipsoid_meshset()
        q = ms.generate_fitmap_quad_simplification(targetpatches=150, regularity=w)
        assert abs(q["patches"] - 150) <= 3
        irregular.append(q["irregular_vertices"])
    assert irregular[1] < irregular[0], irregular


def test_swap_sweep_gives_fewer_irregular_vertices_at_the_same_count():
    # the filter's "swapSweep" (QuadSimplifyParams::swapSweepChain, default 0 = off): chains of swaps
    # after the last collapse cancel pairs of singularities without changing the patch count
    # (the same as run_pipeline.sh --swap-sweep; docs/quad.md "Swap sweep")
    # sweeptolerance=-1: the sweep unchecked; the default (2 %) fits both cages and undoes the
    # chains unless the swept one fits as closely: then it is one of the two cages above
    got = {}
    for chain in (0, 3):
        ms = ellipsoid_meshset()
        got[chain] = ms.generate_fitmap_quad_simplification(targetpatches=150, swapsweep=chain, sweeptolerance=-1)
    assert got[0]["sweep_chains"] == 0
    assert got[3]["sweep_chains"] > 0
    assert got[3]["patches"] == got[0]["patches"]
    assert got[3]["irregular_vertices"] < got[0]["irregular_vertices"], (got[0], got[3])
    guarded = ellipsoid_meshset().generate_fitmap_quad_simplification(targetpatches=150, swapsweep=3)
    assert guarded["sweep_chains"] + guarded["sweep_refused_chains"] == got[3]["sweep_chains"], guarded
    assert guarded["sweep_chains"] * guarded["sweep_refused_chains"] == 0
    same = got[3] if guarded["sweep_chains"] > 0 else got[0]
    assert guarded["irregular_vertices"] == same["irregular_vertices"]
    assert got[3]["sweep_swept_rms_permille"] == -1 and guarded["sweep_unswept_rms_permille"] > 0


@pytest.mark.parametrize("offset", [0.0, 1e4])
def test_swap_sweep_guard_measures_what_the_fit_reports(tmp_path, offset):
    # the guard measures each cage as the fit filter's report will (LayerRoundTrip): in this double
    # build the layer keeps the cage's doubles and the fit's reader rounds them to float, except
    # far from the origin (offset 1e4: float steps of 1e-3 on a 2.3-long ellipsoid), where it keeps
    # them; the kept cage's measure is then the report's, to the last bit (measured 2026-12-05: a
    # guard that always rounded to float, as MeshLab 2020.09's layer does, is 1.6e-5 off at 1e4;
    # one that kept the doubles without the reader's rounding, 1e-5 off at the origin)
    ms = ellipsoid_meshset(offset=offset)
    g = ms.generate_fitmap_quad_simplification(targetpatches=150, swapsweep=3)
    assert g["sweep_unswept_rms_permille"] > 0 and g["sweep_swept_rms_permille"] > 0, g
    fit = ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0, outputdir=str(tmp_path))
    kept = g["sweep_swept_rms_permille" if g["sweep_chains"] > 0 else "sweep_unswept_rms_permille"]
    assert fit["rms_limit_permille"] == pytest.approx(kept, rel=1e-12), (fit, g)


def test_dense_input_is_simplified_from_its_first_start():
    # the filter's "firstWorkingFaces" (vcgext::SimplifyFromWorkingStart; docs/multires.md "A coarser
    # first start"): an input above the working resolution (here 5 000 of its 20 480 triangles) is
    # simplified from its decimation to 1 280 triangles, and that cage kept when it reaches the
    # budget; 0 = from the working resolution, as before, for a cage of the same size
    got = {}
    for first in (0, 1280):
        ms = ellipsoid_meshset(5)
        got[first] = ms.generate_fitmap_quad_simplification(targetpatches=150, workingfaces=5000,
                                                            firstworkingfaces=first)
    assert got[0]["first_start_faces"] == 0 and got[0]["first_start_kept"] == 0
    assert abs(got[1280]["first_start_faces"] - 1280) <= 8
    assert got[1280]["first_start_kept"] == 1
    for q in got.values():
        assert abs(q["patches"] - 150) <= 3, q["patches"]


def test_budget_above_the_layers_quads_is_reached_from_its_refinement():
    # an icosphere of 320 triangles starts from its 1 280-triangle refinement (the 1 000-triangle
    # minimum), whose pairing gives 640 quads: a budget of 700 used to stop there; with a budget the
    # start is refined until it can reach it (2N + 2 triangles: 5 120), as in run_pipeline.sh
    ms = pymeshlab.MeshSet()
    m = icosphere(2)
    assert m.face_number() == 320
    ms.add_mesh(m, "sphere")
    q = ms.generate_fitmap_quad_simplification(targetpatches=700)
    assert 686 <= q["patches"] <= 700, q["patches"]
    assert ms.mesh(0).face_number() == 320  # the input layer is untouched


def test_renderer_grid_bakes_for_blender(tmp_path):
    # rendererGrid (issue 15, docs/blender.md) under its PyMeshLab spelling: the atlas says it was
    # baked for the renderer's level-L subdivision, and the displaced layer is that uniform grid
    # ((2^L + 1)^2 grid points per patch, shared ones counted once: V = P*4^L + 2 for a closed cage).
    ms = pymeshlab.MeshSet()
    m = icosphere(4)
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=m.vertex_matrix() * np.array([1.0, 0.6, 0.4]),
                               face_matrix=m.face_matrix()), "ellipsoid")
    ms.compute_scalar_by_fitmaps_per_vertex()
    ms.generate_fitmap_quad_simplification()
    r = ms.generate_catmull_clark_fit_and_displacement_bake(referencemesh=0, outputdir=str(tmp_path),
                                                            renderergrid=True)
    atlas = json.loads((tmp_path / "displacement.json").read_text())
    assert atlas["baked_for"] == "renderer"
    L = atlas["subdivision_level"]
    assert 2 ** L + 1 == max(t[2] for t in atlas["tiles"])
    displaced = ms.mesh(ms.mesh_number() - 1)
    assert displaced.vertex_number() == r["patches"] * 4 ** L + 2
