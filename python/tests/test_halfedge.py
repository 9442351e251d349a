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


# --- Handles and circulators ------------------------------------------------------------------


def test_handles_read_what_the_arrays_hold():
    mesh = pappus.load("shape:torus")
    c = mesh.connectivity()
    for row in range(0, len(c.next), 7):
        h = mesh.halfedge(row)
        assert h.row == row
        assert (h.next.row, h.prev.row, h.twin.row) == (c.next[row], c.prev[row], c.twin[row])
        assert (h.to_vertex.row, h.from_vertex.row) == (c.to_vertex[row], c.from_vertex[row])
        assert h.edge.row == c.edge[row] and h.face.row == c.face[row]
        assert not h.is_boundary
    for row in range(len(c.vertex_halfedge)):
        assert mesh.vertex(row).halfedge.row == c.vertex_halfedge[row]
    for row in range(len(c.edge_halfedge)):
        assert mesh.edge(row).halfedge.row == c.edge_halfedge[row]
    for row in range(len(c.face_halfedge)):
        assert mesh.face(row).halfedge.row == c.face_halfedge[row]


def test_circulators_walk_the_one_ring_and_the_faces():
    mesh = pappus.load(str(MODELS / "bunny-disk.obj")) if models() else None
    c = mesh.connectivity()
    faces = mesh.faces
    for row in range(0, len(mesh.vertices), 53):
        v = mesh.vertex(row)
        outgoing = [h.row for h in v.outgoing()]
        expected, h = [], c.vertex_halfedge[row]
        while True:
            expected.append(h)
            h = c.twin[c.prev[h]]
            if h == c.vertex_halfedge[row]:
                break
        assert outgoing == expected
        assert [n.row for n in v.neighbours()] == list(c.to_vertex[expected])
        assert [f.row for f in v.faces()] == [f for f in c.face[expected] if f >= 0]
        assert v.valence == len(expected)
        assert v.is_boundary == bool(np.any(c.face[expected] < 0))
    for row in range(0, len(faces), 41):
        f = mesh.face(row)
        assert [v.row for v in f.vertices()] == list(faces[row])
        assert [h.from_vertex.row for h in f.halfedges()] == list(faces[row])
    boundary_edges = 0
    for row in range(len(c.edge_halfedge)):
        e = mesh.edge(row)
        a, b = e.vertices()
        h = c.edge_halfedge[row]
        assert (a.row, b.row) == (c.from_vertex[h], c.to_vertex[h])
        sides = sorted(x for x in (c.face[h], c.face[c.twin[h]]) if x >= 0)
        assert sorted(f.row for f in e.faces()) == sides
        assert e.is_boundary == (len(sides) == 1)
        boundary_edges += e.is_boundary
    assert boundary_edges == np.count_nonzero(c.face < 0)


def test_ids_name_elements_and_handles_compare_by_element():
    mesh = pappus.load("shape:icosphere:1")
    v = mesh.vertex(3)
    assert v.id.startswith("v") and mesh.element(v.id) == v and v == mesh.vertex(3)
    assert v != mesh.vertex(4) and len({v, mesh.vertex(3), mesh.vertex(4)}) == 2
    assert v != mesh.halfedge(3) and repr(v) == f"pappus.Vertex({v.id})"
    for handle in (mesh.halfedge(5), mesh.edge(5), mesh.face(5)):
        again = mesh.element(handle.id)
        assert type(again) is type(handle) and again == handle and again.row == 5
    assert mesh.vertex(-1).row == len(mesh.vertices) - 1
    other = pappus.load("shape:icosphere:1")
    assert other.vertex(3) != v


def test_positions_read_and_write_as_one_edit():
    mesh = two_triangles()
    v = mesh.vertex(2)
    assert v.position == (1.0, 1.0, 0.0)
    v.position = (0.5, 2.0, -1.0)
    np.testing.assert_array_equal(mesh.vertices[2], [0.5, 2.0, -1.0])
    assert v.position == (0.5, 2.0, -1.0)
    with pytest.raises(ValueError, match="finite"):
        v.position = (float("nan"), 0.0, 0.0)
    np.testing.assert_array_equal(mesh.vertices[2], [0.5, 2.0, -1.0])


def test_bad_rows_and_ids_are_clear_errors():
    mesh = two_triangles()
    with pytest.raises(IndexError, match="vertex row 4 is out of range: the mesh has 4"):
        mesh.vertex(4)
    with pytest.raises(IndexError):
        mesh.face(-3)
    with pytest.raises(ValueError, match="no element id"):
        mesh.element("x12")
    with pytest.raises(ValueError, match="names a mesh"):
        mesh.element("m0v0")
    with pytest.raises(pappus.StaleElement, match="v999v0 is gone"):
        mesh.element("v999v0")
    assert issubclass(pappus.StaleElement, pappus.PappusError)


def test_ids_stay_through_a_flip_and_go_with_a_collapse():
    mesh = two_triangles()
    c = mesh.connectivity()
    diagonal = next(
        mesh.edge(e) for e in range(5) if c.face[c.twin[c.edge_halfedge[e]]] >= 0
    )
    corners = {v.row for v in diagonal.vertices()}
    assert corners == {0, 2}
    mesh.flip(0, 2)
    assert {v.row for v in diagonal.vertices()} == {1, 3}
    assert len(diagonal.faces()) == 2

    sphere = pappus.load("shape:icosphere:1")
    a, b = sphere.edge(0).vertices()
    keep = next(sphere.vertex(v) for v in range(12) if v not in (a.row, b.row))
    faces = [sphere.face(f) for f in range(len(sphere.faces))]
    # A shape's input vertex numbers are its rows.
    sphere.collapse(a.row, b.row)
    gone = [x for x in (a, b) if not _alive(x)]
    assert len(gone) == 1
    with pytest.raises(pappus.StaleElement, match=f"{gone[0].id} is gone"):
        gone[0].position
    assert keep.position == tuple(float(x) for x in sphere.vertices[keep.row])
    assert sum(not _alive(f) for f in faces) == 2


def test_subdivision_keeps_vertex_ids_and_ends_the_others():
    mesh = pappus.load("shape:icosphere:1")
    v, f, h = mesh.vertex(7), mesh.face(7), mesh.halfedge(7)
    position = v.position
    mesh.loop()
    assert v.position != position or v.valence == 5
    assert len(v.neighbours()) == v.valence
    for handle in (f, h):
        with pytest.raises(pappus.StaleElement, match=f"{handle.id} is gone"):
            handle.row


def _alive(handle):
    """Whether `handle` still names an element."""
    try:
        handle.row
        return True
    except pappus.StaleElement:
        return False
