"""Every .mlx in meshlab_scripts/ through MeshSet.load_filter_script + apply_filter_script, unchanged
(the same files meshlabserver 2020.09 runs; PyMeshLab reads their camelCase parameter names)."""
import json

import numpy as np
import pymeshlab
import pytest

from conftest import SCRIPTS, icosphere


def run(ms, script):
    ms.load_filter_script(str(SCRIPTS / script))
    ms.apply_filter_script()


def check_fitmaps(ms, tmp_path):
    ms.add_mesh(icosphere(3), "sphere")
    run(ms, "fitmaps.mlx")
    s = ms.current_mesh().vertex_scalar_array()
    assert np.all(np.isfinite(s)) and s.min() > 0


def check_quad(ms, tmp_path):
    ms.add_mesh(icosphere(4), "sphere")
    run(ms, "quad_simplification.mlx")
    assert ms.mesh_number() == 2
    assert all(len(f) == 4 for f in ms.current_mesh().polygonal_face_list())


def check_fit_and_bake(ms, tmp_path):
    ms.add_mesh(icosphere(4), "sphere")
    ms.generate_fitmap_quad_simplification()
    run(ms, "fit_and_bake.mlx")  # outputDir "": <TMPDIR>/fitmap_cc for a layer without a file
    assert ms.mesh_number() == 5
    rep = json.loads((tmp_path / "fitmap_cc" / "report.json").read_text())
    assert rep["patches"] == len(ms.mesh(1).polygonal_face_list())


def check_pipeline(ms, tmp_path):
    ms.add_mesh(icosphere(4), "sphere")
    run(ms, "pipeline.mlx")
    assert ms.mesh_number() == 5 and ms.mesh(0).has_vertex_scalar()
    assert (tmp_path / "fitmap_cc" / "report.json").exists()


def check_loop_refine(ms, tmp_path):
    ms.add_mesh(icosphere(1), "net")
    run(ms, "loop_refine.mlx")
    assert ms.mesh_number() == 2 and ms.current_mesh().face_number() >= 99000


def check_loop_snap(ms, tmp_path):
    ms.add_mesh(icosphere(1), "net")
    ms.add_mesh(icosphere(2, radius=1.5), "points")
    run(ms, "loop_snap.mlx")
    r = np.linalg.norm(ms.current_mesh().vertex_matrix(), axis=1)
    assert r.max() < 1.0 and r.min() > 0.85  # onto the limit surface of the net (inside the unit sphere)


def check_loop_curvature(ms, tmp_path):
    ms.add_mesh(icosphere(3), "sphere")
    run(ms, "loop_curvature.mlx")
    h = ms.current_mesh().vertex_scalar_array()
    assert h.min() > 0.8 and h.max() < 1.3


CHECKS = {
    "fitmaps.mlx": check_fitmaps,
    "quad_simplification.mlx": check_quad,
    "fit_and_bake.mlx": check_fit_and_bake,
    "pipeline.mlx": check_pipeline,
    "loop_refine.mlx": check_loop_refine,
    "loop_snap.mlx": check_loop_snap,
    "loop_curvature.mlx": check_loop_curvature,
}


def test_every_script_is_covered():
    assert sorted(p.name for p in SCRIPTS.glob("*.mlx")) == sorted(CHECKS)


@pytest.mark.parametrize("script", sorted(CHECKS))
def test_script_runs_unchanged(script, tmp_path, monkeypatch):
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    ms = pymeshlab.MeshSet()
    CHECKS[script](ms, tmp_path)
