#!/usr/bin/env python3
"""Hole filling: Pappus's faired patches against MeshLab's "close holes" (pymeshlab), side by side
in one run, on the Stanford bunny (5 holes) and on a cap cut from a sphere. Prints a Markdown
table, ready for a README.

- Pappus: `Mesh.fill_holes(fair=True)`: per hole, Liepa's least-bending triangulation, refined
  toward the surrounding edge length, regularised and faired (k = 3).
- MeshLab: `meshing_close_holes(maxholesize=10000, refinehole=True)` (its ear-cutting fill, then
  its refinement to the default edge length; `selfintersection` left on, its default).

For each: the time of the fill alone (median of 3 runs, loading not timed), whether the result is
closed, the new triangles (those not in the input), their edges over the surrounding mean (the mean
length of the input's edges at the holes' rims: min, mean, max, the rim's own edges included), the
share of the edges the filler made (the rims' left out) within ±25 % of that mean, their smallest
angle and how many have one under 20°, and for the sphere the largest distance of a new
triangle's corner from the sphere, over the radius. The bunny's rim edges alone span 0.21–2.32
of the mean, so some of its rim triangles cannot have both sides within ±25 % and angles of 20°.

Usage: python3 benches/holes_vs_meshlab.py    (needs pymeshlab, numpy, and the Pappus package)
"""
import os
import statistics
import tempfile
import time

import numpy as np
import pymeshlab

import pappus

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUNNY = os.path.join(ROOT, "../shared/models/stanford-bunny.obj")
RUNS = 3


def edges_of(faces):
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    return e


def rim_mean(vertices, faces):
    """The mean length of the edges at the vertices of the boundary edges."""
    e = edges_of(faces)
    key = np.sort(e, axis=1)
    unique, counts = np.unique(key, axis=0, return_counts=True)
    rim = np.unique(unique[counts == 1])
    at_rim = np.isin(key[:, 0], rim) | np.isin(key[:, 1], rim)
    undirected = np.unique(key[at_rim], axis=0)
    return float(np.linalg.norm(vertices[undirected[:, 0]] - vertices[undirected[:, 1]], axis=1).mean())


def new_triangles(before_v, before_f, after_v, after_f):
    """Rows of `after_f` whose corners (by position) are not a triangle of the input."""
    def keys(v, f):
        corners = [tuple(map(tuple, v[t])) for t in f]
        return [tuple(sorted(c)) for c in corners]
    old = set(keys(before_v, before_f))
    return np.array([t for t, k in zip(after_f, keys(after_v, after_f)) if k not in old])


def new_edges(before_v, before_f, after_v, triangles):
    """The undirected edges of `triangles` that the input did not have (by position): the
    patches' own edges, without the rims, which no filler changes."""
    key = lambda v, e: tuple(sorted((tuple(v[e[0]]), tuple(v[e[1]]))))
    old = {key(before_v, e) for e in edges_of(before_f)}
    edges = {tuple(sorted(e)) for e in edges_of(triangles)}
    return np.array([e for e in edges if key(after_v, e) not in old]).reshape(-1, 2)


def shape(vertices, triangles, length, added_edges):
    a, b, c = (vertices[triangles[:, i]] for i in range(3))
    sides = np.stack([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                      np.linalg.norm(a - c, axis=1)], axis=1) / length
    new = np.linalg.norm(vertices[added_edges[:, 0]] - vertices[added_edges[:, 1]], axis=1) / length
    within = float(np.mean((new >= 0.75) & (new <= 1.25))) * 100

    def angle(p, q, r):
        u, w = q - p, r - p
        cos = np.sum(u * w, axis=1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1))
        return np.degrees(np.arccos(np.clip(cos, -1, 1)))
    smallest = np.minimum(np.minimum(angle(a, b, c), angle(b, c, a)), angle(c, a, b))
    return sides.min(), sides.mean(), sides.max(), within, smallest.min(), int(np.sum(smallest < 20))


def closed(faces):
    key = np.sort(edges_of(faces), axis=1)
    _, counts = np.unique(key, axis=0, return_counts=True)
    return bool(np.all(counts == 2))


def run_pappus(path_or_arrays):
    times, mesh = [], None
    for _ in range(RUNS):
        mesh = (pappus.load(path_or_arrays) if isinstance(path_or_arrays, str)
                else pappus.Mesh(*path_or_arrays))
        t = time.perf_counter()
        summary = mesh.fill_holes(fair=True)
        times.append(time.perf_counter() - t)
    mesh.validate()
    return mesh.vertices.astype(np.float64), np.asarray(mesh.faces), statistics.median(times), summary


def run_meshlab(vertices, faces):
    times, ms = [], None
    for _ in range(RUNS):
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(vertices, faces))
        t = time.perf_counter()
        ms.meshing_close_holes(maxholesize=10000, refinehole=True)
        times.append(time.perf_counter() - t)
    m = ms.current_mesh()
    return m.vertex_matrix(), m.face_matrix(), statistics.median(times)


def sphere_with_a_cap_cut():
    sphere = pappus.load("shape:icosphere:4")
    v, f = sphere.vertices.astype(np.float64), np.asarray(sphere.faces)
    keep = v[f].mean(axis=1)[:, 1] <= 0.75
    return v.astype(np.float32), f[keep]


def main():
    print("| input | filler | ms | closed | new triangles | edges / rim mean (min, mean, max) "
          "| new edges within ±25 % | smallest angle (triangles under 20°) | off the sphere |")
    print("|---|---|---:|---|---:|---|---:|---:|---:|")
    bunny = pappus.load(BUNNY)
    cases = [("bunny (5 holes)", BUNNY, bunny.vertices, np.asarray(bunny.faces)),
             ("sphere, 41° cap cut",) + (None,) + sphere_with_a_cap_cut()]
    for name, path, v, f in cases:
        v64 = v.astype(np.float64)
        length = rim_mean(v64, f)
        source = path if path else (v, f)
        for filler, (after_v, after_f, seconds) in [
            ("Pappus", run_pappus(source)[:3]),
            ("MeshLab", run_meshlab(v64, f)),
        ]:
            added = new_triangles(v64, f, after_v, after_f)
            lo, mean, hi, within, smallest, thin = shape(
                after_v, added, length, new_edges(v64, f, after_v, added))
            off = ""
            if path is None:
                corners = after_v[np.unique(added)]
                radius = np.linalg.norm(corners, axis=1)
                off = f"{np.abs(radius - 1).max() * 100:.2f} %"
            print(f"| {name} | {filler} | {seconds * 1e3:.1f} | {closed(after_f)} | {len(added)} "
                  f"| {lo:.2f}, {mean:.2f}, {hi:.2f} | {within:.0f} % | {smallest:.1f}° ({thin}) "
                  f"| {off} |", flush=True)


if __name__ == "__main__":
    main()
