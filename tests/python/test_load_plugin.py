"""pymeshlab.load_plugin(PATH) for users with their own PyMeshLab: a PyMeshLab without our plugin in
its plugins/ folder (a symlink copy of the venv's package minus the plugin) loads build-2025's file."""
import os
import subprocess
import sys

import pymeshlab

from conftest import REPO

CODE = r'''
import sys, numpy as np, pymeshlab
assert pymeshlab.__file__.startswith(sys.argv[1]), pymeshlab.__file__
assert "compute_scalar_by_loop_surrogate_curvature_per_vertex" not in pymeshlab.filter_list()
pymeshlab.load_plugin(sys.argv[2])
ms = pymeshlab.MeshSet()
ms.create_sphere(radius=2.0, subdiv=3)
ms.apply_filter("compute_scalar_by_loop_surrogate_curvature_per_vertex", curvaturekind=0, creaseangle=0)
h = ms.current_mesh().vertex_scalar_array()
assert abs(np.median(h) - 0.5) < 0.02, np.median(h)
try:
    ms.apply_filter("compute_scalar_by_fitmaps_per_vertex", tau=-1)
    raise SystemExit("no exception")
except pymeshlab.PyMeshLabException as e:
    assert str(e).endswith("Details: tau must be in [0, 100] percent"), str(e)
print("OK")
'''


def test_load_plugin_by_path(tmp_path):
    src = os.path.dirname(pymeshlab.__file__)
    dst = tmp_path / "pymeshlab"
    (dst / "lib" / "plugins").mkdir(parents=True)
    for name in os.listdir(src):
        if name != "lib":
            os.symlink(os.path.join(src, name), dst / name)
    for name in os.listdir(os.path.join(src, "lib")):
        if name != "plugins":
            os.symlink(os.path.join(src, "lib", name), dst / "lib" / name)
    for name in os.listdir(os.path.join(src, "lib", "plugins")):
        if name != "libfilter_fitmap_quad.so":
            os.symlink(os.path.join(src, "lib", "plugins", name), dst / "lib" / "plugins" / name)
    plugin = REPO / "build-2025" / "libfilter_fitmap_quad.so"
    assert plugin.exists(), "run scripts/setup_pymeshlab.sh"
    r = subprocess.run([sys.executable, "-c", CODE, str(tmp_path), str(plugin)], capture_output=True, text=True,
                       env=dict(os.environ, PYTHONPATH=str(tmp_path)), timeout=300)
    assert r.returncode == 0 and r.stdout.strip().endswith("OK"), r.stdout[-2000:] + r.stderr[-2000:]
