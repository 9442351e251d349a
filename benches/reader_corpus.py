"""Every reader of Pappus on a corpus of awkward files, each judged against independent readers.

    ~/.cache/pappus/peers-venv/bin/python benches/reader_corpus.py [--out DIR] [--pappus PATH]
        [--only TEXT] [--no-blender] [--no-assimp]

Needs the peers in a venv (the script re-runs itself with that venv's Python when the one it was
started with lacks trimesh):

    python3 -m venv ~/.cache/pappus/peers-venv
    ~/.cache/pappus/peers-venv/bin/pip install trimesh pymeshlab pycollada numpy scipy lxml \
        networkx pillow DracoPy

and, optionally, Debian's `blender` (3.4) and `assimp-utils` on PATH (`apt-get install blender
python3-numpy assimp-utils`): Blender both exports files and reads them back, assimp reads them;
without them their files and columns are left out, and said so. PAPPUS is the binary (default
`${CARGO_TARGET_DIR:-~/.cache/pappus/target}/release/pappus`, else `debug/pappus`, else the
same under `~/.cache/pappus/target` and `target/`); without one
the script still builds the corpus and prints what the peers read. Nothing is downloaded: every
file is made here, in DIR (default a temporary folder, kept), by:

- trimesh's exporters (OBJ, PLY ASCII and binary, STL ASCII and binary, OFF, GLB, glTF embedded
  and with a `.bin`, GLB with Draco, DAE) of procedural shapes (icosphere, box, annulus,
  cylinder, a mesh with vertex colours, a grid with UVs);
- pymeshlab's savers (OBJ, PLY, STL, OFF; binary and ASCII; with and without colours, normals,
  quality) of a sphere, a torus, a cube and an annulus;
- Blender's exporters, run headless on this same file (OBJ with and without normals and UVs,
  with groups, triangulated; PLY; STL; `.glb`, `.gltf` embedded and separate, Draco where the
  exporter has its library; COLLADA with polygons and triangulated) of Suzanne, a UV sphere
  with colours, a cube with an octagon and four pentagons, a torus, a parent and child with
  their transforms, and linked duplicates sharing one mesh;
- this script, by hand: files that rebuild the Khronos glTF samples' shapes (a sparse accessor,
  interleaved views, u8 and u16 indices, strips and fans, a node tree of matrices and TRS,
  several primitives, normalised u8 texture coordinates, POSITION without min/max,
  KHR_materials_pbrSpecularGlossiness required, KHR_mesh_quantization, a glTF 1.0 file, Draco
  required and Draco with an uncompressed fallback, a `.bin` whose name needs percent-encoding),
  COLLADA (polylist, triangles, polygons, Z-up, instance_node, decimal commas), PLY (a `Created
  by` header line, uchar and float colours, `vertex_index`, big-endian doubles, tristrips, a
  point cloud), OBJ (negative indices, `\\` continuations, `3.1+e2`, a keyhole polygon, mixed
  corner forms), STL (binary with a `solid` header, two ASCII solids, CRLF) and OFF (COFF,
  comments, counts on the keyword's line).

For each file it runs `PAPPUS info --json FILE` and the peers: trimesh (`force="mesh"`,
`process=False`), pycollada for `.dae`, assimp (`assimp info`, triangulating) and Blender's
importers. The reference is what the writer wrote (its own triangle and vertex counts and
bounding box) where the maker knows it, else the first peer that read the file (pycollada for
`.dae`, trimesh otherwise). Pappus's triangles are the sum of (n − 2) over its faces, its
vertices those it built less the ones a repair added (glTF and STL weld by position, so their
reference is the distinct positions). Each file is then:

- `opened`: Pappus's triangles, vertices and bounding-box diagonal are the reference's;
- `refused-by-name`: Pappus refused with a message naming the file and the cause, and the
  variant is one Pappus documents it does not read, or no peer could read the file either, or
  it has no surface;
- `mismatch`: anything else (both sides printed: counts, repairs, messages).

It prints one line per file: Pappus's and the writer's counts, then each peer's triangles,
marked `!` where its triangles or bounding box differ from the reference (`✗`: it could not
read the file), `*` where that is a known limit of the peer, whose reason is printed below the
line; for a refusal or a mismatch, Pappus's message and repairs and each peer's reading. Then a
table by format and the summary line `opened N, refused by name N, mismatched N`. It exits 0: a
report, not a test. With Blender and assimp, 220 files in about 20 s on two cores (the peers
most of it; Pappus's debug build reads all of them in 3 s).
"""

import base64
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PEERS_VENV = os.path.expanduser("~/.cache/pappus/peers-venv")
TARGETS = [os.environ.get("CARGO_TARGET_DIR") or os.path.expanduser("~/.cache/pappus/target"),
           os.path.expanduser("~/.cache/pappus/target"), os.path.join(ROOT, "target")]
PAPPUS_TIMEOUT_S = 300
PEER_TIMEOUT_S = 120


# ---------------------------------------------------------------------------------------------
# The Blender side: this file, run by Blender (`blender -b --python THIS -- --blender-...`).
# ---------------------------------------------------------------------------------------------

def blender_main(argv):
    """Inside Blender: `--blender-export DIR` writes Blender's files of each shape and
    DIR/manifest.json (what each holds, by Blender's count); `--blender-import LIST OUT` imports
    each file of LIST (one a line) into an empty scene and appends its counts to OUT as JSON
    lines."""
    import bpy
    import numpy

    # Debian's Blender 3.4 glTF add-on still says `np.bool`, which NumPy 1.24 removed.
    if not hasattr(numpy, "bool"):
        numpy.bool = bool

    def mesh_counts():
        """Triangles (n − 2 per polygon), vertices, and the world bounding-box diagonal of the
        scene's mesh objects."""
        triangles = vertices = 0
        corners = []
        for obj in bpy.context.scene.objects:
            if obj.type != "MESH":
                continue
            mesh = obj.data
            triangles += sum(len(p.vertices) - 2 for p in mesh.polygons)
            vertices += len(mesh.vertices)
            corners += [obj.matrix_world @ v.co for v in mesh.vertices]
        if not corners:
            return triangles, vertices, 0.0
        low = [min(c[i] for c in corners) for i in range(3)]
        high = [max(c[i] for c in corners) for i in range(3)]
        return triangles, vertices, math.dist(low, high)

    if argv[0] == "--blender-import":
        importers = {
            ".obj": lambda p: bpy.ops.wm.obj_import(filepath=p),
            ".ply": lambda p: bpy.ops.import_mesh.ply(filepath=p),
            ".stl": lambda p: bpy.ops.import_mesh.stl(filepath=p),
            ".glb": lambda p: bpy.ops.import_scene.gltf(filepath=p),
            ".gltf": lambda p: bpy.ops.import_scene.gltf(filepath=p),
            ".dae": lambda p: bpy.ops.wm.collada_import(filepath=p),
        }
        with open(argv[1]) as f:
            paths = f.read().split("\n")
        with open(argv[2], "a") as out:
            for path in filter(None, paths):
                bpy.ops.wm.read_factory_settings(use_empty=True)
                record = {"path": path}
                try:
                    result = importers[os.path.splitext(path)[1].lower()](path)
                    if "FINISHED" not in result:
                        raise RuntimeError(f"the importer returned {sorted(result)}")
                    bpy.context.view_layer.update()
                    record["triangles"], record["vertices"], record["bbox"] = mesh_counts()
                except Exception as e:  # noqa: BLE001 - any importer failure is a reading
                    record["error"] = str(e).strip().splitlines()[-1][:200] if str(e) else repr(e)
                out.write(json.dumps(record) + "\n")
                out.flush()
        return

    import bmesh
    from mathutils import Matrix

    folder = argv[1]

    def select_all():
        for obj in bpy.context.scene.objects:
            obj.select_set(True)

    def suzanne():
        bpy.ops.mesh.primitive_monkey_add()

    def uv_sphere():
        bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8)
        mesh = bpy.context.object.data
        colours = mesh.color_attributes.new("Col", "BYTE_COLOR", "POINT")
        for i, c in enumerate(colours.data):
            c.color = ((i % 7) / 6, (i % 5) / 4, (i % 3) / 2, 1.0)

    def ngon_cube():
        """A cube whose top edges are cut once: an octagon on top, four pentagons, a quad."""
        bpy.ops.mesh.primitive_cube_add()
        mesh = bpy.context.object.data
        bm = bmesh.new()
        bm.from_mesh(mesh)
        top = next(f for f in bm.faces if f.normal.z > 0.5)
        bmesh.ops.subdivide_edges(bm, edges=list(top.edges), cuts=1, use_grid_fill=False)
        bm.to_mesh(mesh)
        bm.free()

    def torus():
        bpy.ops.mesh.primitive_torus_add(major_segments=24, minor_segments=8)

    def parent_and_child():
        """A cube moved, turned and scaled, and Suzanne its child, placed relative to it."""
        bpy.ops.mesh.primitive_cube_add(location=(2, 0, 0), rotation=(0, 0, math.radians(30)),
                                        scale=(1.5, 1.5, 1.5))
        parent = bpy.context.object
        bpy.ops.mesh.primitive_monkey_add(location=(0, 0, 0))
        child = bpy.context.object
        child.parent = parent
        child.matrix_parent_inverse = Matrix.Identity(4)
        child.location = (0, 0, 2)
        child.rotation_euler = (math.radians(90), 0, 0)
        for obj, name in [(parent, "Base"), (child, "Head")]:
            material = bpy.data.materials.new(name)
            obj.data.materials.append(material)

    def linked_duplicates():
        """One torus mesh placed by two objects (glTF: one mesh, two nodes; COLLADA: one
        geometry, two instances)."""
        bpy.ops.mesh.primitive_torus_add(major_segments=16, minor_segments=6)
        first = bpy.context.object
        second = first.copy()
        bpy.context.scene.collection.objects.link(second)
        second.location = (3, 0, 1)
        second.rotation_euler = (0, math.radians(45), 0)

    def triangulated_count():
        """The triangles of the scene through a Triangulate modifier (Beauty, as the OBJ and
        COLLADA exporters triangulate): it can make fewer than n − 2 a polygon, where a
        quad's two triangles would coincide with others (Suzanne: 967, not 968)."""
        objects = [o for o in bpy.context.scene.objects if o.type == "MESH"]
        modifiers = [(o, o.modifiers.new("count", "TRIANGULATE")) for o in objects]
        bpy.context.view_layer.update()
        graph = bpy.context.evaluated_depsgraph_get()
        count = sum(len(o.evaluated_get(graph).data.polygons) for o in objects)
        for obj, modifier in modifiers:
            obj.modifiers.remove(modifier)
        return count

    def welded_counts():
        """The vertices left when a reader welds by position (f32 bits, −0 as +0): each
        object's on its own (glTF: a mesh per node), and all of the scene's at once (STL)."""
        objects = [o for o in bpy.context.scene.objects if o.type == "MESH"]
        local = [numpy.array([v.co[:] for v in o.data.vertices], numpy.float32) for o in objects]
        world = [numpy.array([(o.matrix_world @ v.co)[:] for v in o.data.vertices],
                             numpy.float32) for o in objects]
        distinct = lambda points: len(numpy.unique(points + numpy.float32(0), axis=0))  # noqa: E731
        return sum(map(distinct, local)), distinct(numpy.vstack(world))

    def gltf(fmt, **options):
        return lambda p: bpy.ops.export_scene.gltf(filepath=p, export_format=fmt,
                                                   use_selection=True, **options)

    obj_export = bpy.ops.wm.obj_export
    exports = [
        ("obj-plain", ".obj", lambda p: obj_export(
            filepath=p, export_selected_objects=True, export_normals=False, export_uv=False,
            export_materials=False)),
        ("obj-normals-uv", ".obj", lambda p: obj_export(
            filepath=p, export_selected_objects=True, export_materials=False)),
        ("obj-groups", ".obj", lambda p: obj_export(
            filepath=p, export_selected_objects=True, export_object_groups=True,
            export_material_groups=True, export_smooth_groups=True)),
        ("obj-triangulated", ".obj", lambda p: obj_export(
            filepath=p, export_selected_objects=True, export_triangulated_mesh=True,
            export_materials=False)),
        ("ply-ascii", ".ply", lambda p: bpy.ops.export_mesh.ply(
            filepath=p, use_ascii=True, use_selection=True)),
        ("ply-binary-plain", ".ply", lambda p: bpy.ops.export_mesh.ply(
            filepath=p, use_selection=True, use_normals=False, use_uv_coords=False,
            use_colors=False)),
        ("stl-ascii", ".stl", lambda p: bpy.ops.export_mesh.stl(
            filepath=p, ascii=True, use_selection=True)),
        ("stl-binary", ".stl", lambda p: bpy.ops.export_mesh.stl(
            filepath=p, ascii=False, use_selection=True)),
        ("glb", ".glb", gltf("GLB")),
        ("gltf-embedded", ".gltf", gltf("GLTF_EMBEDDED")),
        ("gltf-separate", ".gltf", gltf("GLTF_SEPARATE")),
        ("glb-draco", ".glb", gltf("GLB", export_draco_mesh_compression_enable=True)),
        ("dae-polygons", ".dae", lambda p: bpy.ops.wm.collada_export(
            filepath=p, selected=True, triangulate=False)),
        ("dae-triangulated", ".dae", lambda p: bpy.ops.wm.collada_export(
            filepath=p, selected=True, triangulate=True)),
    ]
    try:
        from io_scene_gltf2.io.com.gltf2_io_draco_compression_extension import dll_exists
        draco = dll_exists(quiet=True)
    except Exception:  # noqa: BLE001 - an add-on without the check has no Draco either
        draco = False
    records = []
    shapes = [suzanne, uv_sphere, ngon_cube, torus, parent_and_child, linked_duplicates]
    for shape in shapes:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        shape()
        bpy.context.view_layer.update()
        triangles, vertices, bbox = mesh_counts()
        triangulated = triangulated_count()
        per_object, in_scene = welded_counts()
        meshes = [o.data for o in bpy.context.scene.objects if o.type == "MESH"]
        sizes = sorted({len(p.vertices) for m in meshes for p in m.polygons})
        instanced = len({m.name for m in meshes}) < len(meshes)
        for variant, suffix, export in exports:
            name = f"{shape.__name__}-{variant}{suffix}"
            record = {"name": name, "shape": shape.__name__, "variant": variant,
                      "triangles": triangulated if "triangulated" in variant else triangles,
                      "vertices": {".stl": in_scene, ".glb": per_object,
                                   ".gltf": per_object}.get(suffix, vertices),
                      "bbox": bbox, "face_sizes": sizes,
                      "instanced": instanced}
            if variant.endswith("draco") and not draco:
                record["skipped"] = "Debian's Blender lacks the Draco library (libextern_draco)"
            else:
                select_all()
                try:
                    export(os.path.join(folder, name))
                except Exception as e:  # noqa: BLE001 - said in the manifest
                    record["skipped"] = f"the exporter failed: {str(e).strip()[:200]}"
            records.append(record)
    with open(os.path.join(folder, "manifest.json"), "w") as f:
        json.dump(records, f, indent=1)


if __name__ == "__main__" and "--" in sys.argv and any(
        a.startswith("--blender-") for a in sys.argv[sys.argv.index("--") + 1:]):
    blender_main(sys.argv[sys.argv.index("--") + 1:])
    sys.exit(0)


# ---------------------------------------------------------------------------------------------
# The peers' Python: re-run with the venv's when this one lacks them.
# ---------------------------------------------------------------------------------------------

try:
    import numpy as np
    import trimesh
except ImportError:
    venv_python = os.path.join(PEERS_VENV, "bin/python")
    if os.path.exists(venv_python) and os.path.realpath(sys.prefix) != os.path.realpath(
            PEERS_VENV):
        os.execv(venv_python, [venv_python, *sys.argv])
    sys.exit(f"needs trimesh and numpy: make {PEERS_VENV} as the docstring says")


# ---------------------------------------------------------------------------------------------
# The corpus: each maker writes files into a folder and says what each holds.
# ---------------------------------------------------------------------------------------------

@dataclass
class Case:
    """One file of the corpus, and what its writer put in it."""

    path: str
    maker: str
    # The writer's triangles (n − 2 per polygon) and the vertices Pappus should keep (for OBJ,
    # PLY, OFF and COLLADA the file's referenced vertices; for glTF and STL, which Pappus welds
    # by position, the distinct positions of each mesh); None: take the reference peer's.
    triangles: int | None = None
    vertices: int | None = None
    bbox: float | None = None
    # Set for a variant Pappus documents it does not read: a refusal by name is right.
    unsupported: str | None = None
    # Known differences, by what differs: "vertices" or "bbox" (Pappus's own count is not
    # compared with the reference: why), or a peer's name (that peer reads the file otherwise:
    # why). Each is printed beside the file's line.
    known: dict = field(default_factory=dict)


# The unit cube of the hand-written files: 8 vertices, 6 quads facing out.
CUBE_V = np.array([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                   (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)], np.float64)
CUBE_QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3),
              (1, 2, 6, 5)]


def cube_triangles():
    return np.array([t for a, b, c, d in CUBE_QUADS for t in ((a, b, c), (a, c, d))], np.uint32)


def bbox_diagonal(points):
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))) if len(points) else 0.0


def distinct_positions(points):
    """Distinct positions as f32 bits, −0 as +0 (Pappus's weld)."""
    points = np.asarray(points, dtype=np.float32).reshape(-1, 3) + np.float32(0)
    return len(np.unique(points, axis=0))


def case_of_mesh(path, maker, mesh, weld, **extra):
    """A Case for a file written from a trimesh.Trimesh: its triangles, its vertices (distinct
    positions where the format welds, else those its faces use) and its bounding box."""
    used = mesh.vertices[np.unique(mesh.faces)]
    vertices = distinct_positions(used) if weld else len(used)
    return Case(path, maker, len(mesh.faces), vertices, bbox_diagonal(used), **extra)


def welds(path):
    return os.path.splitext(path)[1].lower() in (".stl", ".glb", ".gltf")


# --- trimesh ---------------------------------------------------------------------------------

def trimesh_shapes():
    """trimesh's procedural shapes, plus one with vertex colours and a grid with UVs."""
    coloured = trimesh.creation.icosphere(subdivisions=1)
    rng = np.random.default_rng(7)
    coloured.visual.vertex_colors = rng.integers(0, 256, (len(coloured.vertices), 4),
                                                 dtype=np.uint8)
    n = 6
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    grid = np.column_stack([u.ravel() * 2, v.ravel(), np.sin(u.ravel() * 3) * 0.2])
    quads = [(r * n + c, r * n + c + 1, (r + 1) * n + c + 1, (r + 1) * n + c)
             for r in range(n - 1) for c in range(n - 1)]
    faces = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    uv_grid = trimesh.Trimesh(grid, faces, process=False,
                              visual=trimesh.visual.TextureVisuals(
                                  uv=np.column_stack([u.ravel(), v.ravel()])))
    return {
        "icosphere": trimesh.creation.icosphere(subdivisions=2),
        "box": trimesh.creation.box(extents=(1, 2, 3)),
        "annulus": trimesh.creation.annulus(r_min=0.5, r_max=1.0, height=0.3),
        "cylinder": trimesh.creation.cylinder(radius=0.5, height=2, sections=16),
        "coloured": coloured,
        "uv_grid": uv_grid,
    }


def make_trimesh(folder):
    """trimesh's exporters, every format it writes, of each shape."""
    from trimesh.exchange import gltf as tgltf
    exports = {
        "obj": lambda m, p: m.export(p),
        "ply-ascii": lambda m, p: m.export(p, encoding="ascii"),
        "ply-binary": lambda m, p: m.export(p, encoding="binary"),
        "stl-ascii": lambda m, p: m.export(p, file_type="stl_ascii"),
        "stl-binary": lambda m, p: m.export(p),
        "off": lambda m, p: m.export(p),
        "glb": lambda m, p: m.export(p),
        "gltf-embedded": lambda m, p: write_bytes(p, tgltf.export_gltf(
            trimesh.Scene(m), embed_buffers=True)["model.gltf"]),
        "gltf-separate": lambda m, p: write_separate_gltf(p, tgltf.export_gltf(
            trimesh.Scene(m))),
        "glb-draco": lambda m, p: write_bytes(p, tgltf.export_glb(
            trimesh.Scene(m), extension_draco=True)),
        "dae": lambda m, p: m.export(p),
    }
    cases = []
    for name, mesh in trimesh_shapes().items():
        for variant, export in exports.items():
            suffix = "." + variant.split("-")[0]
            path = os.path.join(folder, f"{name}-{variant}{suffix}")
            try:
                export(mesh, path)
            except Exception as e:  # noqa: BLE001 - said, and the file left out
                print(f"  (trimesh did not write {os.path.basename(path)}: {e})")
                continue
            extra = {}
            if variant == "glb-draco":
                extra["known"] = {"blender": BLENDER_DRACO, "assimp": ASSIMP_DRACO}
            cases.append(case_of_mesh(path, "trimesh", mesh, welds(path), **extra))
    return cases


def write_bytes(path, data):
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def write_separate_gltf(path, files):
    """trimesh's `export_gltf` dict ({"model.gltf": ..., "gltf_buffer_0.bin": ...}) as PATH and
    its buffers beside it, renamed to PATH's stem."""
    stem = os.path.splitext(os.path.basename(path))[0]
    document = json.loads(files["model.gltf"])
    for buffer in document.get("buffers", []):
        new = f"{stem}-{buffer['uri']}"
        write_bytes(os.path.join(os.path.dirname(path), new), files[buffer["uri"]])
        buffer["uri"] = new
    write_bytes(path, json.dumps(document))


# --- pymeshlab -------------------------------------------------------------------------------

def make_pymeshlab(folder):
    """MeshLab's savers: each format binary and ASCII, with and without colours, normals and
    quality."""
    import pymeshlab

    shapes = {
        "sphere": lambda ms: ms.create_sphere(subdiv=3),
        "torus": lambda ms: ms.create_torus(hsubdiv=20, vsubdiv=10),
        "cube": lambda ms: ms.create_cube(),
        "annulus": lambda ms: ms.create_annulus(sides=24),
    }
    full = {"save_vertex_color": True, "save_vertex_normal": True}
    saves = {
        "ply-binary-full": (".ply", {"binary": True, **full, "save_vertex_quality": True}),
        "ply-ascii-full": (".ply", {"binary": False, **full, "save_vertex_quality": True}),
        "ply-binary-plain": (".ply", {"binary": True, "save_vertex_color": False,
                                      "save_vertex_normal": False,
                                      "save_vertex_quality": False}),
        "obj-full": (".obj", full),
        "obj-plain": (".obj", {"save_vertex_color": False, "save_vertex_normal": False}),
        "off-colour": (".off", {"save_vertex_color": True}),
        "off-plain": (".off", {"save_vertex_color": False}),
        "stl-binary": (".stl", {"binary": True}),
        "stl-ascii": (".stl", {"binary": False}),
    }
    cases = []
    for name, create in shapes.items():
        ms = pymeshlab.MeshSet()
        create(ms)
        ms.compute_color_by_function_per_vertex(x="abs(x)*255", y="abs(y)*255", z="abs(z)*255")
        ms.compute_scalar_by_function_per_vertex(q="x*y")
        m = ms.current_mesh()
        mesh = trimesh.Trimesh(m.vertex_matrix(), m.face_matrix(), process=False)
        for variant, (suffix, options) in saves.items():
            path = os.path.join(folder, f"{name}-{variant}{suffix}")
            try:
                ms.save_current_mesh(path, **options)
            except Exception as e:  # noqa: BLE001 - said, and the file left out
                print(f"  (pymeshlab did not write {os.path.basename(path)}: {e})")
                continue
            known = {"assimp": ASSIMP_NCOFF} if variant == "off-colour" else {}
            cases.append(case_of_mesh(path, "pymeshlab", mesh, welds(path), known=known))
    return cases


# --- Blender ---------------------------------------------------------------------------------

def blender_env():
    """The environment for Blender without a pyenv or venv Python's traces: Debian's Blender
    runs the system Python 3.11 and its numpy, and a pyenv `python3` first on PATH (or its
    PYENV_* variables) leaves it without numpy."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("PYENV", "PYTHONHOME", "PYTHONPATH", "VIRTUAL_ENV"))}
    env["PATH"] = os.pathsep.join(d for d in env.get("PATH", "").split(os.pathsep)
                                  if ".pyenv" not in d and not d.startswith(PEERS_VENV))
    return env


def make_blender(folder):
    """Blender's exporters, run headless on this file (see blender_main)."""
    if not USE_BLENDER:
        print("  (Blender: not on PATH or --no-blender: its files are left out)")
        return []
    run = subprocess.run(
        ["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python",
         os.path.abspath(__file__), "--", "--blender-export", folder],
        capture_output=True, text=True, timeout=900, env=blender_env())
    manifest = os.path.join(folder, "manifest.json")
    if run.returncode != 0 or not os.path.exists(manifest):
        print(f"  (Blender's export failed: {(run.stdout + run.stderr).strip()[-500:]})")
        return []
    with open(manifest) as f:
        records = json.load(f)
    os.remove(manifest)
    cases = []
    skipped = {}
    for r in records:
        if "skipped" in r:
            skipped.setdefault(r["skipped"], []).append(r["name"])
            continue
        path = os.path.join(folder, r["name"])
        case = Case(path, "blender", r["triangles"], r["vertices"], r["bbox"])
        variant = r["variant"]
        if variant == "ply-ascii":
            case.known["vertices"] = ("Blender's PLY exporter, asked for normals and UVs, "
                                      "writes a vertex per distinct (position, normal, UV, "
                                      "colour), more than the mesh has; PLY readers keep them")
        if variant.startswith("ply-binary") and len(r["face_sizes"]) > 1:
            case.known["trimesh"] = TRIMESH_MIXED_PLY
        if r["instanced"] and variant.startswith(("glb", "gltf", "dae")):
            case.known["assimp"] = ASSIMP_INSTANCES
        cases.append(case)
        if variant == "glb":
            cases += draco_by_gltf_transform(case)
    for why, names in skipped.items():
        print(f"  (Blender did not write {len(names)} files ({names[0]}, …): {why})")
    return cases


GLTF_TRANSFORM = (shutil.which("gltf-transform")
                  or os.path.expanduser("~/.cache/pappus/gltf-transform/node_modules/.bin/"
                                        "gltf-transform"))


def draco_by_gltf_transform(case):
    """The Blender `.glb` of `case` compressed by gltf-transform's `draco` (Google's encoder,
    EdgeBreaker, positions, normals and UVs quantised), which Debian's Blender cannot write:
    the same surface, the same counts. Left out without the CLI (`npm install
    @gltf-transform/cli` in ~/.cache/pappus/gltf-transform)."""
    if not os.path.exists(GLTF_TRANSFORM):
        return []
    path = case.path.removesuffix(".glb") + "-draco-gltf-transform.glb"
    run = subprocess.run([GLTF_TRANSFORM, "draco", case.path, path],
                         capture_output=True, text=True, timeout=120)
    if run.returncode != 0:
        print(f"  (gltf-transform did not write {os.path.basename(path)}: "
              f"{(run.stdout + run.stderr).strip()[-200:]})")
        return []
    return [Case(path, "gltf-transform", case.triangles, case.vertices, case.bbox,
                 known={**case.known, "blender": BLENDER_DRACO})]


# Peers' known limits that several makers' files meet.
ASSIMP_INSTANCES = "assimp counts each mesh once, however many nodes place it"
BLENDER_DRACO = "Debian's Blender lacks the Draco library its importer needs"
ASSIMP_DRACO = ("assimp refuses trimesh's Draco primitives (`Invalid accessor without data`), "
                "though it decodes the hand-made ones")
TRIMESH_MIXED_PLY = "trimesh's binary PLY reader wants every face of one size"
ASSIMP_NCOFF = "assimp's OFF reader refuses the `NCOFF` header"


# --- glTF by hand ----------------------------------------------------------------------------

COMPONENT = {np.dtype(np.int8): 5120, np.dtype(np.uint8): 5121, np.dtype(np.int16): 5122,
             np.dtype(np.uint16): 5123, np.dtype(np.uint32): 5125, np.dtype(np.float32): 5126}
TYPE = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963


class Gltf:
    """A glTF 2.0 document written by hand: one buffer, views and accessors appended."""

    def __init__(self):
        self.doc = {"asset": {"version": "2.0", "generator": "pappus benches/reader_corpus.py"},
                    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [],
                    "accessors": [], "bufferViews": [], "buffers": []}
        self.blob = bytearray()

    def view(self, data, target=None, stride=None):
        self.blob += b"\0" * (-len(self.blob) % 4)
        view = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)}
        if target:
            view["target"] = target
        if stride:
            view["byteStride"] = stride
        self.blob += data
        self.doc["bufferViews"].append(view)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, array, view=None, offset=0, normalized=False, minmax=True, target=None):
        """An accessor for `array` (n × k, or n), in a new view unless `view` is given."""
        array = np.asarray(array)
        if view is None:
            view = self.view(array.tobytes(), target)
        k = 1 if array.ndim == 1 else array.shape[1]
        accessor = {"bufferView": view, "componentType": COMPONENT[array.dtype],
                    "count": len(array), "type": TYPE[k]}
        if offset:
            accessor["byteOffset"] = offset
        if normalized:
            accessor["normalized"] = True
        if minmax:
            flat = array.reshape(len(array), k)
            cast = float if array.dtype.kind == "f" else int
            accessor["min"] = [cast(x) for x in flat.min(axis=0)]
            accessor["max"] = [cast(x) for x in flat.max(axis=0)]
        self.doc["accessors"].append(accessor)
        return len(self.doc["accessors"]) - 1

    def mesh(self, primitives, name=None):
        self.doc["meshes"].append({"primitives": primitives, **({"name": name} if name else {})})
        return len(self.doc["meshes"]) - 1

    def node(self, root=True, **fields):
        self.doc["nodes"].append(fields)
        index = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(index)
        return index

    def save(self, path, bin_name=None):
        """`.glb`, or `.gltf` with the buffer embedded, or beside it as `bin_name`."""
        self.blob += b"\0" * (-len(self.blob) % 4)
        doc = dict(self.doc)
        for key in ("accessors", "bufferViews", "meshes", "nodes"):
            if not doc[key]:
                del doc[key]
        buffer = {"byteLength": len(self.blob)}
        if path.endswith(".glb"):
            doc["buffers"] = [buffer]
            text = json.dumps(doc).encode()
            text += b" " * (-len(text) % 4)
            chunks = (struct.pack("<II", len(text), 0x4E4F534A) + text
                      + struct.pack("<II", len(self.blob), 0x004E4942) + bytes(self.blob))
            write_bytes(path, struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)
            return
        if bin_name:
            from urllib.parse import quote
            write_bytes(os.path.join(os.path.dirname(path), bin_name), bytes(self.blob))
            buffer["uri"] = quote(bin_name)
        else:
            buffer["uri"] = ("data:application/octet-stream;base64,"
                             + base64.b64encode(bytes(self.blob)).decode())
        doc["buffers"] = [buffer]
        write_bytes(path, json.dumps(doc, indent=1))


def box24():
    """The Khronos Box: a unit cube of 24 vertices (4 a face, split by normal), 12 triangles."""
    positions, normals, indices = [], [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = np.zeros(3)
            n[axis] = sign
            u = np.zeros(3)
            u[(axis + 1) % 3] = 1.0
            v = np.cross(n, u)
            base = len(positions)
            for a, b in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                positions.append(0.5 * n + 0.5 * a * u + 0.5 * b * v)
                normals.append(n)
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return (np.array(positions, np.float32), np.array(normals, np.float32),
            np.array(indices, np.uint16))


def box_gltf(index_type=np.uint16, minmax=True):
    """A glTF of the Box, its primitive's attributes and indices as given."""
    g = Gltf()
    p, n, i = box24()
    prim = {"attributes": {"POSITION": g.accessor(p, minmax=minmax, target=ARRAY_BUFFER),
                           "NORMAL": g.accessor(n, target=ARRAY_BUFFER)},
            "indices": g.accessor(i.astype(index_type), target=ELEMENT_ARRAY_BUFFER)}
    g.node(mesh=g.mesh([prim], "Box"))
    return g, prim


def trs_matrix(translation=(0, 0, 0), rotation=(0, 0, 0, 1), scale=(1, 1, 1)):
    x, y, z, w = rotation
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = r * np.asarray(scale)
    m[:3, 3] = translation
    return m


def transformed(matrix, points):
    points = np.asarray(points, np.float64)
    return points @ matrix[:3, :3].T + matrix[:3, 3]


def make_gltf_by_hand(folder):
    """Files that rebuild the shapes of the Khronos glTF samples, each with one awkward
    feature."""
    cases = []
    here = lambda name: os.path.join(folder, name)  # noqa: E731
    box_p, box_n, box_i = box24()
    box_bbox = bbox_diagonal(box_p)

    # SimpleSparseAccessor: a strip of 14 vertices, three raised by a sparse substitution.
    g = Gltf()
    xs = np.arange(7, dtype=np.float32)
    base = np.concatenate([np.column_stack([xs, 0 * xs, 0 * xs]),
                           np.column_stack([xs, 0 * xs + 1, 0 * xs])]).astype(np.float32)
    tris = [t for c in range(6) for t in ((c, c + 1, 8 + c), (c, 8 + c, 7 + c))]
    position = g.accessor(base, target=ARRAY_BUFFER)
    raised_at = np.array([8, 10, 12], np.uint16)
    raised = base[raised_at].copy()
    raised[:, 1] = 4
    g.doc["accessors"][position]["sparse"] = {
        "count": 3,
        "indices": {"bufferView": g.view(raised_at.tobytes()), "componentType": 5123},
        "values": {"bufferView": g.view(raised.tobytes())}}
    final = base.copy()
    final[raised_at] = raised
    g.doc["accessors"][position]["max"] = [6.0, 4.0, 0.0]
    prim = {"attributes": {"POSITION": position},
            "indices": g.accessor(np.array(tris, np.uint16).ravel(),
                                  target=ELEMENT_ARRAY_BUFFER)}
    g.node(mesh=g.mesh([prim]))
    g.save(here("sparse_accessor.gltf"))
    cases.append(Case(here("sparse_accessor.gltf"), "hand", 12, 14, bbox_diagonal(final),
                      known={"trimesh": "trimesh does not apply the sparse substitution of an "
                                        "accessor that has a bufferView (the grid stays flat)"}))

    # BoxInterleaved: POSITION and NORMAL in one view of stride 24.
    g = Gltf()
    view = g.view(np.hstack([box_p, box_n]).tobytes(), ARRAY_BUFFER, stride=24)
    prim = {"attributes": {"POSITION": g.accessor(box_p, view=view),
                           "NORMAL": g.accessor(box_n, view=view, offset=12, minmax=False)},
            "indices": g.accessor(box_i, target=ELEMENT_ARRAY_BUFFER)}
    g.node(mesh=g.mesh([prim]))
    g.save(here("box_interleaved.glb"))
    cases.append(Case(here("box_interleaved.glb"), "hand", 12, 8, box_bbox))

    # The Box with u8 and with u32 indices.
    for kind, name in [(np.uint8, "box_u8_indices.gltf"), (np.uint32, "box_u32_indices.glb")]:
        g, _ = box_gltf(kind)
        g.save(here(name))
        cases.append(Case(here(name), "hand", 12, 8, box_bbox))

    # TriangleStrip and TriangleFan (the Khronos MeshPrimitiveModes sample): a strip of 10
    # triangles and a fan of 8 in one mesh.
    g = Gltf()
    strip = np.array([(c, r, 0) for c in range(6) for r in (0, 1)], np.float32)
    rim = [(10 + math.cos(a), math.sin(a), 2) for a in np.linspace(0, 2 * math.pi, 9)[:-1]]
    fan = np.array([(10, 0, 2), *rim], np.float32)
    prims = [{"attributes": {"POSITION": g.accessor(strip, target=ARRAY_BUFFER)}, "mode": 5},
             {"attributes": {"POSITION": g.accessor(fan, target=ARRAY_BUFFER)},
              "indices": g.accessor(np.array([0, *range(1, 9), 1], np.uint16),
                                    target=ELEMENT_ARRAY_BUFFER), "mode": 6}]
    g.node(mesh=g.mesh(prims))
    g.save(here("strip_and_fan.gltf"))
    cases.append(Case(here("strip_and_fan.gltf"), "hand", 18, 21,
                      bbox_diagonal(np.vstack([strip, fan])),
                      known={"trimesh": "trimesh reads lists and strips, and skips fans "
                                        "(mode 6)"}))

    # A node tree (the Khronos TransformTest's ideas): a matrix root, a TRS child, a matrix
    # grandchild, each drawing the Box.
    g, _ = box_gltf()
    root_m = trs_matrix((0, 0, 3), (math.sin(math.pi / 4), 0, 0, math.cos(math.pi / 4)))
    child_t = dict(translation=[2.0, 0.0, 0.0],
                   rotation=[0.0, math.sin(math.pi / 8), 0.0, math.cos(math.pi / 8)],
                   scale=[1.0, 2.0, 1.0])
    grand_m = trs_matrix((0, 3, 0), scale=(0.5, 0.5, 0.5))
    g.doc["nodes"] = []
    g.doc["scenes"][0]["nodes"] = []
    grand = g.node(root=False, name="grandchild", mesh=0,
                   matrix=list(grand_m.T.ravel()))
    child = g.node(root=False, name="child", mesh=0, children=[grand], **child_t)
    g.node(name="root", mesh=0, children=[child], matrix=list(root_m.T.ravel()))
    child_m = root_m @ trs_matrix(**child_t)
    placed = np.vstack([transformed(m, box_p) for m in (root_m, child_m, child_m @ grand_m)])
    g.save(here("node_tree.gltf"))
    cases.append(Case(here("node_tree.gltf"), "hand", 36, 24, bbox_diagonal(placed),
                      known={"assimp": ASSIMP_INSTANCES}))

    # Several primitives, two materials, one POSITION accessor shared.
    g = Gltf()
    position = g.accessor(box_p, target=ARRAY_BUFFER)
    prims = [{"attributes": {"POSITION": position},
              "indices": g.accessor(part, target=ELEMENT_ARRAY_BUFFER), "material": m}
             for m, part in enumerate([box_i[:12], box_i[12:]])]
    g.doc["materials"] = [{"name": "red", "pbrMetallicRoughness": {"baseColorFactor":
                                                                   [1, 0, 0, 1]}},
                          {"name": "blue"}]
    g.node(mesh=g.mesh(prims))
    g.save(here("two_primitives.glb"))
    cases.append(Case(here("two_primitives.glb"), "hand", 12, 8, box_bbox))

    # Normalised u8 texture coordinates (and u8 indices), each element padded to 4 bytes as
    # the spec asks of vertex attributes.
    g = Gltf()
    grid = np.array([(x, y, 0) for y in range(3) for x in range(3)], np.float32)
    uv = np.array([(x * 127, 255 - y * 127) for y in range(3) for x in range(3)], np.uint8)
    padded = np.zeros((9, 4), np.uint8)
    padded[:, :2] = uv
    view = g.view(padded.tobytes(), ARRAY_BUFFER, stride=4)
    quads = [(y * 3 + x, y * 3 + x + 1, y * 3 + x + 4, y * 3 + x + 3)
             for y in range(2) for x in range(2)]
    tri = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.uint8)
    prim = {"attributes": {"POSITION": g.accessor(grid, target=ARRAY_BUFFER),
                           "TEXCOORD_0": g.accessor(uv, view=view, normalized=True)},
            "indices": g.accessor(tri.ravel(), target=ELEMENT_ARRAY_BUFFER)}
    g.node(mesh=g.mesh([prim]))
    g.save(here("normalized_u8_uv.gltf"))
    cases.append(Case(here("normalized_u8_uv.gltf"), "hand", 8, 9, bbox_diagonal(grid)))

    # POSITION without min/max (the spec requires them; many exporters omit them).
    g, _ = box_gltf(minmax=False)
    g.save(here("no_min_max.gltf"))
    cases.append(Case(here("no_min_max.gltf"), "hand", 12, 8, box_bbox))

    # KHR_materials_pbrSpecularGlossiness required: a material extension, not geometry.
    g, prim = box_gltf()
    g.doc["materials"] = [{"name": "specgloss", "extensions": {
        "KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0.8, 0.2, 0.2, 1],
                                                "specularFactor": [1, 1, 1],
                                                "glossinessFactor": 0.5}}}]
    prim["material"] = 0
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = [
        "KHR_materials_pbrSpecularGlossiness"]
    g.save(here("spec_gloss_required.gltf"))
    cases.append(Case(here("spec_gloss_required.gltf"), "hand", 12, 8, box_bbox))

    # KHR_mesh_quantization (what gltfpack writes): positions as i16, a node scale undoing it.
    g = Gltf()
    quantized = np.round(box_p * 2000).astype(np.int16)
    padded = np.zeros((24, 4), np.int16)
    padded[:, :3] = quantized
    view = g.view(padded.tobytes(), ARRAY_BUFFER, stride=8)
    prim = {"attributes": {"POSITION": g.accessor(quantized, view=view)},
            "indices": g.accessor(box_i, target=ELEMENT_ARRAY_BUFFER)}
    g.node(mesh=g.mesh([prim]), scale=[0.0005, 0.0005, 0.0005])
    g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    g.save(here("mesh_quantization.glb"))
    cases.append(Case(here("mesh_quantization.glb"), "hand", 12, 8, box_bbox))

    # A `.bin` whose name needs percent-encoding in the URI.
    g, _ = box_gltf()
    g.save(here("external_buffer.gltf"), bin_name="box data #1.bin")
    cases.append(Case(here("external_buffer.gltf"), "hand", 12, 8, box_bbox,
                      known={"trimesh": "trimesh opens the URI undecoded (`box%20data…`)",
                             "assimp": "assimp opens the URI undecoded (`box%20data…`)"}))

    # Draco (Google's C++ encoder, through DracoPy): required (no uncompressed data) at the
    # default level (EdgeBreaker), at level 0 (sequential) and 10 (EdgeBreaker valence), and
    # optional with an uncompressed fallback.
    try:
        import DracoPy
    except ImportError:
        DracoPy = None
        print("  (DracoPy not installed: the hand-written Draco files are left out)")
    cube8, cube_tris = CUBE_V.astype(np.float32), cube_triangles()
    variants = [("draco_required", True, 7), ("draco_sequential", True, 0),
                ("draco_valence", True, 10), ("draco_with_fallback", False, 7)]
    for name, required, level in variants if DracoPy else ():
        g = Gltf()
        encoded = DracoPy.encode(cube8, cube_tris, quantization_bits=14,
                                 compression_level=level)
        draco_view = g.view(encoded)
        if required:
            position = {"componentType": 5126, "count": 8, "type": "VEC3",
                        "min": [0.0] * 3, "max": [1.0] * 3}
            indices = {"componentType": 5123, "count": 36, "type": "SCALAR"}
            first = len(g.doc["accessors"])
            g.doc["accessors"] += [position, indices]
            attributes, index = {"POSITION": first}, first + 1
        else:
            attributes = {"POSITION": g.accessor(cube8, target=ARRAY_BUFFER)}
            index = g.accessor(cube_tris.astype(np.uint16).ravel(),
                               target=ELEMENT_ARRAY_BUFFER)
        prim = {"attributes": attributes, "indices": index, "extensions": {
            "KHR_draco_mesh_compression": {"bufferView": draco_view,
                                           "attributes": {"POSITION": 0}}}}
        g.node(mesh=g.mesh([prim]))
        g.doc["extensionsUsed"] = ["KHR_draco_mesh_compression"]
        if required:
            g.doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
        g.save(here(name + ".glb"))
        cases.append(Case(here(name + ".glb"), "hand", 12, 8, math.sqrt(3),
                          known={"blender": BLENDER_DRACO}))

    # glTF 1.0: the older format (objects keyed by id), which glTF 2.0 readers refuse.
    blob = box_p.tobytes() + box_i.tobytes()
    doc = {"asset": {"version": "1.0"}, "scene": "scene0",
           "scenes": {"scene0": {"nodes": ["node0"]}},
           "nodes": {"node0": {"meshes": ["box"], "matrix": list(np.eye(4).ravel())}},
           "meshes": {"box": {"primitives": [{"attributes": {"POSITION": "pos"},
                                              "indices": "idx", "mode": 4,
                                              "material": "mat"}]}},
           "materials": {"mat": {"values": {"diffuse": [0.8, 0.8, 0.8, 1]}}},
           "accessors": {
               "pos": {"bufferView": "vertices", "byteOffset": 0, "byteStride": 12,
                       "componentType": 5126, "count": 24, "type": "VEC3",
                       "min": [-0.5] * 3, "max": [0.5] * 3},
               "idx": {"bufferView": "indices", "byteOffset": 0, "componentType": 5123,
                       "count": 36, "type": "SCALAR"}},
           "bufferViews": {
               "vertices": {"buffer": "buf", "byteOffset": 0, "byteLength": 288,
                            "target": ARRAY_BUFFER},
               "indices": {"buffer": "buf", "byteOffset": 288, "byteLength": 72,
                           "target": ELEMENT_ARRAY_BUFFER}},
           "buffers": {"buf": {"type": "arraybuffer", "byteLength": len(blob),
                               "uri": "data:application/octet-stream;base64,"
                                      + base64.b64encode(blob).decode()}}}
    write_bytes(here("gltf_1_0.gltf"), json.dumps(doc, indent=1))
    cases.append(Case(here("gltf_1_0.gltf"), "hand", 12, 8, box_bbox,
                      unsupported="glTF 1.0 (Pappus reads glTF 2.0)",
                      known={"trimesh": "trimesh reads glTF 2 only",
                             "blender": "Blender's importer reads glTF 2.0 only"}))
    return cases


# --- COLLADA by hand -------------------------------------------------------------------------

def numbers(values, comma=False):
    text = " ".join(f"{v:.6f}" if isinstance(v, float) else str(v) for v in values)
    return text.replace(".", ",") if comma else text


def dae(geometries, scene_nodes, up_axis="Y_UP", library_nodes=""):
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><contributor><authoring_tool>pappus benches/reader_corpus.py</authoring_tool>
  </contributor><unit name="meter" meter="1"/><up_axis>{up_axis}</up_axis></asset>
  <library_geometries>{geometries}</library_geometries>
  {f"<library_nodes>{library_nodes}</library_nodes>" if library_nodes else ""}
  <library_visual_scenes><visual_scene id="scene">{scene_nodes}</visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"""


def dae_cube(gid, primitive="polylist", scale=1.0, comma=False):
    """A cube geometry: 8 positions and a normal per face, as `polylist`, `triangles` or
    `polygons`."""
    positions = [float(x * scale) for x in CUBE_V.ravel()]
    normals = []
    for quad in CUBE_QUADS:
        a, b, c = (CUBE_V[i] for i in quad[:3])
        n = np.cross(b - a, c - a)
        normals += [float(x) for x in n / np.linalg.norm(n)]
    inputs = (f'<input semantic="VERTEX" source="#{gid}-v" offset="0"/>'
              f'<input semantic="NORMAL" source="#{gid}-n" offset="1"/>')
    if primitive == "triangles":
        corners = [(v, t // 2) for t, tri in enumerate(cube_triangles()) for v in tri]
        body = (f'<triangles count="12">{inputs}<p>{numbers(x for c in corners for x in c)}'
                f'</p></triangles>')
    elif primitive == "polylist":
        corners = [(v, f) for f, quad in enumerate(CUBE_QUADS) for v in quad]
        body = (f'<polylist count="6">{inputs}<vcount>4 4 4 4 4 4</vcount>'
                f'<p>{numbers(x for c in corners for x in c)}</p></polylist>')
    else:
        ps = "".join(f"<p>{numbers(x for v in quad for x in (v, f))}</p>"
                     for f, quad in enumerate(CUBE_QUADS))
        body = f'<polygons count="6">{inputs}{ps}</polygons>'

    def source(name, values, count):
        return (f'<source id="{gid}-{name}"><float_array id="{gid}-{name}-a" count="{len(values)}">'
                f'{numbers(values, comma)}</float_array><technique_common>'
                f'<accessor source="#{gid}-{name}-a" count="{count}" stride="3">'
                f'<param name="X" type="float"/><param name="Y" type="float"/>'
                f'<param name="Z" type="float"/></accessor></technique_common></source>')
    return (f'<geometry id="{gid}" name="{gid}"><mesh>{source("p", positions, 8)}'
            f'{source("n", normals, 6)}<vertices id="{gid}-v"><input semantic="POSITION" '
            f'source="#{gid}-p"/></vertices>{body}</mesh></geometry>')


def make_collada_by_hand(folder):
    """COLLADA of a cube, each file with one of the format's variants."""
    cases = []
    here = lambda name: os.path.join(folder, name)  # noqa: E731
    placed = '<node id="n" name="cube"><instance_geometry url="#cube"/></node>'
    cube_bbox = math.sqrt(3)
    for primitive in ("polylist", "triangles", "polygons"):
        write_bytes(here(f"{primitive}.dae"), dae(dae_cube("cube", primitive), placed))
        cases.append(Case(here(f"{primitive}.dae"), "hand", 12, 8, cube_bbox))

    # Z-up, with a node that moves and turns the cube.
    node = ('<node id="n" name="cube"><translate>0 0 5</translate>'
            '<rotate>0 0 1 30</rotate><instance_geometry url="#cube"/></node>')
    write_bytes(here("z_up.dae"), dae(dae_cube("cube"), node, up_axis="Z_UP"))
    turned = transformed(trs_matrix((0, 0, 5), (0, 0, math.sin(math.pi / 12),
                                                math.cos(math.pi / 12))), CUBE_V)
    cases.append(Case(here("z_up.dae"), "hand", 12, 8, bbox_diagonal(turned)))

    # A library node placed twice by <instance_node>.
    library = '<node id="part" name="part"><instance_geometry url="#cube"/></node>'
    nodes = "".join(f'<node id="copy{i}" name="copy{i}"><translate>{3 * i} 0 0</translate>'
                    f'<instance_node url="#part"/></node>' for i in range(2))
    write_bytes(here("instance_node.dae"), dae(dae_cube("cube"), nodes, library_nodes=library))
    cases.append(Case(here("instance_node.dae"), "hand", 24, 16,
                      bbox_diagonal(np.vstack([CUBE_V, CUBE_V + (3, 0, 0)])),
                      known={"assimp": ASSIMP_INSTANCES}))

    # Decimal commas, as some European-locale exporters write them (`1,450607`).
    write_bytes(here("decimal_commas.dae"),
                dae(dae_cube("cube", scale=1.450607, comma=True), placed))
    cases.append(Case(here("decimal_commas.dae"), "hand", 12, 8, 1.450607 * math.sqrt(3),
                      known={"pycollada": "pycollada: `Corrupted float array`",
                             "trimesh": "trimesh (through pycollada) reads no geometry",
                             "blender": "Blender's importer makes no faces of it"}))
    return cases


# --- PLY, OBJ, STL, OFF by hand --------------------------------------------------------------

def ply_header(fmt, vertex_props, face_prop="property list uchar int vertex_indices",
               faces=6, vertices=8, extra_lines=()):
    lines = ["ply", f"format {fmt} 1.0", *extra_lines, f"element vertex {vertices}",
             *vertex_props]
    if faces is not None:
        lines += [f"element face {faces}", face_prop]
    return "\n".join([*lines, "end_header"]) + "\n"


def make_ply_by_hand(folder):
    cases = []
    here = lambda name: os.path.join(folder, name)  # noqa: E731
    xyz = ["property float x", "property float y", "property float z"]
    quads = "".join(f"4 {' '.join(map(str, q))}\n" for q in CUBE_QUADS)
    rows = lambda extra: "".join(  # noqa: E731
        f"{x:g} {y:g} {z:g}{extra(i)}\n" for i, (x, y, z) in enumerate(CUBE_V))
    cube = dict(triangles=12, vertices=8, bbox=math.sqrt(3))

    # A line that is not a keyword (some scanners' `Created by …`).
    text = ply_header("ascii", xyz, extra_lines=["comment made by hand",
                                                   "Created by ScanStudio 2.0"])
    write_bytes(here("created_by_line.ply"), text + rows(lambda i: "") + quads)
    cases.append(Case(here("created_by_line.ply"), "hand", **cube))

    # uchar colours with alpha; float colours, binary.
    text = ply_header("ascii", xyz + [f"property uchar {c}" for c in
                                      ("red", "green", "blue", "alpha")])
    write_bytes(here("uchar_colours.ply"),
                text + rows(lambda i: f" {i * 30} {255 - i * 30} 128 255") + quads)
    cases.append(Case(here("uchar_colours.ply"), "hand", **cube))
    header = ply_header("binary_little_endian",
                        xyz + [f"property float {c}" for c in ("red", "green", "blue")])
    body = b"".join(struct.pack("<6f", *v, i / 8, 1 - i / 8, 0.5) for i, v in enumerate(CUBE_V))
    body += b"".join(struct.pack("<B4i", 4, *q) for q in CUBE_QUADS)
    write_bytes(here("float_colours.ply"), header.encode() + body)
    cases.append(Case(here("float_colours.ply"), "hand", **cube))

    # `vertex_index` (the other name) with the newer type names.
    text = ply_header("ascii", ["property float32 x", "property float32 y", "property float32 z"],
                      face_prop="property list uint8 int32 vertex_index")
    write_bytes(here("vertex_index.ply"), text + rows(lambda i: "") + quads)
    cases.append(Case(here("vertex_index.ply"), "hand", **cube))

    # Big-endian doubles and uint indices.
    header = ply_header("binary_big_endian", [f"property double {c}" for c in "xyz"],
                        face_prop="property list uchar uint vertex_indices")
    body = b"".join(struct.pack(">3d", *v) for v in CUBE_V)
    body += b"".join(struct.pack(">B4I", 4, *q) for q in CUBE_QUADS)
    write_bytes(here("big_endian.ply"), header.encode() + body)
    cases.append(Case(here("big_endian.ply"), "hand", **cube))

    # Triangle strips (as some Stanford scans were saved): two strips of a 2 × 6 grid, −1
    # between them.
    grid = [(c, r, 0) for r in range(3) for c in range(6)]
    strip = [v for c in range(6) for v in (c, 6 + c)] + [-1] + \
            [v for c in range(6) for v in (6 + c, 12 + c)]
    text = ply_header("ascii", xyz, vertices=18, faces=None)
    text = text.replace("end_header", "element tristrips 1\n"
                        "property list int int vertex_indices\nend_header")
    body = "".join(f"{x} {y} {z}\n" for x, y, z in grid)
    body += f"{len(strip)} {' '.join(map(str, strip))}\n"
    write_bytes(here("tristrips.ply"), text + body)
    cases.append(Case(here("tristrips.ply"), "hand", 20, 18, bbox_diagonal(grid),
                      known={"trimesh": "trimesh does not read a `tristrips` element",
                             "assimp": "assimp does not read a `tristrips` element as "
                                       "strips"}))

    # A point cloud: vertices and no face element. No surface.
    text = ply_header("ascii", xyz, vertices=50, faces=None)
    points = np.random.default_rng(3).random((50, 3))
    write_bytes(here("point_cloud.ply"), text + "".join(f"{x} {y} {z}\n" for x, y, z in points))
    cases.append(Case(here("point_cloud.ply"), "hand", 0, 0, None))
    return cases


def obj_cube(vertex=lambda v: "v {} {} {}".format(*v), face=None):
    face = face or (lambda q: "f " + " ".join(str(i + 1) for i in q))
    return "\n".join([*map(vertex, CUBE_V.tolist()), *map(face, CUBE_QUADS)]) + "\n"


def make_obj_by_hand(folder):
    cases = []
    here = lambda name: os.path.join(folder, name)  # noqa: E731
    cube = dict(triangles=12, vertices=8, bbox=math.sqrt(3))

    # Negative (relative) indices: each face counts back from the last vertex.
    write_bytes(here("negative_indices.obj"),
                obj_cube(face=lambda q: "f " + " ".join(str(i - 8) for i in q)))
    cases.append(Case(here("negative_indices.obj"), "hand", **cube))

    # `\` continuations inside `v` and `f` lines.
    text = obj_cube(vertex=lambda v: "v {} \\\n {} {}".format(*v),
                    face=lambda q: "f {} {} \\\n{} {}".format(*(i + 1 for i in q)))
    write_bytes(here("continuations.obj"), "# joined lines\n" + text)
    cases.append(Case(here("continuations.obj"), "hand", **cube))

    # An exponent written `3.1+e2` (some exporters' printf), meaning 3.1e+2.
    text = ("v 0 0 0\nv 3.1+e2 0 0\nv 0 1 0\nv 0 0 1\n"
            "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    write_bytes(here("exponent_typo.obj"), text)
    cases.append(Case(here("exponent_typo.obj"), "hand", 4, 4, math.sqrt(310.0 ** 2 + 1),
                      known={"blender": "Blender's number parse stops at `+e2`: x = 3.1"}))

    # A keyhole: one polygon around a square with a square hole, the bridge edge walked
    # twice (outer square, bridge in, inner square backwards, bridge out).
    text = ("v 0 0 0\nv 3 0 0\nv 3 3 0\nv 0 3 0\nv 1 1 0\nv 1 2 0\nv 2 2 0\nv 2 1 0\n"
            "f 1 2 3 4 1 5 6 7 8 5\n")
    write_bytes(here("keyhole.obj"), text)
    cases.append(Case(here("keyhole.obj"), "hand", 8, 8, math.sqrt(18)))

    # Corner forms mixed within the file: v, v/vt, v//vn, v/vt/vn.
    text = "".join("v {} {} {}\n".format(*v) for v in CUBE_V.tolist())
    text += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
    forms = [lambda i, k: f"{i}", lambda i, k: f"{i}/{k}", lambda i, k: f"{i}//1",
             lambda i, k: f"{i}/{k}/1"]
    for f, quad in enumerate(CUBE_QUADS):
        text += "f " + " ".join(forms[f % 4](i + 1, k + 1) for k, i in enumerate(quad)) + "\n"
    write_bytes(here("mixed_corners.obj"), text)
    cases.append(Case(here("mixed_corners.obj"), "hand", **cube))
    return cases


def stl_binary(triangles, header):
    body = b"".join(struct.pack("<12fH", 0, 0, 0, *t.ravel(), 0) for t in triangles)
    return header.ljust(80, b" ")[:80] + struct.pack("<I", len(triangles)) + body


def stl_ascii(name, triangles, newline="\n"):
    lines = [f"solid {name}"]
    for t in triangles:
        lines += ["  facet normal 0 0 0", "    outer loop",
                  *(f"      vertex {x:e} {y:e} {z:e}" for x, y, z in t),
                  "    endloop", "  endfacet"]
    return newline.join([*lines, f"endsolid {name}"]) + newline


def make_stl_by_hand(folder):
    cases = []
    here = lambda name: os.path.join(folder, name)  # noqa: E731
    tris = CUBE_V[cube_triangles()].astype(np.float32)
    write_bytes(here("solid_header_binary.stl"),
                stl_binary(tris, b"solid cube, binary all the same (a CAD exporter)"))
    cases.append(Case(here("solid_header_binary.stl"), "hand", 12, 8, math.sqrt(3)))
    write_bytes(here("two_solids.stl"),
                stl_ascii("bottom", tris[:6]) + stl_ascii("top", tris[6:] + (0, 0, 2)))
    both = np.vstack([tris[:6].reshape(-1, 3), (tris[6:] + (0, 0, 2)).reshape(-1, 3)])
    cases.append(Case(here("two_solids.stl"), "hand", 12, distinct_positions(both),
                      bbox_diagonal(both)))
    write_bytes(here("crlf_tabs.stl"), stl_ascii("cube", tris, "\r\n").replace("  ", "\t"))
    cases.append(Case(here("crlf_tabs.stl"), "hand", 12, 8, math.sqrt(3)))
    return cases


def make_off_by_hand(folder):
    cases = []
    here = lambda name: os.path.join(folder, name)  # noqa: E731
    cube = dict(triangles=12, vertices=8, bbox=math.sqrt(3))
    quads = "".join(f"4 {' '.join(map(str, q))}\n" for q in CUBE_QUADS)
    rows = "".join("{} {} {}".format(*v) + f" {i * 30} 90 200 255\n"
                   for i, v in enumerate(CUBE_V.tolist()))
    write_bytes(here("coff.off"), "COFF\n# a cube with colours\n8 6 12\n" + rows + quads)
    cases.append(Case(here("coff.off"), "hand", **cube))
    plain = "".join("{} {} {}\n".format(*v) for v in CUBE_V.tolist())
    commented = quads.replace("\n", "  # a face\n", 2)
    write_bytes(here("comments.off"),
                "OFF\n# made by hand\n\n# counts next\n8 6 0\n\n" + plain + "# faces\n"
                + commented)
    cases.append(Case(here("comments.off"), "hand", **cube,
                      known={"assimp": "assimp takes the `# faces` line between the vertices "
                                       "and the faces for a face (a quad lost)"}))
    write_bytes(here("counts_on_keyword_line.off"), "OFF 8 6 0\n" + plain + quads)
    cases.append(Case(here("counts_on_keyword_line.off"), "hand", **cube))
    face_colours = "".join(line.rstrip() + " 255 0 0\n" for line in quads.splitlines())
    write_bytes(here("face_colours.off"), "OFF\n8 6 0\n" + plain + face_colours)
    cases.append(Case(here("face_colours.off"), "hand", **cube))
    return cases


MAKERS = [make_trimesh, make_pymeshlab, make_blender, make_gltf_by_hand,
          make_collada_by_hand, make_ply_by_hand, make_obj_by_hand, make_stl_by_hand,
          make_off_by_hand]


# ---------------------------------------------------------------------------------------------
# The readers: Pappus and its peers, each giving a Reading.
# ---------------------------------------------------------------------------------------------

@dataclass
class Reading:
    triangles: int | None = None
    vertices: int | None = None
    bbox: float | None = None
    error: str | None = None
    repairs: dict = field(default_factory=dict)
    notes: str = ""


def read_pappus(binary, path):
    try:
        run = subprocess.run([binary, "info", "--json", path], capture_output=True, text=True,
                             timeout=PAPPUS_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return Reading(error=f"timed out after {PAPPUS_TIMEOUT_S} s")
    stderr = run.stderr.strip()
    if run.returncode != 0:
        return Reading(error=stderr or f"exit status {run.returncode} and no message")
    info = json.loads(run.stdout)
    triangles = sum((int(n) - 2) * count for n, count in info["face_sizes"].items())
    repairs = {k: v for k, v in info["repairs"].items() if v}
    return Reading(triangles, info["vertices"] - repairs.get("added_vertices", 0),
                   info["bbox_diag"], repairs=repairs, notes=stderr)


def peer_reading(points, faces, triangles=None):
    """A peer's arrays as a Reading: triangles, distinct referenced positions, bbox."""
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    used = np.asarray(points, dtype=np.float64).reshape(-1, 3)[np.unique(faces)] \
        if len(faces) else np.zeros((0, 3))
    return Reading(len(faces) if triangles is None else triangles, distinct_positions(used),
                   bbox_diagonal(used))


def read_trimesh(path):
    mesh = trimesh.load(path, force="mesh", process=False)
    if not hasattr(mesh, "faces"):
        return Reading(0, 0, 0.0, notes=f"not a mesh: {type(mesh).__name__}")
    return peer_reading(mesh.vertices, mesh.faces)


def read_pycollada(path):
    import collada
    from collada.polylist import BoundPolylist
    from collada.triangleset import BoundTriangleSet
    document = collada.Collada(path, ignore=[collada.common.DaeUnsupportedError,
                                             collada.common.DaeBrokenRefError])
    if document.scene is None:
        return Reading(0, 0, 0.0, notes="no scene")
    points = []
    for geometry in document.scene.objects("geometry"):
        for primitive in geometry.primitives():
            if isinstance(primitive, BoundPolylist):
                primitive = primitive.triangleset()
            if isinstance(primitive, BoundTriangleSet) and len(primitive):
                points.append(primitive.vertex[primitive.vertex_index].reshape(-1, 3))
    points = np.vstack(points) if points else np.zeros((0, 3))
    return peer_reading(points, np.arange(len(points)))


def read_assimp(path):
    """`assimp info` (its default post-processing triangulates): faces only, its vertices being
    joined by every attribute, not by position."""
    run = subprocess.run(["assimp", "info", path], capture_output=True, text=True,
                         timeout=PEER_TIMEOUT_S)
    faces = re.search(r"^Faces:\s+(\d+)", run.stdout, re.M)
    if run.returncode != 0 or not faces:
        lines = (run.stderr + run.stdout).strip().splitlines()
        error = next((l for l in lines if "ERROR" in l or "rror" in l), lines[-1] if lines else "")
        return Reading(error=error.strip()[:200] or f"exit status {run.returncode}")
    return Reading(int(faces.group(1)))


def read_blender(paths, folder):
    """Blender's importers, one Blender for all the files, started again past one that kills
    it."""
    listing = os.path.join(folder, "blender-import.txt")
    results = os.path.join(folder, "blender-import.jsonl")
    readable = [p for p in paths if os.path.splitext(p)[1].lower() != ".off"]
    done = {}
    while readable:
        with open(listing, "w") as f:
            f.write("\n".join(readable))
        open(results, "w").close()
        run = subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "3",
                              "--python", os.path.abspath(__file__), "--", "--blender-import",
                              listing, results],
                             capture_output=True, text=True, timeout=1800, env=blender_env())
        with open(results) as f:
            records = [json.loads(line) for line in f if line.strip()]
        if run.returncode == 3:
            # This script failed inside Blender (an importer's failure is caught and recorded,
            # a crash is a signal): no file is Blender's fault.
            why = (run.stdout + run.stderr).strip().splitlines()
            print(f"  (Blender's import failed: {why[-3] if len(why) > 2 else why})")
            return {}
        for r in records:
            done[r["path"]] = (Reading(error=r["error"]) if "error" in r else
                               Reading(r["triangles"], r["vertices"], r["bbox"]))
        if len(records) == len(readable):
            break
        crashed = readable[len(records)]
        done[crashed] = Reading(error="Blender crashed importing it")
        readable = readable[len(records) + 1:]
    for name in (listing, results):
        os.remove(name)
    return done


def describe(reading):
    """`12t 8v bbox 1.73205 repairs {...}`, or the error."""
    if reading.error is not None:
        return reading.error
    parts = [f"{reading.triangles}t"]
    if reading.vertices is not None:
        parts.append(f"{reading.vertices}v")
    if reading.bbox is not None:
        parts.append(f"bbox {reading.bbox:.6g}")
    if reading.repairs:
        parts.append(f"repairs {reading.repairs}")
    return " ".join(parts)


def guarded(reader, path):
    try:
        return reader(path)
    except Exception as e:  # noqa: BLE001 - a peer that throws could not read the file
        text = str(e).strip().splitlines()
        return Reading(error=f"{type(e).__name__}: {text[-1] if text else ''}"[:200])


# ---------------------------------------------------------------------------------------------
# Judging.
# ---------------------------------------------------------------------------------------------

def names_cause(message, path):
    """Whether a refusal names the file and says something after it (not a panic)."""
    if "panicked" in message or "RUST_BACKTRACE" in message:
        return False
    name = re.escape(os.path.basename(path))
    return re.search(name + r"[^\n]*:\s*\S", message) is not None


def judge(case, pappus, peers):
    """(verdict, detail) for one file: `opened`, `refused-by-name` or `mismatch`."""
    primary = [p for p in peers.values() if p.error is None and p.triangles is not None]
    order = ["pycollada", "trimesh", "assimp", "blender"]
    first = next((peers[n] for n in order if n in peers and peers[n].error is None), None)
    ref_t = case.triangles if case.triangles is not None else (first and first.triangles)
    ref_v = case.vertices if case.vertices is not None else (first and first.vertices)
    ref_b = case.bbox if case.bbox is not None else (first and first.bbox)
    if pappus.error is not None:
        readers = [n for n, p in peers.items()
                   if p.error is None and p.triangles and n not in case.known]
        if names_cause(pappus.error, case.path) and (case.unsupported or not readers
                                                     or ref_t == 0):
            why = (f"documented: {case.unsupported}" if case.unsupported else
                   "no surface" if ref_t == 0 else "no peer reads it either")
            return "refused-by-name", why
        if ref_t is None and not primary:
            return "mismatch", "Pappus refused and nothing says what the file holds"
        return "mismatch", ("Pappus refused (" + ("a panic" if "panicked" in pappus.error else
                            "no cause named" if not names_cause(pappus.error, case.path)
                            else "read by " + ", ".join(readers)) + ")")
    problems = []
    if ref_t is not None and pappus.triangles != ref_t:
        problems.append(f"triangles {pappus.triangles} ≠ {ref_t}")
    if ref_v is not None and "vertices" not in case.known and pappus.vertices != ref_v:
        problems.append(f"vertices {pappus.vertices} ≠ {ref_v}")
    if ref_b and "bbox" not in case.known and not math.isclose(pappus.bbox, ref_b,
                                                               rel_tol=1e-4, abs_tol=1e-5):
        problems.append(f"bbox diagonal {pappus.bbox:.6g} ≠ {ref_b:.6g}")
    if problems:
        return "mismatch", "; ".join(problems)
    return "opened", (f"(documented unsupported, read all the same: {case.unsupported})"
                      if case.unsupported else "")


def peer_column(case, peers):
    """`trimesh 12, assimp 12!, blender ✗` — `!` differs from the reference, `*` differs for a
    reason the corpus gives, `✗` could not read it."""
    first = next((p for p in peers.values() if p.error is None), None)
    ref = case.triangles if case.triangles is not None else first and first.triangles
    ref_bbox = case.bbox if case.bbox is not None else first and first.bbox
    parts = []
    for name, p in peers.items():
        if p.error is not None:
            parts.append(f"{name} ✗" + ("*" if name in case.known else ""))
            continue
        differs = (ref is not None and p.triangles != ref) or (
            ref_bbox and p.bbox is not None
            and not math.isclose(p.bbox, ref_bbox, rel_tol=1e-4, abs_tol=1e-5))
        mark = ("*" if name in case.known else "!") if differs else ""
        parts.append(f"{name} {p.triangles}{mark}")
    return ", ".join(parts)


# ---------------------------------------------------------------------------------------------

def option(name, default=None):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


USE_BLENDER = shutil.which("blender") is not None and "--no-blender" not in sys.argv
USE_ASSIMP = shutil.which("assimp") is not None and "--no-assimp" not in sys.argv


def find_pappus():
    given = option("--pappus")
    if given:
        return given if os.path.exists(given) else None
    for target in TARGETS:
        for profile in ("release", "debug"):
            path = os.path.join(target, profile, "pappus")
            if os.path.exists(path):
                return os.path.abspath(path)
    return None


def main():
    start = time.perf_counter()
    out = option("--out") or tempfile.mkdtemp(prefix="pappus-corpus-")
    only = option("--only")
    pappus = find_pappus()
    print(f"corpus in {out}; Pappus: {pappus or 'none found (peers only)'}; "
          f"Blender: {'yes' if USE_BLENDER else 'no'}; assimp: {'yes' if USE_ASSIMP else 'no'}")
    cases = []
    for maker in MAKERS:
        folder = os.path.join(out, maker.__name__.removeprefix("make_"))
        os.makedirs(folder, exist_ok=True)
        cases += maker(folder)
    if only:
        cases = [c for c in cases if only in os.path.relpath(c.path, out)]
    made = time.perf_counter()
    peers = {c.path: {} for c in cases}
    for c in cases:
        ext = os.path.splitext(c.path)[1].lower()
        if ext == ".dae":
            peers[c.path]["pycollada"] = guarded(read_pycollada, c.path)
        peers[c.path]["trimesh"] = guarded(read_trimesh, c.path)
        if USE_ASSIMP:
            peers[c.path]["assimp"] = guarded(read_assimp, c.path)
    if USE_BLENDER:
        blender = read_blender([c.path for c in cases], out)
        for path, reading in blender.items():
            peers[path]["blender"] = reading
    read = time.perf_counter()
    tally = {}
    counts = {"opened": 0, "refused-by-name": 0, "mismatch": 0}
    for c in cases:
        name = os.path.relpath(c.path, out)
        column = peer_column(c, peers[c.path])
        if not pappus:
            print(f"{'(peers)':<16} {name:<46} writer {c.triangles}t {c.vertices}v | {column}")
            continue
        p = read_pappus(pappus, c.path)
        verdict, detail = judge(c, p, peers[c.path])
        counts[verdict] += 1
        fmt = os.path.splitext(c.path)[1].lower().lstrip(".")
        tally.setdefault(fmt, {k: 0 for k in counts})[verdict] += 1
        said = (f"Pappus {p.triangles}t {p.vertices}v" if p.error is None
                else "Pappus refused")
        print(f"{verdict:<16} {name:<46} {said} | writer {c.triangles}t {c.vertices}v | "
              f"{column}{'  ' + detail if detail else ''}")
        if verdict == "mismatch" or p.error is not None:
            message = p.error if p.error is not None else p.notes
            for line in (message or "").splitlines()[-3:]:
                line = line.strip()[:300]
                print(f"{'':<17}{line if line.startswith('pappus') else 'pappus: ' + line}")
            if p.error is None:
                print(f"{'':<17}pappus: {describe(p)}")
            for peer, r in peers[c.path].items():
                if r.error is not None or verdict == "mismatch":
                    print(f"{'':<17}{peer}: {describe(r)}")
        for what, why in c.known.items():
            print(f"{'':<17}known ({what}): {why}")
    if pappus:
        print()
        print(f"{'format':<8} {'opened':>8} {'refused':>8} {'mismatch':>9}")
        for fmt, row in sorted(tally.items()):
            print(f"{fmt:<8} {row['opened']:>8} {row['refused-by-name']:>8} {row['mismatch']:>9}")
        print()
    done = time.perf_counter()
    print(f"{len(cases)} files: made in {made - start:.0f} s, peers {read - made:.0f} s, "
          f"Pappus {done - read:.0f} s")
    if pappus:
        print(f"opened {counts['opened']}, refused by name {counts['refused-by-name']}, "
              f"mismatched {counts['mismatch']}")


if __name__ == "__main__":
    main()
