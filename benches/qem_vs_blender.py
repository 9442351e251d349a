#!/usr/bin/env python3
"""QEM simplification, Pappus against Blender's Decimate modifier (collapse), side by side in
one run, each result's Hausdorff distance to the input bounded the same way.

For each ratio, runs `pappus process MESH -o OUT simplify:RATIO --json` (release build) and
Blender's Decimate modifier (`COLLAPSE`, the same ratio, triangulated) on the same OBJ, headless
(`blender -b`), and prints the face counts, the times (Pappus's step; Blender's modifier
applied, timed inside Blender) and the symmetric Hausdorff distance of each result to the input
in % of the bounding-box diagonal, bounded to within 0.0005 % by `surface_distance.py`.

Usage: python3 benches/qem_vs_blender.py [MESH] (default: ../shared/models/stanford-bunny.obj)
Needs: Blender on PATH (Debian's `blender` package, 3.4), pip install libigl numpy pymeshlab;
cargo build --release.
"""
import json
import os
import subprocess
import tempfile

from meshlab_common import MESH, run_pappus
from surface_distance import hausdorff_pct, text

# Run inside Blender: import the OBJ, apply a Decimate modifier, export the result as OBJ and
# print the modifier's time as JSON.
BLENDER = r"""
import bpy, json, sys, time
path, ratio, out = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=path)
obj = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = obj
modifier = obj.modifiers.new("decimate", "DECIMATE")
modifier.decimate_type = "COLLAPSE"
modifier.ratio = float(ratio)
modifier.use_collapse_triangulate = True
start = time.perf_counter()
bpy.ops.object.modifier_apply(modifier="decimate")
ms = (time.perf_counter() - start) * 1000
bpy.ops.wm.obj_export(filepath=out, export_selected_objects=True, export_materials=False,
                      export_uv=False, export_normals=False, apply_modifiers=False)
print("RESULT " + json.dumps({"ms": ms, "faces": len(obj.data.polygons)}))
"""


def blender(path, ratio, out):
    """Blender's decimation of `path` to `ratio`, written to `out`: {"ms", "faces"}."""
    result = subprocess.run(["blender", "-b", "--python-expr", BLENDER, "--", path, str(ratio),
                             out], check=True, capture_output=True, text=True)
    line = next(x for x in result.stdout.splitlines() if x.startswith("RESULT "))
    return json.loads(line[len("RESULT "):])


def main():
    with tempfile.TemporaryDirectory() as tmp:
        for ratio in (0.5, 0.25, 0.1):
            ours = os.path.join(tmp, f"pappus-{ratio}.ply")
            report = run_pappus(MESH, ours, f"simplify:{ratio}")
            theirs = os.path.join(tmp, f"blender-{ratio}.obj")
            peer = blender(MESH, ratio, theirs)
            print(f"ratio {ratio}: Pappus {report['result']['faces']} faces in "
                  f"{report['steps'][0]['ms']:.0f} ms, Hausdorff "
                  f"{text(hausdorff_pct(MESH, ours))} % | Blender {peer['faces']} faces in "
                  f"{peer['ms']:.0f} ms, Hausdorff {text(hausdorff_pct(MESH, theirs))} %",
                  flush=True)


if __name__ == "__main__":
    main()
