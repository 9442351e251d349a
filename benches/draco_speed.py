"""Reading a Draco-compressed glTF: Pappus (draco-core, pure Rust) against Google's C++ decoder.

    ~/.cache/pappus/peers-venv/bin/python benches/draco_speed.py PAPPUS [MESH] [--runs N]

Writes MESH (default the shared Stanford bunny) as `.glb` with PAPPUS, compresses it with
gltf-transform's `draco` (Google's encoder, as Blender and most pipelines use it; `npm install
@gltf-transform/cli` in ~/.cache/pappus/gltf-transform), then, N times (default 7) in turn:
`pappus info --json` on the compressed file (its `read_ms`, the parse and decode into a soup)
and on the uncompressed one, trimesh's load of the
same file (which decodes with DracoPy, Google's C++ Draco), and DracoPy's decode of the stream
alone. Prints the medians and Pappus's ratio to each.
"""

import json
import os
import statistics
import struct
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNS = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 7
ARGS = [a for i, a in enumerate(sys.argv[1:], 1)
        if not a.startswith("--") and sys.argv[i - 1] != "--runs"]
if not ARGS:
    sys.exit(__doc__)
PAPPUS = ARGS[0]
MESH = ARGS[1] if len(ARGS) > 1 else os.path.join(ROOT, "../shared/models/stanford-bunny.obj")
GLTF_TRANSFORM = os.path.expanduser(
    "~/.cache/pappus/gltf-transform/node_modules/.bin/gltf-transform")


def draco_stream(path):
    """The bytes of the first Draco-compressed primitive's buffer view of a `.glb`."""
    with open(path, "rb") as f:
        data = f.read()
    length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20:20 + length])
    binary = data[20 + length + 8:]
    primitive = document["meshes"][0]["primitives"][0]
    view = document["bufferViews"][primitive["extensions"]["KHR_draco_mesh_compression"]
                                   ["bufferView"]]
    start = view.get("byteOffset", 0)
    return binary[start:start + view["byteLength"]]


def main():
    import DracoPy
    import trimesh
    folder = tempfile.mkdtemp(prefix="pappus-draco-")
    plain, compressed = os.path.join(folder, "mesh.glb"), os.path.join(folder, "draco.glb")
    subprocess.run([PAPPUS, "convert", MESH, plain], check=True, capture_output=True)
    subprocess.run([GLTF_TRANSFORM, "draco", plain, compressed], check=True,
                   capture_output=True)
    stream = draco_stream(compressed)
    times = {"pappus": [], "plain": [], "trimesh": [], "dracopy": []}
    for _ in range(RUNS):
        for key, path in [("pappus", compressed), ("plain", plain)]:
            out = subprocess.run([PAPPUS, "info", "--json", path], check=True,
                                 capture_output=True, text=True)
            times[key].append(json.loads(out.stdout)["read_ms"])
        start = time.perf_counter()
        mesh = trimesh.load(compressed, force="mesh", process=False)
        times["trimesh"].append((time.perf_counter() - start) * 1e3)
        start = time.perf_counter()
        decoded = DracoPy.decode(stream)
        times["dracopy"].append((time.perf_counter() - start) * 1e3)
    median = {k: statistics.median(v) for k, v in times.items()}
    print(f"{os.path.basename(MESH)}: {len(decoded.faces)} triangles, {len(decoded.points)} "
          f"points; {os.path.getsize(plain)} bytes as .glb, {os.path.getsize(compressed)} "
          f"with Draco; trimesh read {len(mesh.faces)} triangles; medians of {RUNS}:")
    print(f"  Pappus read (parse, decode, weld) {median['pappus']:8.1f} ms")
    print(f"  Pappus read of the uncompressed   {median['plain']:8.1f} ms")
    print(f"  trimesh load (DracoPy inside)     {median['trimesh']:8.1f} ms   "
          f"Pappus / trimesh {median['pappus'] / median['trimesh']:.2f}")
    print(f"  DracoPy decode of the stream      {median['dracopy']:8.1f} ms   "
          f"Pappus / DracoPy {median['pappus'] / median['dracopy']:.2f}")


if __name__ == "__main__":
    main()
