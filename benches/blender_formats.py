"""Pappus's glTF and COLLADA against Blender, the formats' reference client, both ways.

    blender -b --python benches/blender_formats.py -- [PAPPUS] [MODELS]

PAPPUS is the `pappus` binary (default: $CARGO_TARGET_DIR/release/pappus, else target/), MODELS
the shared models (default ../shared/models). Needs Blender (Debian's `blender` package, 3.4);
CI does not run it. For each shared model it checks, and prints one line:

1. Pappus → Blender: `pappus convert MODEL.obj X.glb`, imported by Blender: as many triangles
   as Pappus wrote (Pappus's triangle count of the model).
2. Blender → Pappus: Blender imports the OBJ, moves the object by a node transform (location
   (1, 2, 3), a quarter turn about z, scale 2), and exports `.glb` and `.dae`; `pappus process`
   reads each and writes OBJ: as many faces as Blender's triangles (glb) or polygons (dae,
   exported without triangulating), a closed model with no
   boundary loop (Blender's split vertices welded), and the bounding box where Blender put it
   (Blender's z-up world turned y-up: (x, y, z) → (x, z, −y)).

3. Objects and materials: Blender imports spot and suzanne as two objects, gives suzanne two
   materials (faces alternating) and spot one, and exports OBJ (with `.mtl`), `.glb` and `.dae`.
   `pappus convert` of the OBJ to OBJ writes every face with the same `o`, `g`, `usemtl`, `s` and
   vertices, and the same `mtllib`; of the `.glb` and `.dae` to OBJ, as many faces under each
   (object, material) as Blender's triangles (glb) or polygons (dae) of it; Pappus's `.glb` of
   Blender's OBJ, imported by Blender, has each material's triangle count.

A closed model whose exported file already has non-manifold edges (Blender's glTF exporter
triangulates, and a quad's diagonal can be an edge already) is noted, not failed. Exits with
status 1 when any check fails.
"""

import json
import os
import subprocess
import sys
import tempfile

import bpy
import numpy

# Debian's Blender 3.4 glTF importer still says `np.bool`, which Debian's NumPy (1.24) removed.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAPPUS = ARGS[0] if ARGS else os.path.join(
    os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release/pappus")
MODELS = ARGS[1] if len(ARGS) > 1 else os.path.join(ROOT, "../shared/models")
NAMES = ["spot", "cow", "fandisk", "homer", "teapot", "suzanne", "beast", "stanford-bunny", "ogre"]


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def scene_triangles():
    """Triangles of every mesh object, as Blender counts them (polygons fanned)."""
    return sum(sum(len(p.vertices) - 2 for p in o.data.polygons)
               for o in bpy.context.scene.objects if o.type == "MESH")


def world_bbox_y_up():
    """The scene's meshes' world bounding box, turned y-up."""
    lo, hi = [float("inf")] * 3, [float("-inf")] * 3
    for o in bpy.context.scene.objects:
        if o.type != "MESH":
            continue
        for v in o.data.vertices:
            x, y, z = o.matrix_world @ v.co
            for k, c in enumerate((x, z, -y)):
                lo[k], hi[k] = min(lo[k], c), max(hi[k], c)
    return lo, hi


def obj_bbox(path):
    lo, hi = [float("inf")] * 3, [float("-inf")] * 3
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                for k, c in enumerate(map(float, line.split()[1:4])):
                    lo[k], hi[k] = min(lo[k], c), max(hi[k], c)
    return lo, hi


def pappus_json(*args):
    out = subprocess.run([PAPPUS, *args, "--json"], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(out.stderr.strip())
    return json.loads(out.stdout)


def obj_faces(path):
    """Each face of an OBJ file with the statements in force: ((o, g, usemtl, s), vertices),
    and the mtllib lines."""
    state, faces, libraries = {"o": None, "g": None, "usemtl": None, "s": None}, [], []
    with open(path) as f:
        for line in f:
            keyword, _, rest = line.strip().partition(" ")
            if keyword in state:
                state[keyword] = rest.strip()
            elif keyword == "mtllib":
                libraries.append(rest.strip())
            elif keyword == "f":
                vertices = tuple(int(c.split("/")[0]) for c in rest.split())
                faces.append((tuple(state.values()), vertices))
    return faces, libraries


def per_object_material(faces):
    """Faces per (object, material) of `obj_faces`' list."""
    counts = {}
    for (o, _, m, _), _ in faces:
        counts[(o, m)] = counts.get((o, m), 0) + 1
    return counts


def blender_per_object_material(triangles):
    """Blender's triangles (or polygons) per (object, material)."""
    counts = {}
    for o in bpy.context.scene.objects:
        if o.type != "MESH":
            continue
        for p in o.data.polygons:
            slot = o.material_slots[p.material_index].name if o.material_slots else None
            key = (o.name, slot)
            counts[key] = counts.get(key, 0) + (len(p.vertices) - 2 if triangles else 1)
    return counts


def check_groups(folder, failures):
    """Check 3 of the module doc; returns the line to print."""
    reset()
    for name in ["spot", "suzanne"]:
        bpy.ops.wm.obj_import(filepath=os.path.join(MODELS, name + ".obj"))
    colours = {"spot": ["Hide"], "suzanne": ["Skin", "Eyes"]}
    for o in list(bpy.context.scene.objects):
        names = colours[o.name.split(".")[0]]
        o.data.materials.clear()
        for m in names:
            o.data.materials.append(bpy.data.materials.get(m) or bpy.data.materials.new(m))
        for p in o.data.polygons:
            p.material_index = p.index % len(names)
    exported = os.path.join(folder, "groups-blender.obj")
    bpy.ops.wm.obj_export(filepath=exported, export_materials=True, export_object_groups=False,
                          export_material_groups=False, export_smooth_groups=True)
    polygons = blender_per_object_material(False)
    triangles = blender_per_object_material(True)
    glb, dae = (os.path.join(folder, "groups-blender." + e) for e in ["glb", "dae"])
    bpy.ops.export_scene.gltf(filepath=glb, export_format="GLB")
    bpy.ops.wm.collada_export(filepath=dae, triangulate=False)
    results = []
    # OBJ → Pappus → OBJ: every face under the same statements.
    back = os.path.join(folder, "groups-back.obj")
    subprocess.run([PAPPUS, "convert", exported, back], check=True, capture_output=True)
    theirs, ours = obj_faces(exported), obj_faces(back)
    same = theirs == ours
    results.append(f"obj {len(ours[0])} faces {'same' if same else 'DIFFER'}")
    if not same:
        failures.append(f"groups: the OBJ round trip changed faces or statements ({len(theirs[0])} → {len(ours[0])})")
    # glb and dae → Pappus → OBJ: faces per (object, material).
    for path, expected in [(glb, triangles), (dae, polygons)]:
        out = path + ".obj"
        subprocess.run([PAPPUS, "convert", path, out], check=True, capture_output=True)
        got = per_object_material(obj_faces(out)[0])
        ext = path.rsplit(".", 1)[1]
        # COLLADA names a material by its symbol (`Skin-material`), not its name.
        if sorted(got.values()) != sorted(expected.values()):
            failures.append(f"groups.{ext}: faces per object and material {got}, Blender {expected}")
        results.append(f"{ext} {len(got)} groups {'ok' if sorted(got.values()) == sorted(expected.values()) else 'DIFFER'}")
    # Pappus's glb of Blender's OBJ, imported by Blender.
    ours_glb = os.path.join(folder, "groups-pappus.glb")
    subprocess.run([PAPPUS, "convert", exported, ours_glb], check=True, capture_output=True)
    reset()
    bpy.ops.import_scene.gltf(filepath=ours_glb)
    per_material = {}
    for (_, m), n in blender_per_object_material(True).items():
        per_material[m] = per_material.get(m, 0) + n
    wanted = {}
    for (_, m), n in triangles.items():
        wanted[m] = wanted.get(m, 0) + n
    if per_material != wanted:
        failures.append(f"groups: Blender read Pappus's glb as {per_material}, expected {wanted}")
    results.append(f"P→B glb {'ok' if per_material == wanted else 'DIFFER'}")
    return "; ".join(results)


def main():
    failures, notes = [], []
    folder = tempfile.mkdtemp(prefix="pappus-blender-")
    print("objects and materials:", check_groups(folder, failures))
    print(f"{'model':<16} {'P→B tris':>17} {'B→P glb faces/loops':>22} {'B→P dae faces/loops':>22} bbox")
    for name in NAMES:
        model = os.path.join(MODELS, name + ".obj")
        if not os.path.exists(model):
            continue
        # 1. Pappus → Blender.
        glb = os.path.join(folder, name + "-pappus.glb")
        subprocess.run([PAPPUS, "convert", model, glb], check=True, capture_output=True)
        info = pappus_json("process", model, "-o", os.path.join(folder, name + "-tri.obj"), "triangulate")
        ours = info["result"]["faces"]
        reset()
        bpy.ops.import_scene.gltf(filepath=glb)
        theirs = scene_triangles()
        if ours != theirs:
            failures.append(f"{name}: Pappus wrote {ours} triangles, Blender read {theirs}")
        # 2. Blender → Pappus.
        reset()
        bpy.ops.wm.obj_import(filepath=model)
        for o in bpy.context.scene.objects:
            o.location = (1.0, 2.0, 3.0)
            o.rotation_euler = (0.0, 0.0, 1.5707963)
            o.scale = (2.0, 2.0, 2.0)
        bpy.context.view_layer.update()
        blender_tris = scene_triangles()
        blender_polygons = sum(len(o.data.polygons) for o in bpy.context.scene.objects if o.type == "MESH")
        lo, hi = world_bbox_y_up()
        closed = pappus_json("info", model)["closed"]
        row = []
        for ext in ["glb", "dae"]:
            path = os.path.join(folder, f"{name}-blender.{ext}")
            try:
                if ext == "glb":
                    bpy.ops.export_scene.gltf(filepath=path, export_format="GLB")
                else:
                    # Polygons as polygons: Blender's triangulation can give a quad's
                    # diagonal twice (a non-manifold edge the reader must repair).
                    bpy.ops.wm.collada_export(filepath=path, triangulate=False)
            except Exception as e:  # Blender built without COLLADA
                row.append(f"no export ({e})"[:22])
                continue
            out = os.path.join(folder, f"{name}-back-{ext}.obj")
            result = pappus_json("process", path, "-o", out)["result"]
            row.append(f"{result['faces']}/{result['boundary_loops']}")
            plo, phi = obj_bbox(out)
            size = max(h - l for l, h in zip(lo, hi))
            off = max(abs(a - b) for a, b in zip(plo + phi, lo + hi)) / size
            expected = blender_tris if ext == "glb" else blender_polygons
            if result["faces"] != expected or off > 1e-5:
                failures.append(f"{name}.{ext}: {result['faces']} faces (Blender {expected}), bbox off by {off:.2e}")
            if closed and result["boundary_loops"] != 0:
                repairs = result["repairs"]
                if repairs["non_manifold_edge_faces"] > 0:
                    # The file itself has an edge in three faces: Blender's triangulation gave
                    # a quad's diagonal that is already an edge. No reader can close that.
                    notes.append(f"{name}.{ext}: {repairs['non_manifold_edge_faces']} faces on "
                                 "non-manifold edges in Blender's file (its triangulation)")
                else:
                    failures.append(f"{name}.{ext}: a closed model came back with {result['boundary_loops']} loops")
        failed = any(f.startswith(name) for f in failures)
        print(f"{name:<16} {ours:>8} / {theirs:<8} {row[0]:>22} {row[1]:>22} {'FAIL' if failed else 'ok'}")
    for n in notes:
        print("note:", n)
    for f in failures:
        print("FAIL:", f)
    print("all checks passed" if not failures else f"{len(failures)} check(s) failed")
    sys.exit(1 if failures else 0)


main()
