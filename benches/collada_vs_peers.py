"""COLLADA reading: Pappus beside pycollada and trimesh, in one process, on the same files.

    python3 benches/collada_vs_peers.py [--runs N] [FILE.dae ...]

Needs the `pappus` package (`pip install ./`), `pycollada`, `trimesh` and numpy. Without FILEs it
writes its own into a temporary folder with pycollada (a writer that is not Pappus's): the
bunny (69 k triangles) and the bunny Loop-subdivided twice by Pappus (1.1 M triangles, the size
of the course's `dragon2.dae` and more), each as one `<triangles>` with normals, placed by a
node with a transform, Z-up, plus the course's own scenes where ../shared/models/course has them.

For each file it prints the median of N runs (default 5), each tool in turn so that the
machine's drift touches all alike:
- Pappus: `pappus.load` (parse, then build the halfedge mesh), and its `read_ms` (the parse
  alone, as `info()` reports it; `info()` itself is not timed);
- pycollada: `collada.Collada(path)` (parse into its object model, arrays as numpy);
- trimesh: `trimesh.load(path)` (pycollada, then a scene of triangle arrays).
and checks that Pappus read the triangles pycollada reads.
"""

import os
import statistics
import sys
import tempfile
import time
import warnings

import collada
import numpy as np
import pappus
import trimesh

# What a file held that Pappus does not read is said with warnings.warn on every load: once is
# enough here.
warnings.simplefilter("once")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = os.path.join(ROOT, "../shared/models")
RUNS = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 5
FILES = [a for i, a in enumerate(sys.argv[1:], 1)
         if not a.startswith("--") and sys.argv[i - 1] != "--runs"]


def write_dae(mesh, path):
    """Writes a Pappus mesh as COLLADA with pycollada: one <triangles> with per-corner normals,
    under a node that scales and moves it, in a Z-up scene."""
    vertices, faces = mesh.arrays()
    vertices = vertices.astype(np.float32)
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
    doc = collada.Collada()
    doc.assetInfo.upaxis = collada.asset.UP_AXIS.Z_UP
    sources = [
        collada.source.FloatSource("p", vertices.ravel(), ("X", "Y", "Z")),
        collada.source.FloatSource("n", normals.astype(np.float32).ravel(), ("X", "Y", "Z")),
    ]
    geometry = collada.geometry.Geometry(doc, "g", "mesh", sources)
    inputs = collada.source.InputList()
    inputs.addInput(0, "VERTEX", "#p")
    inputs.addInput(1, "NORMAL", "#n")
    index = np.empty((len(faces), 3, 2), dtype=np.int64)
    index[:, :, 0] = faces
    index[:, :, 1] = np.arange(len(faces))[:, None]
    geometry.primitives.append(geometry.createTriangleSet(index.ravel(), inputs, ""))
    doc.geometries.append(geometry)
    node = collada.scene.Node("n", [collada.scene.GeometryNode(geometry, [])], transforms=[
        collada.scene.TranslateTransform(1, 2, 3), collada.scene.ScaleTransform(2, 2, 2)])
    scene = collada.scene.Scene("scene", [node])
    doc.scenes.append(scene)
    doc.scene = scene
    doc.write(path)


def median_ms(fn):
    times = []
    for _ in range(RUNS):
        start = time.perf_counter()
        fn()
        times.append((time.perf_counter() - start) * 1000)
    return statistics.median(times)


def pycollada_triangles(path):
    doc = collada.Collada(path)
    return sum(len(p) for g in doc.geometries for p in g.primitives)


def main():
    files = list(FILES)
    folder = tempfile.mkdtemp(prefix="pappus-dae-")
    if not files:
        bunny = os.path.join(MODELS, "stanford-bunny.obj")
        for name, levels in [("bunny", 0), ("bunny-loop2", 2)]:
            mesh = pappus.load(bunny)
            for _ in range(levels):
                mesh.loop()
            path = os.path.join(folder, name + ".dae")
            write_dae(mesh, path)
            files.append(path)
        for name in ["cube.dae", "quadball.dae"]:
            path = os.path.join(MODELS, "course", name)
            if os.path.exists(path):
                files.append(path)
    print(f"{'file':<18} {'MB':>6} {'triangles':>10} {'Pappus load':>12} {'(read)':>8} "
          f"{'pycollada':>10} {'trimesh':>9} {'P/pycollada':>12} {'P/trimesh':>10}")
    for path in files:
        mesh = pappus.load(path)
        triangles = pycollada_triangles(path)
        assert mesh.info()["faces"] == triangles, (path, mesh.info()["faces"], triangles)
        loads, reads = [], []
        for _ in range(RUNS):
            start = time.perf_counter()
            loaded = pappus.load(path)
            loads.append((time.perf_counter() - start) * 1000)
            reads.append(loaded.info()["read_ms"])
            del loaded
        p = statistics.median(loads)
        c = median_ms(lambda: collada.Collada(path))
        t = median_ms(lambda: trimesh.load(path, force="mesh"))
        size = os.path.getsize(path) / 1e6
        print(f"{os.path.basename(path):<18} {size:>6.1f} {triangles:>10} {p:>10.1f}ms "
              f"{statistics.median(reads):>6.1f}ms {c:>8.1f}ms {t:>7.1f}ms "
              f"{p / c:>12.2f} {p / t:>10.2f}")


if __name__ == "__main__":
    main()
