"""Checks of `surface_distance.py` on shapes whose distance is known.

    python3 -m pytest benches/test_surface_distance.py   (needs numpy, libigl, pymeshlab)

Not part of CI (its environment has no libigl); run it after changing the bounds.
"""
import numpy as np

from surface_distance import one_sided, point_triangle_distance

SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
SQUARE_FACES = np.array([[0, 1, 2], [0, 2, 3]])


def test_point_triangle_distance_is_the_nearest_of_dense_samples():
    rng = np.random.default_rng(1)
    a, b, c = rng.normal(size=(3, 200, 3))
    p = 2 * rng.normal(size=(200, 3))
    exact = point_triangle_distance(p, a, b, c)
    u, v = np.meshgrid(np.linspace(0, 1, 301), np.linspace(0, 1, 301))
    inside = u + v <= 1
    u, v = u[inside], v[inside]
    for i in range(len(p)):
        samples = a[i] + u[:, None] * (b[i] - a[i]) + v[:, None] * (c[i] - a[i])
        sampled = np.linalg.norm(samples - p[i], axis=1).min()
        # Never farther than a sample, and the grid's step (under 1 % of the sides) away.
        assert exact[i] <= sampled + 1e-12
        assert sampled - exact[i] < 0.02


def test_parallel_squares_are_their_offset_apart():
    low, high = one_sided(SQUARE, SQUARE_FACES, SQUARE + [0, 0, 0.1], SQUARE_FACES, 1e-6)
    assert abs(low - 0.1) < 1e-12 and abs(high - 0.1) < 1e-6


def test_a_square_is_its_far_corner_from_its_half_size_copy_and_that_copy_inside_it():
    low, high = one_sided(SQUARE, SQUARE_FACES, SQUARE * 0.5, SQUARE_FACES, 1e-6)
    assert abs(low - np.sqrt(0.5)) < 1e-12 and high - low <= 1e-6
    assert one_sided(SQUARE * 0.5, SQUARE_FACES, SQUARE, SQUARE_FACES, 1e-6) == (0.0, 0.0)


def test_a_tent_is_its_height_from_its_base():
    tent = np.array([[0, 0, 0], [1, 0, 0], [0.3, 0.9, 0], [0.3, 0.3, 0.5]], float)
    sides = np.array([[0, 1, 3], [1, 2, 3], [2, 0, 3]])
    low, high = one_sided(tent, sides, tent[:3], np.array([[0, 1, 2]]), 1e-6)
    assert abs(low - 0.5) < 1e-12 and high - low <= 1e-6
