"""glTF in Pappus beside its OBJ and beside trimesh, in one process, on the same mesh.

    python3 benches/gltf_vs_peers.py [MESH] [--runs N]

Needs the `pappus` package (`pip install ./`), `trimesh` and numpy. On the bunny (default) it
writes MESH as `.glb` and `.obj` with Pappus, then prints the median of N runs (default 5), each
tool in turn so that the machine's drift touches all alike, of:
- Pappus reading (`pappus.load`: parse and build the halfedge mesh; and the parse alone,
  `read_ms`) the `.glb` and the `.obj`, and writing (`Mesh.save`) each;
- trimesh reading the same `.glb` (`trimesh.load(path, force="mesh")`: triangle arrays, no
  halfedges) and writing it (`export`).
"""

import os
import statistics
import sys
import tempfile
import time

import pappus
import trimesh

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNS = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 5
ARGS = [a for i, a in enumerate(sys.argv[1:], 1)
        if not a.startswith("--") and sys.argv[i - 1] != "--runs"]
MESH = ARGS[0] if ARGS else os.path.join(ROOT, "../shared/models/stanford-bunny.obj")


def timed(fn):
    start = time.perf_counter()
    result = fn()
    return (time.perf_counter() - start) * 1000, result


def main():
    folder = tempfile.mkdtemp(prefix="pappus-gltf-")
    mesh = pappus.load(MESH)
    glb, obj = os.path.join(folder, "m.glb"), os.path.join(folder, "m.obj")
    mesh.save(glb)
    mesh.save(obj)
    rows = {k: [] for k in ["load glb", "read glb", "load obj", "read obj", "save glb",
                            "save obj", "trimesh load glb", "trimesh save glb"]}
    for _ in range(RUNS):
        for ext, path in [("glb", glb), ("obj", obj)]:
            ms, loaded = timed(lambda: pappus.load(path))
            rows[f"load {ext}"].append(ms)
            rows[f"read {ext}"].append(loaded.info()["read_ms"])
            out = os.path.join(folder, f"out.{ext}")
            rows[f"save {ext}"].append(timed(lambda: loaded.save(out))[0])
        ms, tm = timed(lambda: trimesh.load(glb, force="mesh"))
        rows["trimesh load glb"].append(ms)
        rows["trimesh save glb"].append(timed(lambda: tm.export(os.path.join(folder, "t.glb")))[0])
    median = {k: statistics.median(v) for k, v in rows.items()}
    info = mesh.info()
    print(f"{os.path.basename(MESH)}: {info['vertices']} vertices, {info['faces']} faces; "
          f".glb {os.path.getsize(glb) / 1e6:.1f} MB, .obj {os.path.getsize(obj) / 1e6:.1f} MB")
    for key, ms in median.items():
        print(f"  {key:<18} {ms:8.1f} ms")
    print(f"  Pappus glb load / obj load:      {median['load glb'] / median['load obj']:.2f}")
    print(f"  Pappus glb save / obj save:      {median['save glb'] / median['save obj']:.2f}")
    print(f"  Pappus glb load / trimesh load:  {median['load glb'] / median['trimesh load glb']:.2f}")
    print(f"  Pappus glb read / trimesh load:  {median['read glb'] / median['trimesh load glb']:.2f}")


if __name__ == "__main__":
    main()
