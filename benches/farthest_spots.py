#!/usr/bin/env python3
"""Where two meshes lie farthest apart: the distinct spots, both ways, over a threshold.

Each mesh is sampled at its vertices and on a barycentric grid in every triangle (`--grid N`
steps a side; 8 gives 42 points a triangle besides the corners), and every sample is measured
against the other mesh (libigl's `point_mesh_squared_distance`). The farthest samples are listed
in % of the first mesh's bounding-box diagonal, one per spot (a sample within 1 % of the diagonal
of one already listed is the same spot), down to `--floor`. `surface_distance.py` gives the
distance itself; this says where it is, and how many places come near it.

Usage: python3 benches/farthest_spots.py INPUT RESULT [--floor PCT] [--grid N] [--spots K]
Needs: pip install numpy pymeshlab libigl.
"""
import argparse

import numpy as np

from surface_distance import read


def samples(v, f, n):
    """The vertices of a mesh and the points of an n-step barycentric grid on each triangle
    (its corners left out: they are vertices)."""
    t = v[f]
    points = [v]
    for i in range(n + 1):
        for j in range(n + 1 - i):
            k = n - i - j
            if (i, j, k).count(0) >= 2:
                continue  # a corner
            points.append((i * t[:, 0] + j * t[:, 1] + k * t[:, 2]) / n)
    return np.concatenate(points)


def spots(points, distance, floor, radius, most):
    """The farthest samples over `floor`, one per spot of `radius`, at most `most`."""
    found = []
    for i in np.argsort(-distance):
        if distance[i] < floor or len(found) >= most:
            break
        if all(np.linalg.norm(points[i] - p) > radius for p, _ in found):
            found.append((points[i], distance[i]))
    return found


def main():
    import igl

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("input")
    parser.add_argument("result")
    parser.add_argument("--floor", type=float, default=0.0, help="least distance listed, %% of the diagonal")
    parser.add_argument("--grid", type=int, default=8)
    parser.add_argument("--spots", type=int, default=12)
    args = parser.parse_args()
    va, fa = read(args.input)
    vb, fb = read(args.result)
    diag = float(np.linalg.norm(va.max(0) - va.min(0)))
    for name, (v, f, w, g) in (("input -> result", (va, fa, vb, fb)),
                               ("result -> input", (vb, fb, va, fa))):
        points = samples(v, f, args.grid)
        d2, _, _ = igl.point_mesh_squared_distance(points, w, g)
        distance = 100 * np.sqrt(np.maximum(d2, 0)) / diag
        print(name)
        for p, d in spots(points, distance, args.floor, 0.01 * diag, args.spots):
            print(f"  {d:.3f} % at ({p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f})")


if __name__ == "__main__":
    main()
