#!/usr/bin/env python3
"""As-rigid-as-possible deformation: Pappus against libigl, side by side in one run, on the shared
models. Prints a Markdown table, ready for a README.

The same problem for both, on the same vertices and triangles (read with libigl, unreferenced
vertices removed, positions rounded to f32 as Pappus stores them, and handed to Pappus as arrays,
so that vertex numbers agree):
- anchors: the vertices in the lowest 20 % of the model's height (its longest bounding-box side);
- handle: the vertices in the highest 15 %, moved by 15 % of the height sideways and 5 % up;
- start: the rest pose with the handle moved (libigl's `arap_solve` takes it as its guess U;
  Pappus's `deform` starts there);
- N iterations (default 10) of the spokes energy with cotangent weights
  (`ARAP_ENERGY_TYPE_SPOKES`, Sorkine & Alexa 2007), libigl's `arap_precomputation` +
  `arap_solve` with `max_iter = N`, Pappus's `Mesh.deform("arap", …, iterations=N)`.

Energy: both results are scored by one evaluator here (numpy): cotangent weights from
`igl.cotmatrix` of the rest pose, each vertex's best rotation by SVD of
`sum_j w_ij (p_i - p_j)(p'_i - p'_j)^T` (the sign of the last singular vector flipped when the
determinant is negative), `E = sum_i sum_j w_ij |(p'_i - p'_j) - R_i (p_i - p_j)|^2`. Cotangent
weights of obtuse triangles are negative, so E can be below 0 on meshes with many (homer, the
bunny); the difference of the two energies is given over the starting energy.

Time per iteration: libigl's `arap_solve` time over N (its local step, its right-hand side and
its prefactored solve); Pappus's own measured time per iteration (local step, global step and
Anderson acceleration) from the summary of `deform`, which it times inside the call, after its
factorisation. Neither counts a local step after the last iteration: libigl runs none, and
Pappus's, which checks the last accelerated guess, is the one that measures its final energy. Each the median of
3 runs. The factorisations are listed beside (libigl's `arap_precomputation`, Pappus's
"factored in").

Also checked, from Pappus's result: the anchors did not move (bit for bit) and the handle sits at
its start plus the offset (in f32).

Usage: python3 benches/arap_vs_libigl.py [--iterations N] [MODEL ...]
       (default: spot, cow, homer, fandisk and the Stanford bunny from ../shared/models)
Needs: pip install libigl numpy scipy, and the Pappus package (pip install ./).
"""
import argparse
import os
import re
import statistics
import time

import igl
import numpy as np

import pappus

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = os.path.join(ROOT, "../shared/models")
DEFAULT = ["spot.obj", "cow.obj", "homer.obj", "fandisk.obj", "stanford-bunny.obj"]
RUNS = 3


def load(path):
    """Vertices (float64 holding f32 values) and triangles, unreferenced vertices removed."""
    v, f = igl.read_triangle_mesh(path)
    v, f, _, _ = igl.remove_unreferenced(v, f)
    return v.astype(np.float32).astype(np.float64), f.astype(np.int64)


def problem(v):
    """Anchors, handle and offset (see the module doc)."""
    axis = int(np.argmax(v.max(0) - v.min(0)))
    low, high = v[:, axis].min(), v[:, axis].max()
    height = high - low
    fixed = np.flatnonzero(v[:, axis] < low + 0.2 * height)
    handle = np.flatnonzero(v[:, axis] > high - 0.15 * height)
    side = (axis + 1) % 3
    offset = np.zeros(3)
    offset[side] = 0.15 * height
    offset[axis] = 0.05 * height
    return fixed, handle, offset


def energy(rest, deformed, f):
    """The spokes ARAP energy of `deformed` with its best rotations (see the module doc)."""
    c = igl.cotmatrix(rest, f).tocoo()
    keep = c.row != c.col
    i, j, w = c.row[keep], c.col[keep], c.data[keep]
    e = rest[i] - rest[j]
    d = deformed[i] - deformed[j]
    s = np.zeros((len(rest), 3, 3))
    np.add.at(s, i, w[:, None, None] * e[:, :, None] * d[:, None, :])
    u, _, vt = np.linalg.svd(s)
    r = np.einsum("nji,nkj->nik", vt, u)  # V U^T
    flip = np.linalg.det(r) < 0
    u[flip, :, 2] *= -1
    r[flip] = np.einsum("nji,nkj->nik", vt[flip], u[flip])
    residual = d - np.einsum("nij,nj->ni", r[i], e)
    return float(np.sum(w * np.sum(residual * residual, axis=1)))


def run_libigl(v, f, fixed, handle, offset, iterations):
    b = np.concatenate([fixed, handle]).astype(np.int32)
    bc = v[b].copy()
    bc[len(fixed):] += offset
    start = v.copy()
    start[b] = bc
    factor, solve, result = [], [], None
    for _ in range(RUNS):
        data = igl.ARAPData()
        data.energy = igl.ARAP_ENERGY_TYPE_SPOKES
        data.max_iter = iterations
        t = time.perf_counter()
        igl.arap_precomputation(v, f, 3, b, data)
        factor.append(time.perf_counter() - t)
        t = time.perf_counter()
        result = igl.arap_solve(bc, data, start)
        solve.append(time.perf_counter() - t)
    return result, statistics.median(factor) * 1e3, statistics.median(solve) / iterations * 1e3


def run_pappus(v, f, fixed, handle, offset, iterations):
    factor, per_iteration, result = [], [], None
    for _ in range(RUNS):
        mesh = pappus.Mesh(v.astype(np.float32), f)
        summary = mesh.deform("arap", fixed.tolist(), handle.tolist(), tuple(offset), iterations)
        factor.append(float(re.search(r"factored in ([\d.]+) ms", summary).group(1)))
        per_iteration.append(float(re.search(r"([\d.]+) ms an iteration", summary).group(1)))
        result = mesh.vertices.astype(np.float64)
    if len(result) != len(v):
        return None  # Pappus repaired the mesh (split a non-manifold vertex): not the same problem
    return result, statistics.median(factor), statistics.median(per_iteration)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--iterations", type=int, default=10)
    parser.add_argument("models", nargs="*", default=DEFAULT)
    args = parser.parse_args()
    n = args.iterations
    print(f"| model | vertices | anchors / handle | E start | E Pappus | E libigl "
          f"| (E Pappus - E libigl) / E start | ms/iteration Pappus | libigl | ratio "
          f"| factor ms Pappus | libigl |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name in args.models:
        path = name if os.path.exists(name) else os.path.join(MODELS, name)
        v, f = load(path)
        fixed, handle, offset = problem(v)
        start = v.copy()
        start[handle] += offset
        pappus_run = run_pappus(v, f, fixed, handle, offset, n)
        if pappus_run is None:
            print(f"| {os.path.basename(path)} | skipped: Pappus's loader splits its non-manifold "
                  f"vertices, so the two would not solve the same problem |", flush=True)
            continue
        ours, our_factor, our_iteration = pappus_run
        theirs, their_factor, their_iteration = run_libigl(v, f, fixed, handle, offset, n)
        v32 = v.astype(np.float32)
        assert np.array_equal(ours[fixed].astype(np.float32), v32[fixed]), "anchors moved"
        sent = (v32[handle] + offset.astype(np.float32)).astype(np.float32)
        assert np.allclose(ours[handle].astype(np.float32), sent, rtol=0, atol=1e-6), "handle"
        e0, e1, e2 = energy(v, start, f), energy(v, ours, f), energy(v, theirs, f)
        print(f"| {os.path.basename(path)} | {len(v)} | {len(fixed)} / {len(handle)} | {e0:.4g} "
              f"| {e1:.6g} | {e2:.6g} | {(e1 - e2) / e0:+.1e} | {our_iteration:.2f} | {their_iteration:.2f} "
              f"| {our_iteration / their_iteration:.2f} | {our_factor:.1f} | {their_factor:.1f} |",
              flush=True)
    print(f"\n{n} iterations each; times are medians of {RUNS} runs on this machine.")


if __name__ == "__main__":
    main()
