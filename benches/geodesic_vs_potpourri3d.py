#!/usr/bin/env python3
"""Geodesic distance by the heat method: Pappus's `geodesic` quantity against potpourri3d's
`MeshHeatMethodDistanceSolver` (geometry-central), side by side in one run, on the same
triangles: the shared models by default.

For each model, Pappus loads it (`pappus.load`, triangulated where it has polygons) and both
libraries get exactly its vertices and triangles; the source is vertex row 0. Printed: the
largest difference between the two distances as a share of potpourri3d's largest distance, and
the median of 5 runs of each one-shot computation in milliseconds — for Pappus
`mesh.quantity("geodesic", sources=[0])` (the mesh's tables read, both systems built and
factored, solved), for potpourri3d the solver built (its two factorizations) and
`compute_distance(0)`. Two potpourri3d solvers: its default `use_robust=True`, the same
method as Pappus's (heat time t = h², h the mean edge length, lumped mass, the cotangent
Laplacian of the intrinsic Delaunay triangulation, Sharp & Crane 2020), which stays right on
meshes whose obtuse, non-Delaunay triangles make the plain cotangent heat flow negative; and
`use_robust=False`, the cotangent Laplacian of the mesh's own triangles.

Usage: python3 benches/geodesic_vs_potpourri3d.py [MODEL ...]
Needs: the Pappus package (pip install ./), potpourri3d and numpy.
"""
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import potpourri3d as pp3d

import pappus

ROOT = Path(__file__).resolve().parents[1]
MODELS = ["stanford-bunny", "spot", "fandisk", "cow", "homer", "bunny-disk", "suzanne"]


def median_ms(run, repeat=5):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = run()
        times.append((time.perf_counter() - start) * 1000)
    return statistics.median(times), result


def compare(path):
    mesh = pappus.load(str(path))
    faces = mesh.faces
    if not isinstance(faces, np.ndarray) or faces.shape[1] != 3:
        mesh.triangulate()
        faces = mesh.faces
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    ours_ms, ours = median_ms(lambda: mesh.quantity("geodesic", sources=[0]))
    reached = np.isfinite(ours)
    row = [len(faces), ours_ms]
    for robust in (False, True):
        theirs_ms, theirs = median_ms(
            lambda: pp3d.MeshHeatMethodDistanceSolver(
                vertices, faces, use_robust=robust
            ).compute_distance(0)
        )
        largest = float(np.max(theirs[reached]))
        worst = float(np.max(np.abs(ours[reached] - theirs[reached]))) / largest
        row += [100 * worst, theirs_ms, ours_ms / theirs_ms]
    return row + [int((~reached).sum())]


def main():
    paths = [Path(p) for p in sys.argv[1:]] or [
        ROOT / ".." / "shared" / "models" / f"{name}.obj" for name in MODELS
    ]
    print("| model | triangles | Pappus ms | vs plain: largest difference | plain ms | ratio "
          "| vs robust: largest difference | robust ms | ratio | unreached |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for path in paths:
        if not path.exists():
            print(f"| {path.stem} | missing | | | | | | | | |")
            continue
        tri, ms, d0, ms0, r0, d1, ms1, r1, unreached = compare(path)
        print(f"| {path.stem} | {tri} | {ms:.1f} | {d0:.3f} % | {ms0:.1f} | {r0:.2f} "
              f"| {d1:.3f} % | {ms1:.1f} | {r1:.2f} | {unreached} |")


if __name__ == "__main__":
    main()
