#!/usr/bin/env python3
"""Isotropic remeshing, Pappus against MeshLab (pymeshlab), side by side in one run.

Runs `pappus process MESH -o OUT remesh --json` (release build: 5 iterations, target length the
mean edge length, features at 45 degrees) and pymeshlab's `meshing_isotropic_explicit_remeshing`
with the same iteration count and target length, and measures both results the same way:
the share of triangles with a minimum angle below 30 degrees, the share of interior vertices
of valence 6, the symmetric Hausdorff distance to the input (in % of the bounding-box diagonal:
bounded to within 0.0005 % by `surface_distance.py`, with pymeshlab's sampled figures beside it,
see `meshlab_common.hausdorff_pct`), and the time: the median of RUNS (environment, default 3)
runs of each, taken in turn, with the ratio of the medians (one run varies by a fifth on the
2-core development machine).

Usage: python3 benches/remesh_vs_meshlab.py [MESH] (default: ../shared/models/stanford-bunny.obj)
Needs: pip install pymeshlab numpy libigl; cargo build --release.
"""
import os
import statistics
import tempfile
import time

import numpy as np
import pymeshlab

from meshlab_common import MESH, hausdorff_text, meshset, run_pappus, spread


RUNS = int(os.environ.get("RUNS", "3"))


def load(path):
    ms = meshset(path)  # kept alive while its mesh is read
    m = ms.current_mesh()
    return m.vertex_matrix(), m.face_matrix()


def quality(path):
    """(% triangles with min angle < 30 deg, % interior vertices of valence 6, faces)."""
    v, f = load(path)
    p = v[f]
    angles = []
    for i in range(3):
        a, b, c = p[:, i], p[:, (i + 1) % 3], p[:, (i + 2) % 3]
        u, w = b - a, c - a
        cos = (u * w).sum(1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1) + 1e-30)
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    min_angle = np.min(np.stack(angles, 1), 1)
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), 1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    valence = np.bincount(unique.ravel(), minlength=len(v))
    on_boundary = np.zeros(len(v), bool)
    on_boundary[unique[count == 1].ravel()] = True
    interior = ~on_boundary & (valence > 0)
    return (100 * np.mean(min_angle < 30), 100 * np.mean(valence[interior] == 6), len(f))


def mean_edge_length(path):
    v, f = load(path)
    edges = np.unique(np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), 1), axis=0)
    return float(np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1).mean())


def line(name, path, times=None):
    """The quality of the mesh at `path`, with its distance to the input and the median and
    range of `times` (ms) where given."""
    angle, six, faces = quality(path)
    text = f"{name:8} {faces:7d} faces  {angle:6.3f} % < 30 deg  {six:5.1f} % valence 6"
    if times is not None:
        text += f"  {hausdorff_text(MESH, path)}  {spread(times)}"
    print(text)


def main():
    length = mean_edge_length(MESH)
    print(f"{os.path.basename(MESH)}: 5 iterations, target length {length:.6f} (mean edge length)")
    with tempfile.TemporaryDirectory() as tmp:
        ours = os.path.join(tmp, "pappus.ply")
        theirs = os.path.join(tmp, "meshlab.ply")
        ours_ms, theirs_ms = [], []
        for _ in range(RUNS):
            report = run_pappus(MESH, ours, f"remesh:5:{length}")
            ours_ms.append(report["steps"][0]["ms"])
            ms = meshset(MESH)
            start = time.perf_counter()
            ms.meshing_isotropic_explicit_remeshing(iterations=5,
                                                    targetlen=pymeshlab.PureValue(length))
            theirs_ms.append((time.perf_counter() - start) * 1000)
            ms.save_current_mesh(theirs)
        line("input", MESH)
        line("Pappus", ours, ours_ms)
        line("MeshLab", theirs, theirs_ms)
        ratio = statistics.median(ours_ms) / statistics.median(theirs_ms)
        print(f"time: {ratio:.2f}× MeshLab's (medians of {RUNS} runs each, taken in turn)")


if __name__ == "__main__":
    main()
