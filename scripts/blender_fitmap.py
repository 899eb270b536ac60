"""Build the fitted Catmull-Clark surface with its displacement in Blender, from a pipeline output.

    blender -b --python scripts/blender_fitmap.py -- OUTDIR [--level N] [--save FILE.blend]
            [--render FILE.png] [--samples N] [--resolution W] [--up z|y] [--measure] [--reference MESH]

OUTDIR is what `meshlab_scripts/run_pipeline.sh` (or the fit filter's `outputDir`) wrote:
control.obj, displacement.png, displacement.json, and fitmap.ply (the scan). The script makes the
object a user would otherwise set up by hand:

- the cage imported with Blender's axes matching the file's (forward Y, up Z: coordinates kept);
- a Subdivision Surface modifier: Catmull-Clark, "Use Limit Surface", UV smooth "None", boundary
  "All" (the fit's OpenSubdiv options: VTX_BOUNDARY_EDGE_ONLY, linear face-varying data), at the
  level the atlas was baked for (run_pipeline.sh --blender) or else the one with one vertex per
  texel of the largest tiles (`--level` overrides);
- a Displace modifier reading the atlas: image texture, Non-Color, bilinear (interpolation on,
  box filter of one texel, no mipmaps), UV coordinates, along the normal, with strength and
  midlevel from displacement.json (value = offset + scale * q16: strength = 65535 * scale,
  midlevel = -offset / strength);
- a material (the object-space normal map when the bake wrote one).

--measure writes OUTDIR/blender_report.json: the RMS distance from the scan's vertices to the
surface Blender evaluates, limit only and displaced, in 1/1000 of the scan's bounding-box
diagonal (as report.json), beside report.json's own figures; and the seam checks (open edges of
the evaluated surface against the cage's, and the largest difference between the displacements
one vertex reads through the UVs of its different faces). --render draws the displaced surface
beside the cage with Cycles on the CPU. From Blender's UI: Scripting > Open > Run Script, with
OUTDIR set in FITMAP_OUTDIR (the environment) or typed into OUTDIR below.
"""
import json
import math
import os
import struct
import sys

import bpy
from mathutils import Vector
from mathutils.bvhtree import BVHTree

OUTDIR = ""  # for a run from Blender's UI without arguments


def parse_args(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    opt = {"outdir": os.environ.get("FITMAP_OUTDIR", OUTDIR), "level": 0, "save": "", "render": "",
           "measure": False, "reference": "", "samples": 32, "resolution": 1200, "up": "z"}
    i = 0
    while i < len(args):
        a = args[i]
        if a in ("--level", "--samples", "--resolution"):
            opt[a[2:]] = int(args[i + 1])
            i += 2
        elif a in ("--save", "--render", "--reference", "--up"):
            opt[a[2:]] = args[i + 1]
            i += 2
        elif a == "--measure":
            opt["measure"] = True
            i += 1
        elif a.startswith("--"):
            raise SystemExit("blender_fitmap.py: unknown option " + a)
        else:
            opt["outdir"] = a
            i += 1
    if opt["up"] not in ("z", "y"):
        raise SystemExit("blender_fitmap.py: --up takes z (Blender's) or y (most scans')")
    if not opt["outdir"]:
        raise SystemExit("blender_fitmap.py: give the pipeline's output folder: blender -b --python "
                         "scripts/blender_fitmap.py -- OUTDIR")
    return opt


def level_for(atlas):
    """The level the atlas was baked for (displacement.json "subdivision_level", run_pipeline.sh
    --blender), else the one with one vertex per texel along the largest tiles' sides (tiles are
    2^k + 1 texels wide: level k), between 1 and 6."""
    if atlas.get("subdivision_level", 0) > 0:
        return atlas["subdivision_level"]
    sizes = [t[2] for t in atlas["tiles"]] if atlas.get("tiles") else [atlas.get("tile", 9)]
    return max(1, min(6, round(math.log2(max(max(sizes) - 1, 1)))))


def import_cage(path):
    before = set(bpy.data.objects)
    bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
    new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    if len(new) != 1:
        raise SystemExit("blender_fitmap.py: %s did not import as one mesh object" % path)
    obj = new[0]
    obj.name = "fitmap cage"
    return obj


def add_subdivision(obj, level):
    m = obj.modifiers.new("Catmull-Clark limit", "SUBSURF")
    m.subdivision_type = "CATMULL_CLARK"
    m.levels = level
    m.render_levels = level
    m.use_limit_surface = True
    m.quality = 6  # adaptive isolation depth of the limit evaluation near extraordinary vertices
    m.uv_smooth = "NONE"
    m.boundary_smooth = "ALL"
    m.use_creases = False
    return m


def add_displacement(obj, outdir, atlas):
    img = bpy.data.images.load(os.path.join(outdir, atlas["image"]), check_existing=True)
    img.colorspace_settings.name = "Non-Color"
    tex = bpy.data.textures.new("fitmap displacement", "IMAGE")
    tex.image = img
    tex.use_interpolation = True
    tex.use_mipmap = False
    tex.filter_type = "BOX"
    tex.filter_size = 1.0
    tex.extension = "EXTEND"
    m = obj.modifiers.new("Displacement atlas", "DISPLACE")
    m.texture = tex
    m.texture_coords = "UV"
    m.uv_layer = obj.data.uv_layers[0].name
    m.direction = "NORMAL"
    m.space = "LOCAL"
    strength = 65535.0 * atlas["scale"]
    m.strength = strength
    m.mid_level = -atlas["offset"] / strength if strength != 0 else 0.0
    return m


def add_material(obj, outdir, atlas):
    mat = bpy.data.materials.new("fitmap surface")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.75, 0.72, 0.66, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.55
    if atlas.get("normal_image"):
        nt = mat.node_tree
        img = bpy.data.images.load(os.path.join(outdir, atlas["normal_image"]), check_existing=True)
        img.colorspace_settings.name = "Non-Color"
        tn = nt.nodes.new("ShaderNodeTexImage")
        tn.image = img
        tn.interpolation = "Linear"
        nm = nt.nodes.new("ShaderNodeNormalMap")
        nm.space = "OBJECT"
        nt.links.new(tn.outputs["Color"], nm.inputs["Color"])
        nt.links.new(nm.outputs["Normal"], bsdf.inputs["Normal"])
        print("blender_fitmap.py: object-space normal map %s in the material" % atlas["normal_image"])
    obj.data.materials.append(mat)


# --- reference mesh (vertices only) ---------------------------------------------------------

_PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
              "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
              "float": "f", "float32": "f", "double": "d", "float64": "d"}


def read_ply_vertices(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise SystemExit("%s: not a PLY file" % path)
        fmt, nv, props, in_vertex = None, 0, [], False
        while True:
            line = f.readline()
            if not line:
                raise SystemExit("%s: truncated header" % path)
            w = line.decode("ascii", "replace").split()
            if not w:
                continue
            if w[0] == "format":
                fmt = w[1]
            elif w[0] == "element":
                in_vertex = w[1] == "vertex"
                if in_vertex:
                    nv = int(w[2])
            elif w[0] == "property" and in_vertex:
                if w[1] == "list":
                    raise SystemExit("%s: list property on vertices" % path)
                props.append((w[2], w[1]))
            elif w[0] == "end_header":
                break
        names = [p[0] for p in props]
        ix, iy, iz = names.index("x"), names.index("y"), names.index("z")
        if fmt == "ascii":
            verts = []
            for _ in range(nv):
                v = f.readline().split()
                verts.append(Vector((float(v[ix]), float(v[iy]), float(v[iz]))))
            return verts
        end = "<" if fmt == "binary_little_endian" else ">"
        st = struct.Struct(end + "".join(_PLY_TYPES[p[1]] for p in props))
        data = f.read(st.size * nv)
        return [Vector((r[ix], r[iy], r[iz])) for r in st.iter_unpack(data[:st.size * nv])]


def read_off_vertices(path):
    with open(path) as f:
        words = []
        for line in f:
            line = line.split("#")[0]
            words.extend(line.split())
            if len(words) >= 4:
                break
        if words[0].upper().endswith("OFF"):
            words = words[1:]
        nv = int(words[0])
        rest = words[3:]
        verts = []
        while len(verts) < nv:
            while len(rest) < 3:
                rest.extend(f.readline().split("#")[0].split())
            verts.append(Vector((float(rest[0]), float(rest[1]), float(rest[2]))))
            rest = rest[3:]
        return verts


def read_obj_vertices(path):
    verts = []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                w = line.split()
                verts.append(Vector((float(w[1]), float(w[2]), float(w[3]))))
    return verts


def read_vertices(path):
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ply":
        return read_ply_vertices(path)
    if ext == ".off":
        return read_off_vertices(path)
    if ext == ".obj":
        return read_obj_vertices(path)
    raise SystemExit("blender_fitmap.py: reference %s: PLY, OFF or OBJ expected" % path)


# --- measurements ---------------------------------------------------------------------------

def evaluated_mesh(obj):
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    ev = obj.evaluated_get(dg)
    return ev, ev.to_mesh()


def rms_to_surface(points, obj):
    """RMS and max of the distances from points to obj's evaluated surface (local coordinates)."""
    dg = bpy.context.evaluated_depsgraph_get()
    bvh = BVHTree.FromObject(obj, dg)
    s, mx = 0.0, 0.0
    for p in points:
        hit = bvh.find_nearest(p)
        d = hit[3] if hit[0] is not None else float("inf")
        s += d * d
        mx = max(mx, d)
    return math.sqrt(s / max(len(points), 1)), mx


def open_edges(mesh):
    count = {}
    for poly in mesh.polygons:
        vs = poly.vertices
        for k in range(len(vs)):
            e = (min(vs[k], vs[k - 1]), max(vs[k], vs[k - 1]))
            count[e] = count.get(e, 0) + 1
    return sum(1 for c in count.values() if c == 1)


def seam_gap(obj, atlas, image):
    """Largest difference (mesh units) between the displacements one vertex of the subdivided
    surface reads through the UVs of its different faces (0 = the atlas has no seams)."""
    w, h = image.size
    px = list(image.pixels)
    scale = atlas["scale"] * 65535.0

    def value(u, v):  # bilinear between texel centres, as the texture system reads it
        x, y = u * w - 0.5, v * h - 0.5
        x0, y0 = max(0, min(w - 1, math.floor(x))), max(0, min(h - 1, math.floor(y)))
        x1, y1 = min(w - 1, x0 + 1), min(h - 1, y0 + 1)
        fx, fy = min(max(x - x0, 0.0), 1.0), min(max(y - y0, 0.0), 1.0)

        def t(i, j):
            return px[4 * (j * w + i)]
        return ((1 - fy) * ((1 - fx) * t(x0, y0) + fx * t(x1, y0)) +
                fy * ((1 - fx) * t(x0, y1) + fx * t(x1, y1)))

    ev, mesh = evaluated_mesh(obj)
    uv = mesh.uv_layers.active.data
    seen = {}
    gap = 0.0
    for loop in mesh.loops:
        d = value(uv[loop.index].uv[0], uv[loop.index].uv[1]) * scale
        v = loop.vertex_index
        if v in seen:
            lo, hi = seen[v]
            lo, hi = min(lo, d), max(hi, d)
            seen[v] = (lo, hi)
            gap = max(gap, hi - lo)
        else:
            seen[v] = (d, d)
    ev.to_mesh_clear()
    return gap


def measure(obj, sub, disp, opt, atlas, image):
    ref_path = opt["reference"] or os.path.join(opt["outdir"], "fitmap.ply")
    if not os.path.exists(ref_path):
        raise SystemExit("blender_fitmap.py: --measure needs the scan: %s is missing (give --reference)" % ref_path)
    pts = read_vertices(ref_path)
    lo = Vector([min(p[i] for p in pts) for i in range(3)])
    hi = Vector([max(p[i] for p in pts) for i in range(3)])
    pm = 1000.0 / (hi - lo).length
    disp.show_viewport = False
    rl, ml = rms_to_surface(pts, obj)
    ev, mesh = evaluated_mesh(obj)
    open_limit = open_edges(mesh)
    ev.to_mesh_clear()
    disp.show_viewport = True
    rd, md = rms_to_surface(pts, obj)
    ev, mesh = evaluated_mesh(obj)
    open_displaced = open_edges(mesh)
    nverts = len(mesh.vertices)
    ev.to_mesh_clear()
    cage_open = open_edges(obj.data)
    rep = {}
    rp = os.path.join(opt["outdir"], "report.json")
    if os.path.exists(rp):
        with open(rp) as f:
            rep = json.load(f)
    out = {
        "blender_version": bpy.app.version_string,
        "reference": os.path.abspath(ref_path),
        "reference_vertices": len(pts),
        "bbox_diagonal": (hi - lo).length,
        "quantization_step_permille": atlas["scale"] * pm,
        "baked_for": atlas.get("baked_for", "limit"),
        "level": sub.levels,
        "evaluated_vertices": nverts,
        "rms_limit_blender_permille": rl * pm,
        "max_limit_blender_permille": ml * pm,
        "rms_displaced_blender_permille": rd * pm,
        "max_displaced_blender_permille": md * pm,
        "rms_limit_permille": rep.get("rms_limit_permille"),
        "rms_displaced_permille": rep.get("rms_displaced_permille"),
        "cage_open_edges": cage_open,
        "limit_open_edges": open_limit,
        "displaced_open_edges": open_displaced,
        "open_edges_per_cage_edge": 2 ** sub.levels,
        "seam_gap_permille": seam_gap(obj, atlas, image) * pm,
    }
    path = os.path.join(opt["outdir"], "blender_report.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=2)
    print("blender_fitmap.py: limit RMS %.4f permille (report %s), displaced RMS %.4f permille (report %s), "
          "level %d, open edges %d (cage %d), seam gap %.2g permille -> %s"
          % (out["rms_limit_blender_permille"], out["rms_limit_permille"], out["rms_displaced_blender_permille"],
             out["rms_displaced_permille"], sub.levels, open_displaced, cage_open, out["seam_gap_permille"], path))


# --- picture --------------------------------------------------------------------------------

def render(obj, opt):
    """The displaced surface (left) beside the cage (right, flat with its edges), Cycles CPU."""
    scene = bpy.context.scene
    cage = obj.copy()
    cage.data = obj.data.copy()
    cage.modifiers.clear()
    cage.name = "fitmap cage (control mesh)"
    bpy.context.collection.objects.link(cage)
    lo = Vector([min(v.co[i] for v in obj.data.vertices) for i in range(3)])
    hi = Vector([max(v.co[i] for v in obj.data.vertices) for i in range(3)])
    size = hi - lo
    cage.location.x += size.x * 1.15
    wire = cage.copy()
    wire.data = cage.data
    wire.name = "fitmap cage edges"
    bpy.context.collection.objects.link(wire)
    wm = wire.modifiers.new("edges", "WIREFRAME")
    wm.thickness = size.length * 0.002
    dark = bpy.data.materials.new("edges")
    dark.use_nodes = True
    dark.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.05, 0.05, 0.08, 1)
    wire.data = cage.data.copy()
    wire.data.materials.clear()
    wire.data.materials.append(dark)
    # the camera looks at the model's front: along +Y with Z up, or (--up y) along -Z with Y up
    up = 2 if opt["up"] == "z" else 1
    centre = (lo + hi) / 2 + Vector((size.x * 0.575, 0, 0))
    extent = max(size.x * 2.15, size[up] * 2.0)
    cam_data = bpy.data.cameras.new("camera")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = extent * 1.05
    cam_data.clip_end = size.length * 10
    cam = bpy.data.objects.new("camera", cam_data)
    bpy.context.collection.objects.link(cam)
    if up == 2:
        cam.location = centre + Vector((0, -size.length * 3, 0))
        cam.rotation_euler = (math.pi / 2, 0, 0)
    else:
        cam.location = centre + Vector((0, 0, size.length * 3))
        cam.rotation_euler = (0, 0, 0)
    scene.camera = cam
    sun = bpy.data.lights.new("sun", "SUN")
    sun.energy = 3.0
    sun_obj = bpy.data.objects.new("sun", sun)
    sun_obj.rotation_euler = ((math.radians(50), math.radians(-20), math.radians(-30)) if up == 2 else
                              (math.radians(-30), math.radians(-35), 0))
    bpy.context.collection.objects.link(sun_obj)
    world = scene.world or bpy.data.worlds.new("world")
    scene.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.9, 0.9, 0.92, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = opt["samples"]
    scene.cycles.use_denoising = False  # Debian's Blender is built without OpenImageDenoise
    W = opt["resolution"]
    scene.render.resolution_x = W
    scene.render.resolution_y = max(W // 4, min(W, int(W * size[up] * 1.1 / extent) if extent > 0 else W // 2))
    scene.render.filepath = os.path.abspath(opt["render"])
    scene.render.image_settings.file_format = "PNG"
    bpy.ops.render.render(write_still=True)
    print("blender_fitmap.py: rendered %s" % scene.render.filepath)


def main():
    opt = parse_args(sys.argv)
    outdir = opt["outdir"]
    for f in ("control.obj", "displacement.json"):
        if not os.path.exists(os.path.join(outdir, f)):
            raise SystemExit("blender_fitmap.py: %s has no %s: give the folder run_pipeline.sh wrote" % (outdir, f))
    with open(os.path.join(outdir, "displacement.json")) as f:
        atlas = json.load(f)
    # headless: an empty scene (the startup file's cube, camera and light removed); from the UI the
    # user's scene is kept and the object is added to it
    if bpy.app.background:
        for o in list(bpy.data.objects):
            bpy.data.objects.remove(o, do_unlink=True)
    obj = import_cage(os.path.join(outdir, "control.obj"))
    level = opt["level"] or level_for(atlas)
    if atlas.get("baked_for") == "renderer" and level != atlas.get("subdivision_level"):
        print("blender_fitmap.py: warning: the atlas was baked for level %d; at level %d Blender rebuilds "
              "another surface" % (atlas["subdivision_level"], level))
    elif atlas.get("baked_for", "limit") != "renderer":
        print("blender_fitmap.py: note: the atlas was baked for the per-tile limit surface, not for Blender's "
              "uniform subdivision: expect a larger displaced error than reported (run_pipeline.sh --blender "
              "bakes for Blender; docs/blender.md)")
    sub = add_subdivision(obj, level)
    disp = add_displacement(obj, outdir, atlas)
    add_material(obj, outdir, atlas)
    print("blender_fitmap.py: %s: %d quads, subdivision level %d, displacement strength %.6g midlevel %.6f"
          % (outdir, len(obj.data.polygons), level, disp.strength, disp.mid_level))
    if opt["measure"]:
        measure(obj, sub, disp, opt, atlas, disp.texture.image)
    if opt["save"]:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(opt["save"]))
        print("blender_fitmap.py: saved %s" % opt["save"])
    if opt["render"]:
        render(obj, opt)


if __name__ == "__main__":
    main()
