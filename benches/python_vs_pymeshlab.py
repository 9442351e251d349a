"""Pappus from Python beside its own command line and beside pymeshlab, in one process.

    python3 benches/python_vs_pymeshlab.py [MESH] [--runs N]

Needs the `pappus` package (`pip install ./`), `pymeshlab` and numpy, and the release binary
(`cargo build --release`, in CARGO_TARGET_DIR or target/, or the path in $PAPPUS). On the bunny (default) it times:

- simplify to 25 %, remesh (5 iterations, the mean edge length), Loop x1: the Python call
  (`mesh.simplify(0.25)`, …; the mesh loaded fresh before each run, not timed), the same step's
  own time as `pappus process --json` reports it, and pymeshlab's filter on the same mesh;
- the NumPy round trip: `mesh.arrays()` (to NumPy), and `pappus.Mesh(vertices, faces)` (from
  NumPy: the array conversion alone, as `info()["read_ms"]`, and with the entities built), with
  pymeshlab's `vertex_matrix()` / `face_matrix()` and `pymeshlab.Mesh(v, f)` beside them.

Each figure is the median of N runs (default 5), the Python call and the command line
alternating so that the machine's drift touches both alike.
"""

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import pappus
import pymeshlab

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNS = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 5
ARGS = [a for i, a in enumerate(sys.argv[1:], 1)
        if not a.startswith("--") and sys.argv[i - 1] != "--runs"]
MESH = ARGS[0] if ARGS else os.path.join(ROOT, "../shared/models/stanford-bunny.obj")
# The release binary: $PAPPUS if set, else in CARGO_TARGET_DIR (or target/).
PAPPUS = os.environ.get("PAPPUS") or os.path.join(
    os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release/pappus")


def cli_step_ms(step, out):
    """The step's own time as `pappus process MESH -o OUT --json STEP` reports it."""
    result = subprocess.run([PAPPUS, "process", MESH, "-o", out, "--json", step],
                            check=True, capture_output=True, text=True)
    report = json.loads(result.stdout)
    assert report["steps"][0]["outcome"] == "applied", report
    return report["steps"][0]["ms"]


def python_ms(call):
    """One Python call on a freshly loaded mesh, in ms (the load is not timed)."""
    mesh = pappus.load(MESH)
    start = time.perf_counter()
    call(mesh)
    return (time.perf_counter() - start) * 1000


def meshlab_ms(apply):
    """One pymeshlab filter on a freshly loaded mesh (unreferenced vertices dropped, as Pappus
    drops them), in ms."""
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(MESH)
    ms.meshing_remove_unreferenced_vertices()
    start = time.perf_counter()
    apply(ms)
    return (time.perf_counter() - start) * 1000


def median_ms(fn):
    """Median of RUNS timings of `fn`, in ms."""
    return statistics.median(fn() for _ in range(RUNS))


def main():
    base = pappus.load(MESH)
    info = base.info()
    faces, length = info["faces"], info["mean_edge_length"]
    print(f"{os.path.basename(MESH)}: {info['vertices']} vertices, {faces} faces; "
          f"median of {RUNS} runs")
    operations = [
        ("simplify to 25 %", "simplify:0.25", lambda m: m.simplify(0.25),
         lambda ms: ms.meshing_decimation_quadric_edge_collapse(
             targetfacenum=round(faces * 0.25), preserveboundary=True, preservenormal=True)),
        ("remesh, 5 iterations", "remesh", lambda m: m.remesh(),
         lambda ms: ms.meshing_isotropic_explicit_remeshing(
             iterations=5, targetlen=pymeshlab.PureValue(length))),
        ("Loop x1", "loop", lambda m: m.loop(),
         lambda ms: ms.meshing_surface_subdivision_loop(
             loopweight="Loop", iterations=1, threshold=pymeshlab.PercentageValue(0.0))),
    ]
    print(f"{'operation':24} {'Python':>10} {'CLI step':>10} {'Py/CLI':>7} {'pymeshlab':>10}")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.ply")
        for name, step, call, apply in operations:
            py, cli = [], []
            for _ in range(RUNS):
                py.append(python_ms(call))
                cli.append(cli_step_ms(step, out))
            py, cli = statistics.median(py), statistics.median(cli)
            ml = median_ms(lambda: meshlab_ms(apply))
            print(f"{name:24} {py:8.1f} ms {cli:7.1f} ms {py / cli:7.3f} {ml:7.1f} ms")

    vertices, faces_array = base.arrays()
    to_numpy = median_ms(lambda: _timed(base.arrays))
    conversions, builds, totals = [], [], []
    for _ in range(RUNS):
        start = time.perf_counter()
        mesh = pappus.Mesh(vertices, faces_array)
        totals.append((time.perf_counter() - start) * 1000)
        built = mesh.info()
        conversions.append(built["read_ms"])
        builds.append(built["build_ms"])
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(MESH)
    ms.meshing_remove_unreferenced_vertices()
    current = ms.current_mesh()
    ml_to = median_ms(lambda: _timed(lambda: (current.vertex_matrix(), current.face_matrix())))
    v64, f32 = vertices.astype(np.float64), faces_array.astype(np.int32)
    ml_from = median_ms(lambda: _timed(lambda: pymeshlab.Mesh(v64, f32)))
    print(f"to NumPy (mesh.arrays())            {to_numpy:6.2f} ms   pymeshlab {ml_to:6.2f} ms")
    print(f"from NumPy: arrays converted         {statistics.median(conversions):6.2f} ms   "
          f"pymeshlab.Mesh(v, f) {ml_from:6.2f} ms")
    print(f"from NumPy: + entities built         {statistics.median(totals):6.2f} ms "
          f"(build {statistics.median(builds):.2f} ms)")


def _timed(fn):
    start = time.perf_counter()
    fn()
    return (time.perf_counter() - start) * 1000


if __name__ == "__main__":
    main()
