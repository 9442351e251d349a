"""Tests of the halfedge structure from Python: `Mesh.connectivity()`'s arrays, checked against
the halfedge invariants and against `Mesh.faces`, on closed, bounded and polygonal meshes."""

import numpy as np
import pytest

import pappus
from test_pappus import MODELS, models, two_triangles


def check_invariants(c, faces, vertex_count):
    """Every invariant the arrays must keep, and each face's cycle against its row of `faces`."""
    nh = len(c.next)
    rows = np.arange(nh)
    for name in ("next", "prev", "twin", "to_vertex", "from_vertex", "edge", "face"):
        array = getattr(c, name)
        assert array.dtype == np.int64 and array.shape == (nh,), name
    np.testing.assert_array_equal(c.twin[c.twin], rows)
    assert not np.any(c.twin == rows)
    np.testing.assert_array_equal(c.next[c.prev], rows)
    np.testing.assert_array_equal(c.prev[c.next], rows)
    np.testing.assert_array_equal(c.edge[c.twin], c.edge)
    np.testing.assert_array_equal(c.to_vertex[c.prev], c.from_vertex)
    np.testing.assert_array_equal(c.from_vertex, c.to_vertex[c.twin])
    np.testing.assert_array_equal(c.face[c.next], c.face)
    assert nh == 2 * len(c.edge_halfedge)
    np.testing.assert_array_equal(c.edge[c.edge_halfedge], np.arange(len(c.edge_halfedge)))
    assert len(c.vertex_halfedge) == vertex_count
    live = c.vertex_halfedge >= 0
    np.testing.assert_array_equal(c.from_vertex[c.vertex_halfedge[live]], np.flatnonzero(live))
    assert len(c.face_halfedge) == len(faces)
    for f, corners in enumerate(faces):
        h, cycle = c.face_halfedge[f], []
        for _ in range(len(corners)):
            assert c.face[h] == f
            cycle.append(c.from_vertex[h])
            h = c.next[h]
        assert h == c.face_halfedge[f], f"face {f} does not close after its corners"
        np.testing.assert_array_equal(cycle, corners)


def test_a_closed_triangle_mesh():
    mesh = pappus.load("shape:icosphere:2")
    c = mesh.connectivity()
    check_invariants(c, mesh.faces, len(mesh.vertices))
    info = mesh.info()
    assert (len(c.vertex_halfedge), len(c.edge_halfedge), len(c.face_halfedge)) == (
        info["vertices"],
        info["edges"],
        info["faces"],
    )
    assert not np.any(c.face < 0)
    # An icosphere's vertices have valence 5 or 6: the fan around each closes within that.
    for v in range(len(c.vertex_halfedge)):
        h, valence = c.vertex_halfedge[v], 0
        while True:
            valence += 1
            h = c.twin[c.prev[h]]
            if h == c.vertex_halfedge[v]:
                break
        assert valence in (5, 6)


def test_the_boundary_is_minus_one_and_a_boundary_vertex_leaves_by_it():
    mesh = two_triangles()
    c = mesh.connectivity()
    check_invariants(c, mesh.faces, 4)
    boundary = np.flatnonzero(c.face == -1)
    assert len(boundary) == 4
    # The boundary loop runs against the faces: 0→3→2→1→0 on this square.
    assert sorted(zip(c.from_vertex[boundary], c.to_vertex[boundary])) == [
        (0, 3),
        (1, 0),
        (2, 1),
        (3, 2),
    ]
    # Every vertex lies on the boundary, so each one's halfedge is its boundary one.
    assert np.all(c.face[c.vertex_halfedge] == -1)
    # An edge's halfedge is an interior one where it has one (here every edge has a face).
    assert np.all(c.face[c.edge_halfedge] >= 0)


def test_quads_and_mixed_polygons():
    cube = pappus.load("shape:cube")
    check_invariants(cube.connectivity(), cube.faces, len(cube.vertices))
    vertices = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0], [3, 0.5, 0]], float
    )
    mesh = pappus.Mesh(vertices, [[0, 1, 2, 3], [1, 4, 5, 2], [4, 6, 5]])
    faces = mesh.faces
    assert isinstance(faces, list)
    check_invariants(mesh.connectivity(), faces, 7)


def test_the_one_ring_from_the_arrays_is_the_one_from_the_faces():
    mesh = pappus.load(str(MODELS / "bunny-disk.obj")) if models() else None
    c = mesh.connectivity()
    faces = mesh.faces
    check_invariants(c, faces, len(mesh.vertices))
    neighbours = [set() for _ in range(len(mesh.vertices))]
    for corners in faces:
        for a, b in zip(corners, np.roll(corners, -1)):
            neighbours[a].add(int(b))
            neighbours[b].add(int(a))
    for v in range(0, len(neighbours), 37):
        start = h = c.vertex_halfedge[v]
        ring = []
        while True:
            ring.append(int(c.to_vertex[h]))
            h = c.twin[c.prev[h]]
            if h == start:
                break
        assert len(ring) == len(set(ring)) and set(ring) == neighbours[v], v


@pytest.mark.parametrize("name", ["stanford-bunny.obj", "fandisk.obj"])
def test_the_shared_models_keep_the_invariants(name):
    mesh = pappus.load(str(MODELS / name)) if models() else None
    check_invariants(mesh.connectivity(), mesh.faces, len(mesh.vertices))


def test_the_arrays_are_a_snapshot():
    mesh = two_triangles()
    before = mesh.connectivity()
    twin = before.twin.copy()
    mesh.flip(0, 2)
    np.testing.assert_array_equal(before.twin, twin)
    after = mesh.connectivity()
    check_invariants(after, mesh.faces, 4)
    assert sorted(map(tuple, np.sort(mesh.faces, axis=1))) == [(0, 1, 3), (1, 2, 3)]
    assert "4 vertices, 10 halfedges, 5 edges, 2 faces" in repr(after)
