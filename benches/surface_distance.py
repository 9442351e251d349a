"""The Hausdorff distance between two triangle meshes, to a stated tolerance and the same
figure every time.

MeshLab's `get_hausdorff_distance` samples the surfaces at random: with a million samples each
way, one file measured 0.139 and 0.158 % of the bunny's diagonal in two calls, the spread of
the differences the remeshing and QEM goals turn on. Here the distance is bounded instead
(branch and bound over the triangles of one mesh):

- the distance from a point to one triangle of the other mesh is a convex function, so over a
  triangle it is largest at a corner; the other mesh is nearer than any of its triangles, so
  the largest of a triangle's corners' distances to one triangle of the other mesh bounds the
  whole triangle's distance (each corner's nearest triangle is tried);
- the distance to a surface is also 1-Lipschitz: no point of a triangle lies farther from it
  than the triangle's farthest corner plus its longest side / sqrt 3 (no point of a triangle
  is farther from its nearest corner);
- the largest distance found at a corner is a lower bound of the one-sided distance; every
  triangle whose upper bound does not pass it by more than the tolerance is dropped, the rest
  are cut into four at their sides' middles, whose distances are measured (libigl's
  `point_mesh_squared_distance`, an AABB tree), until none is left.

The result, in % of the first mesh's bounding-box diagonal, is the larger of the two directions.

Usage: python3 benches/surface_distance.py A B   (needs pip install numpy pymeshlab libigl; its checks:
python3 -m pytest benches/test_surface_distance.py)
"""
import sys

import numpy as np

# The most points measured in one direction; past it the bounds found so far are returned,
# wider than asked (on the fandisk's QEM: about half a minute, the process under 1.4 GB). Only
# where both meshes lie in one plane over large areas, far smaller than their distance elsewhere
# (QEM of the fandisk: 0.0048 %), does that happen: a triangle of one crossing an edge of the
# other's flat region is bounded by its size, not by the flat distance.
MAX_POINTS = 3_000_000


def point_triangle_distance(p, a, b, c):
    """The distance from each point p[i] to the triangle a[i] b[i] c[i] (arrays of shape
    (n, 3)), by the regions of Ericson's "Real-Time Collision Detection" §5.1.5; infinite for
    a triangle too thin to say."""
    ab, ac, ap, bp, cp = b - a, c - a, p - a, p - b, p - c
    dot = lambda x, y: np.einsum("ij,ij->i", x, y)  # noqa: E731
    d1, d2, d3, d4, d5, d6 = dot(ab, ap), dot(ac, ap), dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        total = va + vb + vc
        q = a + ab * (vb / total)[:, None] + ac * (vc / total)[:, None]
        # The regions, the last written the one that holds when several seem to.
        bc = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        q = np.where(bc[:, None], b + (c - b) * t[:, None], q)
        on_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
        q = np.where(on_ac[:, None], a + ac * (d2 / (d2 - d6))[:, None], q)
        q = np.where(((d6 >= 0) & (d5 <= d6))[:, None], c, q)
        on_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
        q = np.where(on_ab[:, None], a + ab * (d1 / (d1 - d3))[:, None], q)
        q = np.where(((d3 >= 0) & (d4 <= d3))[:, None], b, q)
        q = np.where(((d1 <= 0) & (d2 <= 0))[:, None], a, q)
        d = np.linalg.norm(p - q, axis=1)
    return np.where(np.isfinite(d), d, np.inf)


def one_sided(va, fa, vb, fb, tolerance):
    """max over the points p of mesh A of min over mesh B of |p - q|: (lower, upper) bounds,
    upper - lower <= tolerance unless that takes measuring more than MAX_POINTS points."""
    import igl

    def measure(points):
        d2, nearest, _ = igl.point_mesh_squared_distance(points, vb, fb)
        return np.sqrt(np.maximum(d2, 0)), nearest

    def upper_bounds(corners, far, nearest):
        sides = np.stack([np.linalg.norm(corners[:, (i + 1) % 3] - corners[:, i], axis=1)
                          for i in range(3)], 1)
        bound = far.max(1) + sides.max(1) / np.sqrt(3)
        for k in range(3):
            t = vb[fb[nearest[:, k]]]
            worst = np.max([point_triangle_distance(corners[:, j], t[:, 0], t[:, 1], t[:, 2])
                            for j in range(3)], axis=0)
            bound = np.minimum(bound, worst)
        return bound

    d, i = measure(va)
    corners, far, nearest = va[fa], d[fa], i[fa]
    lower = float(far.max(initial=0.0))
    measured = len(va)
    while True:
        upper_of = upper_bounds(corners, far, nearest)
        keep = upper_of > lower + tolerance
        measured += 3 * int(keep.sum())
        if not keep.any() or measured > MAX_POINTS:
            return lower, float(max(lower, upper_of.max(initial=lower)))
        p, f, n = corners[keep], far[keep], nearest[keep]
        m = (p + np.roll(p, -1, axis=1)) / 2  # middle i: corners i and i + 1
        d, i = measure(m.reshape(-1, 3))
        d, i = d.reshape(-1, 3), i.reshape(-1, 3)
        lower = max(lower, float(d.max()))
        corners, far, nearest = _quartered(p, m), _quartered(f, d), _quartered(n, i)


def _quartered(x, y):
    """The values at the corners of the four triangles a triangle is cut into, from its
    corners' values `x` and its sides' middles' `y` (middle i between corners i and i + 1)."""
    return np.concatenate([np.stack([x[:, 0], y[:, 0], y[:, 2]], 1),
                           np.stack([y[:, 0], x[:, 1], y[:, 1]], 1),
                           np.stack([y[:, 2], y[:, 1], x[:, 2]], 1), y])


def read(path):
    """The vertices (float64) and triangles of the mesh at `path`, read by pymeshlab (polygons
    triangulated), unreferenced vertices dropped: the surface itself."""
    from meshlab_common import meshset

    ms = meshset(path)  # kept alive while its mesh is read
    m = ms.current_mesh()
    return np.asarray(m.vertex_matrix(), np.float64), np.asarray(m.face_matrix(), np.int64)


def hausdorff_pct(path_a, path_b, tolerance_pct=0.0005):
    """The symmetric Hausdorff distance between the meshes at `path_a` and `path_b`, as % of
    A's bounding-box diagonal, within `tolerance_pct` of that diagonal: (lower, upper)."""
    va, fa = read(path_a)
    vb, fb = read(path_b)
    diag = float(np.linalg.norm(va.max(0) - va.min(0)))
    tolerance = tolerance_pct * diag / 100
    there = one_sided(va, fa, vb, fb, tolerance)
    back = one_sided(vb, fb, va, fa, tolerance)
    return (100 * max(there[0], back[0]) / diag, 100 * max(there[1], back[1]) / diag)


def text(bounds, tolerance_pct=0.0005):
    """A distance's bounds as the scripts print them: the lower bound, and the upper where the
    two are farther apart than the tolerance."""
    low, high = bounds
    return f"{low:.3f}" if high - low <= tolerance_pct * 1.001 else f"{low:.3f} (≤ {high:.3f})"


if __name__ == "__main__":
    low, high = hausdorff_pct(sys.argv[1], sys.argv[2])
    print(f"Hausdorff {low:.4f} % (at most {high:.4f} %)")
