"""The README's PyMeshLab example, run exactly as printed (from a folder that looks like the repo root)."""
import os
import re
import subprocess
import sys

from conftest import DATA, REPO


def test_readme_example_runs(tmp_path):
    readme = (REPO / "README.md").read_text()
    m = re.search(r"<!-- pymeshlab-example -->\n```python\n(.*?)```", readme, re.S)
    assert m, "README.md: no <!-- pymeshlab-example --> code block"
    (tmp_path / "example.py").write_text(m.group(1))
    (tmp_path / ".deps" / "data").mkdir(parents=True)
    (tmp_path / ".deps" / "data" / "meshes").symlink_to(DATA)
    r = subprocess.run([sys.executable, "example.py"], cwd=tmp_path, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout + r.stderr
    layers, patches = re.search(r"^(\d+) layers, (\d+) patches$", r.stdout, re.M).groups()
    assert int(layers) == 5 and 300 <= int(patches) <= 500
    out = tmp_path / "out_py"
    for f in ["report.json", "displacement.png", "control.obj", "fitted.obj"]:
        assert (out / f).stat().st_size > 0, f
    assert os.path.exists(out / "fitted.obj.mtl")
