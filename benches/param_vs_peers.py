#!/usr/bin/env python3
"""Parameterization: Pappus against libigl and MeshLab (pymeshlab), side by side in one run, on
the shared `bunny-disk.obj` (the bunny above its median height: one boundary loop, 34k faces)
and on a ~45k-face single-loop disk cut from the Stanford bunny here (issue 22's figure). Prints
a Markdown table, ready for a README.

Every time is the median of 5 runs (7 for Pappus), in milliseconds, of the computation alone (no
loading, no writing):

- Pappus: the command line's own step time (`pappus process IN -o OUT.obj --json
  param:METHOD`, the JSON's `ms`; the release build, or the binary named by `PAPPUS`): reading
  the mesh into tables, the cut and topology check, the weights, the boundary on the circle by
  arc length (harmonic) or the two pins (LSCM), the sparse factorization and solve (faer's
  Cholesky), the distortion report, and writing a UV onto every corner of the mesh.
  (`cargo bench --bench param` times the library call alone.)
- libigl (Python package `libigl`): harmonic = `boundary_loop` + `map_vertices_to_circle` +
  `harmonic(V, F, bnd, bnd_uv, 1)` (the cotangent Laplacian, boundary on the circle by arc
  length, as Pappus's); LSCM = `boundary_loop` + two pins (the loop's first vertex and the one
  halfway round, libigl's tutorial) + `lscm`.
- MeshLab (pymeshlab): `compute_texcoord_parametrization_harmonic()` and
  `compute_texcoord_parametrization_least_squares_conformal_maps()` on a freshly loaded MeshSet
  (loading not timed).

Flips: triangles whose UV orientation is opposite to the majority's (so a mirrored layout counts
as 0), for every peer output. Pappus's are its report's (signed UV area <= 0).

The 45k disk: the bunny's faces whose centroid is above the height that keeps ~45k of them, the
largest connected piece, accepted when it is a disk (one boundary loop, manifold boundary,
Euler characteristic 1); otherwise the height moves down a little and it tries again. Written
to a temporary OBJ with full-precision positions.

Usage: python3 benches/param_vs_peers.py [--peers-only]
Needs: pip install libigl pymeshlab numpy; the release build (`cargo build --release`).
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from importlib import metadata

import igl
import numpy as np
import pymeshlab

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = os.path.join(ROOT, "../shared/models")
RUNS = 5
TARGET_FACES = 45_000


def median_ms(work):
    """The median time of RUNS calls of `work()` (ms), and the last result."""
    times, result = [], None
    for _ in range(RUNS):
        start = time.perf_counter()
        result = work()
        times.append((time.perf_counter() - start) * 1000)
    return float(np.median(times)), result


def boundary_loops(f):
    """The boundary loops of triangles `f` (lists of vertices), or None when the boundary is not
    manifold (a vertex starting two boundary edges)."""
    directed = {}
    for a, b, c in f:
        for i, j in ((a, b), (b, c), (c, a)):
            directed[(i, j)] = True
    successor = {}
    for (i, j) in directed:
        if (j, i) not in directed:
            if i in successor:
                return None
            successor[i] = j
    loops, seen = [], set()
    for start in successor:
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen:
            seen.add(v)
            loop.append(v)
            v = successor[v]
        loops.append(loop)
    return loops


def cut_disk(v, f):
    """A single-loop disk of about TARGET_FACES faces cut from (v, f): (V, F, height)."""
    centroid_y = v[f].mean(axis=1)[:, 1]
    quantile = 1.0 - TARGET_FACES / len(f)
    for step in range(40):
        height = np.quantile(centroid_y, max(quantile - 0.002 * step, 0.0))
        keep = f[centroid_y > height]
        _, component, sizes = igl.connected_components(igl.adjacency_matrix(keep))
        # Faces of the vertex-connected piece with the most vertices.
        piece = np.argmax(sizes)
        keep = keep[component[keep[:, 0]] == piece]
        sub_v, sub_f, _, _ = igl.remove_unreferenced(v, keep)
        loops = boundary_loops(sub_f.tolist())
        if loops is None or len(loops) != 1:
            continue
        edges = igl.edges(sub_f)
        if len(sub_v) - len(edges) + len(sub_f) == 1:
            return sub_v, sub_f, height
    sys.exit("could not cut a single-loop disk from the bunny")


def write_obj(path, v, f):
    with open(path, "w") as out:
        out.write("# A disk cut from the Stanford bunny by benches/param_vs_peers.py\n")
        for p in v:
            out.write("v %.17g %.17g %.17g\n" % (p[0], p[1], p[2]))
        for t in f + 1:
            out.write(f"f {t[0]} {t[1]} {t[2]}\n")


def flips(uv, f):
    """Triangles whose UV orientation is against the majority's."""
    a, b, c = uv[f[:, 0]], uv[f[:, 1]], uv[f[:, 2]]
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    positive = int((area > 0).sum())
    return min(positive, len(f) - positive)


def wedge_flips(ms):
    """Flips of pymeshlab's texture coordinates: per wedge (3 per face) where the filter wrote
    them, else per vertex."""
    m = ms.current_mesh()
    if m.has_wedge_tex_coord():
        w = m.wedge_tex_coord_matrix().reshape(-1, 3, 2)
    else:
        w = m.vertex_tex_coord_matrix()[m.face_matrix()]
    area = ((w[:, 1, 0] - w[:, 0, 0]) * (w[:, 2, 1] - w[:, 0, 1])
            - (w[:, 2, 0] - w[:, 0, 0]) * (w[:, 1, 1] - w[:, 0, 1]))
    positive = int((area > 0).sum())
    return min(positive, len(area) - positive)


def libigl_side(path):
    v, f = igl.read_triangle_mesh(path)
    v, f, _, _ = igl.remove_unreferenced(v, f)
    vf = np.asfortranarray(v)

    def harmonic():
        bnd = igl.boundary_loop(f)
        bnd_uv = igl.map_vertices_to_circle(vf, bnd.astype(np.int32))
        return igl.harmonic(v, f, bnd, np.ascontiguousarray(bnd_uv), 1)

    def lscm():
        bnd = igl.boundary_loop(f)
        b = np.array([bnd[0], bnd[len(bnd) // 2]], dtype=np.int64)
        bc = np.array([[0.0, 0.0], [1.0, 0.0]])
        return igl.lscm(v, f, b, bc)[0]

    out = {}
    for name, work in (("harmonic", harmonic), ("lscm", lscm)):
        ms, uv = median_ms(work)
        out[name] = (ms, flips(uv, f))
    return out


def meshlab_side(path):
    out = {}
    for name, filt in (("harmonic", "compute_texcoord_parametrization_harmonic"),
                       ("lscm", "compute_texcoord_parametrization_least_squares_conformal_maps")):
        times, ms = [], None
        for _ in range(RUNS):
            ms = pymeshlab.MeshSet()
            ms.load_new_mesh(path)
            ms.meshing_remove_unreferenced_vertices()
            start = time.perf_counter()
            getattr(ms, filt)()
            times.append((time.perf_counter() - start) * 1000)
        out[name] = (float(np.median(times)), wedge_flips(ms))
    return out


def pappus_binary():
    """The release build (or the binary named by `PAPPUS`)."""
    if os.environ.get("PAPPUS"):
        return os.environ["PAPPUS"]
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.path.join(target, "release", "pappus")


def pappus_side(paths):
    """Times the command line's own `param:METHOD` step on each of `paths` (median of 7 runs of
    `pappus process PATH -o OUT.obj --json param:METHOD`, the step's `ms`: reading the mesh's
    tables, cutting, weights, solve, report, and writing a UV onto every corner):
    {(path, method): record}."""
    binary = pappus_binary()
    records = {}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.obj")
        for path in paths:
            for method in ("harmonic", "lscm", "uniform", "mean-value"):
                times, summary = [], ""
                for _ in range(7):
                    result = subprocess.run(
                        [binary, "process", path, "-o", out, "--json", f"param:{method}"],
                        capture_output=True, text=True)
                    if result.returncode != 0:
                        sys.exit(f"{binary} failed:\n{result.stderr[-4000:]}")
                    step = json.loads(result.stdout)["steps"][0]
                    if step["outcome"] != "applied":
                        sys.exit(f"param:{method} on {path}: {step}")
                    times.append(step["ms"])
                    summary = step["summary"]
                times.sort()
                records[(path, method)] = {
                    "median_ms": times[len(times) // 2],
                    "flipped": int(summary.split(" flipped")[0]),
                    "summary": summary,
                }
    return records


def version(package):
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "?"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--peers-only", action="store_true", help="skip Pappus")
    args = parser.parse_args()
    bunny_disk = os.path.abspath(os.path.join(MODELS, "bunny-disk.obj"))
    v, f = igl.read_triangle_mesh(os.path.join(MODELS, "stanford-bunny.obj"))
    v, f, _, _ = igl.remove_unreferenced(v, f)
    with tempfile.TemporaryDirectory() as tmp:
        disk_v, disk_f, height = cut_disk(v, f)
        disk = os.path.join(tmp, "bunny-disk-45k.obj")
        write_obj(disk, disk_v, disk_f)
        inputs = [("bunny-disk.obj", bunny_disk),
                  (f"bunny above y = {height:.4f} ({len(disk_f)} faces)", disk)]
        pappus = None if args.peers_only else pappus_side([p for _, p in inputs])
        rows = []
        for label, path in inputs:
            faces = len(igl.read_triangle_mesh(path)[1])
            libigl = libigl_side(path)
            meshlab = meshlab_side(path)
            for method in ("harmonic", "lscm"):
                p = pappus.get((path, method)) if pappus else None
                pappus_cell = f"{p['median_ms']:.1f} ({p['flipped']} flips)" if p else "—"
                rows.append([label, str(faces), method, pappus_cell,
                             f"{libigl[method][0]:.1f} ({libigl[method][1]} flips)",
                             f"{meshlab[method][0]:.1f} ({meshlab[method][1]} flips)"])
            if pappus:
                for method in ("uniform", "mean-value"):
                    p = pappus.get((path, method))
                    if p:
                        rows.append([label, str(faces), method,
                                     f"{p['median_ms']:.1f} ({p['flipped']} flips)", "—", "—"])

    print(f"Median of {RUNS} runs (Pappus 7, the step's own time), ms; {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} logical CPUs. libigl {version('libigl')}, pymeshlab "
          f"{version('pymeshlab')}, NumPy {np.__version__}.")
    print()
    print("| Input | faces | method | Pappus | libigl | MeshLab |")
    print("|---|---:|---|---:|---:|---:|")
    for row in rows:
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
