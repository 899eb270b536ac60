"""Blender (Debian 12's 3.4) rebuilds the pipeline's output as report.json measures it (issue 15):
scripts/blender_fitmap.py run headless on run_pipeline.sh's output of bunny00.
Run: .venv/bin/python -m pytest tests/blender (ctest does, as Blender.pytest)."""
import json
import os
import pathlib
import shutil
import struct
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("FITMAP_DATA_DIR", REPO / ".deps" / "data" / "meshes"))
SCRIPT = REPO / "scripts" / "blender_fitmap.py"
BLENDER = shutil.which("blender")


def blender(outdir, *args, check=True):
    assert BLENDER, "blender is not installed (scripts/setup_blender.sh installs Debian's)"
    p = subprocess.run([BLENDER, "-b", "--factory-startup", "--python", str(SCRIPT), "--", str(outdir), *args],
                       capture_output=True, text=True, timeout=900)
    if check:
        assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    return p


def pipeline(outdir, *args, mesh="bunny00.off"):
    env = dict(os.environ, FITMAP_SKIP_SETUP="1")
    p = subprocess.run([str(REPO / "meshlab_scripts" / "run_pipeline.sh"), *args, str(DATA / mesh),
                        str(outdir)], capture_output=True, text=True, env=env, timeout=900)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    with open(outdir / "report.json") as f:
        return json.load(f)


@pytest.fixture(scope="module")
def bunny(tmp_path_factory):
    """The pipeline's output on bunny00 baked for Blender (--blender) and Blender's measurement."""
    out = tmp_path_factory.mktemp("bunny_blender")
    report = pipeline(out, "--blender")
    blender(out, "--measure", "--save", str(out / "fitmap.blend"))
    with open(out / "blender_report.json") as f:
        return out, report, json.load(f)


def test_blender_rebuilds_the_reported_surface(bunny):
    out, report, b = bunny
    with open(out / "displacement.json") as f:
        atlas = json.load(f)
    # baked for the renderer's grid, at the level the script picks
    assert atlas["baked_for"] == "renderer"
    assert b["level"] == atlas["subdivision_level"] >= 1
    # the cage: Blender's limit surface (level L, vertices on the limit) is the report's within 1 %
    assert b["rms_limit_blender_permille"] == pytest.approx(report["rms_limit_permille"], rel=0.01)
    # the displaced surface within 25 % (measured 2026-12-02: +9 %; the rest is Blender's
    # vertex-only sampling and float texture read)
    assert b["rms_displaced_blender_permille"] == pytest.approx(report["rms_displaced_permille"], rel=0.25)
    # watertight where the cage is: each open cage edge becomes 2^L open edges, nothing else opens
    assert b["displaced_open_edges"] == b["cage_open_edges"] * 2 ** b["level"]
    assert b["limit_open_edges"] == b["displaced_open_edges"]
    # no seam: the displacements one vertex reads through its faces' UVs agree within two 16-bit
    # steps (the finer tile's interpolated edge texels are rounded on their own)
    assert 0 <= b["seam_gap_permille"] <= 2 * b["quantization_step_permille"]
    assert b["reference_vertices"] == report["reference_vertices"]
    assert (out / "fitmap.blend").stat().st_size > 10000


def test_the_default_atlas_reads_worse_in_blender(bunny, tmp_path):
    """docs/blender.md: the default bake (per-tile surface, limit normal), rebuilt by Blender's
    uniform subdivision, is further from the scan than the bake for Blender, and the script says so."""
    _, report, b = bunny
    limit_report = pipeline(tmp_path)
    p = blender(tmp_path, "--measure")
    assert "not for Blender's uniform subdivision" in p.stdout
    with open(tmp_path / "blender_report.json") as f:
        bl = json.load(f)
    assert bl["baked_for"] == "limit"
    assert limit_report["patches"] == report["patches"]  # same cage: only the bake differs
    assert bl["rms_limit_blender_permille"] == pytest.approx(b["rms_limit_blender_permille"], rel=1e-6)
    assert bl["rms_displaced_blender_permille"] > 1.2 * b["rms_displaced_blender_permille"]


def test_another_scan_with_its_normal_map(tmp_path):
    """elephant (another scan, 499 patches) with the normal map: the material uses it, and
    Blender's figures agree with the report as on bunny00."""
    report = pipeline(tmp_path, "--blender", "--normal-map", mesh="elephant.off")
    p = blender(tmp_path, "--measure")
    assert "object-space normal map normal.png" in p.stdout
    with open(tmp_path / "blender_report.json") as f:
        b = json.load(f)
    # limit: the report tessellates small meshes coarser than Blender's level 4 (docs/blender.md:
    # it overstates by 2.5 % here), never lower
    assert report["rms_limit_permille"] * 0.96 <= b["rms_limit_blender_permille"] <= report["rms_limit_permille"] * 1.001
    assert b["rms_displaced_blender_permille"] == pytest.approx(report["rms_displaced_permille"], rel=0.25)
    assert b["displaced_open_edges"] == b["cage_open_edges"] * 2 ** b["level"]


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


def test_cycles_renders_the_displaced_surface_beside_the_cage(bunny, tmp_path):
    out, _, _ = bunny
    png = tmp_path / "render.png"
    p = blender(out, "--render", str(png), "--resolution", "240", "--samples", "2")
    assert "rendered" in p.stdout
    w, h = png_size(png)
    assert w == 240 and 60 <= h <= 240
    assert png.stat().st_size > 5000  # not a blank frame (a flat image compresses to ~1 kB)


def test_a_folder_without_outputs_is_a_clear_error(tmp_path):
    p = blender(tmp_path, check=False)
    assert p.returncode != 0
    assert "has no control.obj" in p.stdout + p.stderr
