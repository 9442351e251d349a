#!/usr/bin/env python3
"""Loop subdivision, Pappus against MeshLab (pymeshlab), side by side in one run.

Runs `pappus process MESH -o OUT loop:1 --json` (release build) and pymeshlab's
`meshing_surface_subdivision_loop` (Loop weights, one iteration, threshold 0 so every edge is
split) on the same input, and prints both times and how far the two results are apart: for
every vertex of one, the distance to the nearest vertex of the other, as a percentage of the
bounding-box diagonal (max and 99th percentile), split into interior vertices of valence 6
(where the course's weights, 3/(8n), and Loop's original ones, which MeshLab uses, coincide),
other interior vertices, and boundary vertices.

Usage: python3 benches/loop_vs_meshlab.py [MESH]   (default: ../shared/models/stanford-bunny.obj)
Needs: pip install pymeshlab numpy scipy; cargo build --release.
"""
import os
import tempfile
import time

import numpy as np
import pymeshlab
from scipy.spatial import cKDTree

from meshlab_common import MESH, meshset, run_pappus


def pappus(mesh, out):
    return run_pappus(mesh, out, "loop:1")["steps"][0]["ms"]


def meshlab(mesh, out):
    ms = meshset(mesh)
    start = time.perf_counter()
    ms.meshing_surface_subdivision_loop(loopweight="Loop", iterations=1,
                                        threshold=pymeshlab.PercentageValue(0.0))
    ms_time = (time.perf_counter() - start) * 1000
    ms.save_current_mesh(out)
    return ms_time


def load(path):
    ms = meshset(path)  # kept alive while its mesh is read
    m = ms.current_mesh()
    return m.vertex_matrix(), m.face_matrix()


def valences_and_boundary(v, f):
    """Each vertex's valence, and whether it is on the boundary (on an edge with one face)."""
    sides = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    edges, uses = np.unique(sides, axis=0, return_counts=True)
    valence = np.bincount(edges.ravel(), minlength=len(v))
    boundary = np.zeros(len(v), dtype=bool)
    boundary[edges[uses == 1].ravel()] = True
    return valence, boundary


def main():
    with tempfile.TemporaryDirectory() as tmp:
        a_path, b_path = os.path.join(tmp, "pappus.ply"), os.path.join(tmp, "meshlab.ply")
        t_pappus = pappus(MESH, a_path)
        t_meshlab = meshlab(MESH, b_path)
        (va, fa), (vb, fb) = load(a_path), load(b_path)
    diag = np.linalg.norm(va.max(0) - va.min(0))
    d, _ = cKDTree(vb).query(va)
    pct = 100 * d / diag
    val, boundary = valences_and_boundary(va, fa)
    regular = (val == 6) & ~boundary
    print(f"input: {MESH}")
    print(f"Pappus : {len(va)} vertices, {len(fa)} faces in {t_pappus:.1f} ms")
    print(f"MeshLab: {len(vb)} vertices, {len(fb)} faces in {t_meshlab:.1f} ms")
    groups = [
        ("all", np.ones_like(regular)),
        ("valence 6", regular),
        ("other", ~regular & ~boundary),
        ("boundary", boundary),
    ]
    for label, mask in groups:
        if mask.any():
            print(f"{label:>10}: {mask.sum():7d} vertices, distance to MeshLab's nearest vertex: "
                  f"max {pct[mask].max():.2e} %, p99 {np.percentile(pct[mask], 99):.2e} % of the diagonal")


if __name__ == "__main__":
    main()
