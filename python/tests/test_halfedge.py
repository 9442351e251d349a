"""Tests of the halfedge structure from Python: `Mesh.connectivity()`'s arrays, checked against
the halfedge invariants and against `Mesh.faces`, on closed, bounded and polygonal meshes; the
element handles, their circulators and ids, stale after the edits that remove them; quantities
against their formulas and the command line's; positions in; a PLY's vertex quality kept."""

import os
import pickle
import subprocess
import warnings
from pathlib import Path

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


# --- Quantities out, positions in -------------------------------------------------------------


def corner_angles(vertices, faces):
    """Each triangle's corner angles (radians), M×3, in float64."""
    p = vertices.astype(np.float64)[faces]
    angles = []
    for k in range(3):
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        cos = np.einsum("ij,ij->i", a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
        angles.append(np.arccos(np.clip(cos, -1, 1)))
    return np.stack(angles, axis=1)


def test_quantities_are_their_formulas():
    mesh = pappus.load("shape:torus")
    mesh.triangulate()
    vertices, faces = mesh.arrays()
    c = mesh.connectivity()
    n = len(vertices)
    valence = np.bincount(c.from_vertex, minlength=n)
    np.testing.assert_array_equal(mesh.quantity("valence"), valence)
    lengths = np.linalg.norm(vertices[c.to_vertex] - vertices[c.from_vertex], axis=1)
    mean_length = np.bincount(c.from_vertex, weights=lengths.astype(np.float64), minlength=n)
    np.testing.assert_allclose(mesh.quantity("edge-length"), mean_length / valence, rtol=1e-6)
    angles = corner_angles(vertices, faces)
    angle_sum = np.bincount(faces.ravel(), weights=angles.ravel(), minlength=n)
    defect = mesh.quantity("angle-defect")
    np.testing.assert_allclose(defect, 2 * np.pi - angle_sum, atol=1e-5)
    # Gauss-Bonnet: a torus's angle defects sum to 2πχ = 0.
    assert abs(defect.sum()) < 1e-4
    smallest = np.full(n, np.inf)
    np.minimum.at(smallest, faces.ravel(), np.repeat(angles.min(axis=1), 3))
    np.testing.assert_allclose(mesh.quantity("MIN-ANGLE"), np.degrees(smallest), atol=1e-3)
    for name in ("mean", "gaussian", "max-curvature", "min-curvature"):
        values = mesh.quantity(name)
        assert values.dtype == np.float64 and values.shape == (n,) and np.all(np.isfinite(values))
    assert np.all(mesh.quantity("max-curvature") >= mesh.quantity("min-curvature") - 1e-9)


def test_a_sphere_has_curvature_one_over_its_radius():
    mesh = pappus.load("shape:icosphere:4")
    radius = np.linalg.norm(mesh.vertices, axis=1).mean()
    np.testing.assert_allclose(np.abs(mesh.quantity("mean")), 1 / radius, rtol=0.02)
    np.testing.assert_allclose(mesh.quantity("gaussian"), 1 / radius**2, rtol=0.03)
    # Gauss-Bonnet on a sphere: the defects sum to 4π.
    assert abs(mesh.quantity("angle-defect").sum() - 4 * np.pi) < 1e-4


def test_distance_measures_to_another_mesh():
    near, far = two_triangles(), two_triangles()
    far.vertices = far.vertices + np.array([0, 0, 0.5])
    np.testing.assert_allclose(near.quantity("distance", to=far), 0.5, rtol=1e-6)
    np.testing.assert_array_equal(near.quantity("distance", to=near), 0.0)
    with pytest.raises(ValueError, match="give it as `to=`"):
        near.quantity("distance")
    with pytest.raises(ValueError, match="`to=` is for a quantity that measures to another mesh"):
        near.quantity("valence", to=far)
    with pytest.raises(ValueError, match="`sources=` is for a quantity that starts from vertices"):
        near.quantity("distance", to=far, sources=[0])
    with pytest.raises(ValueError, match="unknown quantity `curl`; known: mean, gaussian"):
        near.quantity("curl")


def test_geodesic_distance_starts_from_the_sources():
    mesh = pappus.load("shape:icosphere:4")
    d = mesh.quantity("geodesic", sources=[0])
    assert d.shape == (len(mesh.vertices),)
    assert abs(d[0]) < 1e-9
    # The unit sphere's farthest point is π away; every vertex within 3 % of π of its arc.
    arc = np.arccos(np.clip(mesh.vertices @ mesh.vertices[0], -1, 1))
    assert abs(d.max() - np.pi) < 0.02 * np.pi
    assert np.max(np.abs(d - arc)) < 0.03 * np.pi
    # A second source (the last row) brings every vertex as near or nearer, within the
    # method's error, and is itself at no distance.
    near = mesh.quantity("geodesic", sources=[0, -1])
    assert np.all(near <= d + 0.03 * np.pi)
    assert abs(near[-1]) < 0.03 * np.pi
    with pytest.raises(ValueError, match="give their rows as `sources=`"):
        mesh.quantity("geodesic")
    with pytest.raises(ValueError, match="out of range"):
        mesh.quantity("geodesic", sources=[len(mesh.vertices)])


def test_vertex_normals_are_the_surfaces():
    mesh = pappus.load("shape:icosphere:3")
    normals = mesh.vertex_normals
    assert normals.dtype == np.float32 and normals.shape == mesh.vertices.shape
    outward = mesh.vertices / np.linalg.norm(mesh.vertices, axis=1, keepdims=True)
    assert np.all(np.einsum("ij,ij->i", normals, outward) > 0.999)
    flat = two_triangles()
    np.testing.assert_allclose(flat.vertex_normals, [[0, 0, 1]] * 4, atol=1e-6)


def test_setting_vertices_moves_every_vertex_as_one_edit():
    mesh = two_triangles()
    before = mesh.vertices
    mesh.vertices = before * 2 + 1
    np.testing.assert_array_equal(mesh.vertices, before * 2 + 1)
    mesh.vertices = (before * 3).astype(np.float16)
    np.testing.assert_array_equal(mesh.vertices, before * 3)
    moved = mesh.vertices
    with pytest.raises(ValueError, match="must be a 4×3 array"):
        mesh.vertices = np.zeros((3, 3))
    with pytest.raises(ValueError, match="vertex row 1 is not finite"):
        mesh.vertices = np.where(np.arange(12).reshape(4, 3) == 4, np.nan, moved)
    np.testing.assert_array_equal(mesh.vertices, moved)
    assert mesh.validate() is None


def pappus_binary():
    """The command line `cargo test` built (in $CARGO_TARGET_DIR, else ./target), or a skip (a
    failure under CI=true, where `.ci/run` builds it before the Python tests)."""
    root = Path(__file__).resolve().parents[2]
    target = Path(os.environ.get("CARGO_TARGET_DIR", root / "target"))
    for profile in ("debug", "release"):
        if (target / profile / "pappus").is_file():
            return target / profile / "pappus"
    if os.environ.get("CI") in ("true", "1"):
        pytest.fail(f"no pappus binary under {target}, and under CI=true a test may not skip")
    pytest.skip(f"no pappus binary under {target}")


@pytest.mark.parametrize("name", ["mean", "gaussian", "angle-defect", "valence", "min-angle"])
def test_a_quantity_is_the_command_lines(tmp_path, name):
    binary = pappus_binary()
    output = tmp_path / "out.ply"
    subprocess.run(
        [binary, "process", "shape:torus", "-o", output, "--quantity", name],
        check=True,
        capture_output=True,
    )
    written = pappus.load(output).vertex_data["quality"]
    mesh = pappus.load("shape:torus")
    np.testing.assert_array_equal(written, mesh.quantity(name).astype(np.float32))


def test_a_plys_quality_is_kept_by_vertex_through_edits_and_pickles(tmp_path):
    path = tmp_path / "quality.ply"
    path.write_text(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty float quality\nelement face 2\n"
        "property list uchar int vertex_indices\nend_header\n"
        "0 0 0 0.5\n1 0 0 1.5\n1 1 0 2.5\n0 1 0 3.5\n3 0 1 2\n3 0 2 3\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = pappus.load(path)
    quality = mesh.vertex_data["quality"]
    assert quality.dtype == np.float32
    np.testing.assert_array_equal(quality, [0.5, 1.5, 2.5, 3.5])
    mesh.split(0, 2)
    after = mesh.vertex_data["quality"]
    np.testing.assert_array_equal(after[:4], [0.5, 1.5, 2.5, 3.5])
    # The split's midpoint takes the mean of its edge's ends.
    assert len(after) == 5 and after[4] == (0.5 + 2.5) / 2
    back = pickle.loads(pickle.dumps(mesh))
    np.testing.assert_array_equal(back.vertex_data["quality"], after)
    assert len(two_triangles().vertex_data) == 0


# --- Every operation one way: mesh.run ---------------------------------------------------------


def test_run_takes_handles_and_says_what_it_made():
    mesh = pappus.load("shape:icosphere:1")
    edge = mesh.edge(0)
    a, b = edge.vertices()
    out = mesh.run("split", edge)
    assert isinstance(out, pappus.Outcome) and isinstance(out, str)
    assert out.startswith("new vertex v")
    made = {type(x).__name__: [] for x in out.created}
    for x in out.created:
        made[type(x).__name__].append(x)
    assert len(made["Vertex"]) == 1 and len(made["Face"]) == 2 and len(made["Edge"]) == 3
    new = made["Vertex"][0]
    assert new.valence == 4 and {n.row for n in new.neighbours()} >= {a.row, b.row}
    # A flip follows on the new vertex, which has no input number.
    spoke = next(h.edge for h in new.outgoing() if h.to_vertex not in (a, b))
    flipped = mesh.run("flip", spoke)
    assert flipped.created == [] and flipped.removed == []
    assert new.valence == 3
    assert mesh.validate() is None


def test_a_collapse_says_what_it_removed():
    mesh = pappus.load("shape:icosphere:1")
    a, b = mesh.edge(3).vertices()
    out = mesh.collapse(a.row, b.row)
    kinds = sorted(type(x).__name__ for x in out.removed)
    assert kinds.count("Vertex") == 1 and kinds.count("Face") == 2 and kinds.count("Edge") == 3
    assert out.created == []
    gone = next(x for x in out.removed if isinstance(x, pappus.Vertex))
    assert gone in (a, b)
    with pytest.raises(pappus.StaleElement, match=f"{gone.id} is gone"):
        gone.position


def test_a_whole_mesh_operation_keeps_no_record_and_ends_the_handles_it_rewrote():
    mesh = pappus.load("shape:icosphere:1")
    vertex, face = mesh.vertex(3), mesh.face(3)
    out = mesh.run("loop", levels=1)
    assert out.created is None and out.removed is None and out.endswith("320 faces")
    assert vertex.valence == 5
    with pytest.raises(pappus.StaleElement, match=f"{face.id} is gone"):
        face.row


def test_run_reads_parameters_by_their_declared_names():
    for step, name, elements, parameters in [
        ("simplify:0.25", "simplify", (), {"ratio": 0.25}),
        ("simplify:0.25:8", "simplify", (), {"ratio": 0.25, "distance": 8}),
        ("smooth:cotan:3", "smooth", (), {"method": "cotan", "iterations": 3}),
        ("remesh:2:auto", "remesh", (), {"iterations": 2, "length": None}),
        ("catmull-clark:1", "catmull_clark", (), {}),
        ("flip:0,42", "flip", ((0, 42),), {}),
        ("extrude:0,42,44:0.5", "extrude", ((0, 42, 44),), {"distance": 0.5}),
    ]:
        by_step, by_run = pappus.load("shape:icosphere:2"), pappus.load("shape:icosphere:2")
        summary = by_step.step(step)
        assert by_run.run(name, *elements, **parameters).split(" in ")[0] == summary.split(" in ")[0]
        np.testing.assert_array_equal(by_run.vertices, by_step.vertices)
        assert [list(f) for f in by_run.faces] == [list(f) for f in by_step.faces], step


def test_run_refuses_clearly_and_changes_nothing():
    mesh = pappus.load("shape:icosphere:1")
    other = pappus.load("shape:icosphere:1")
    before = mesh.vertices
    with pytest.raises(ValueError, match="no operation is called `twirl`; known: triangulate"):
        mesh.run("twirl")
    with pytest.raises(ValueError, match="flip needs"):
        mesh.run("flip")
    with pytest.raises(ValueError, match="must be a number from"):
        mesh.run("simplify", ratio=2)
    with pytest.raises(ValueError, match="simplify has no parameter `faces`; it takes ratio"):
        mesh.run("simplify", faces=10)
    with pytest.raises(ValueError, match="must be one of uniform"):
        mesh.run("smooth", method="swirl")
    with pytest.raises(ValueError, match="is an element of another mesh"):
        mesh.run("flip", other.edge(0))
    with pytest.raises(ValueError, match="an element is a handle"):
        mesh.run("flip", 1.5)
    with pytest.raises(pappus.Refused, match="share no edge"):
        mesh.run("flip", (0, 11))
    edge = mesh.edge(0)
    a, b = edge.vertices()
    mesh.run("collapse", edge)
    gone = a if not _alive(a) else b
    with pytest.raises(pappus.StaleElement, match="is gone"):
        mesh.run("dissolve", gone)
    assert len(mesh.vertices) == len(before) - 1 and mesh.validate() is None


def declared_default(parameter):
    """A declared parameter's default as a Python keyword would give it (None for auto)."""
    return None if parameter["default"] == "auto" else parameter["default"]


def test_every_declared_operation_runs_by_name_with_its_declared_keywords():
    for op in pappus.operations():
        if op["names"] != "mesh":
            continue
        keywords = {p["name"].lower(): declared_default(p) for p in op["parameters"]}
        mesh = pappus.load("shape:icosphere:2")
        if op["name"] == "refine":
            mesh.run("simplify")  # refining moves back along a simplification
        if op["name"] == "fill-holes":
            with pytest.raises(pappus.Refused, match="no hole"):
                mesh.run(op["name"], **keywords)
            continue
        out = mesh.run(op["name"], **keywords)
        assert isinstance(out, pappus.Outcome) and mesh.validate() is None, op["name"]


def test_the_stubs_name_the_declared_parameters_with_their_defaults():
    """Each hand-written method of the stubs that is a declared operation (`_` for `-`; the
    simplification by faces is `simplify`'s `faces`, the parameterization `param`) takes
    keywords that are that operation's declared parameters, with the declared defaults."""
    import ast

    stub = ast.parse((Path(pappus.__file__).parent / "__init__.pyi").read_text())
    mesh_class = next(n for n in stub.body if isinstance(n, ast.ClassDef) and n.name == "Mesh")
    declared = {}
    for op in pappus.operations():
        for p in op["parameters"]:
            declared.setdefault(op["name"], {})[p["name"].lower()] = declared_default(p)
    aliases = {"parameterize": ["param"], "simplify": ["simplify", "simplify-faces"]}
    checked = 0
    for method in mesh_class.body:
        if not isinstance(method, ast.FunctionDef):
            continue
        names = aliases.get(method.name, [method.name.replace("_", "-")])
        if not any(n in declared for n in names):
            continue
        args = method.args
        with_defaults = list(zip(args.args[len(args.args) - len(args.defaults) :], args.defaults))
        for arg, default in with_defaults:
            if arg.arg in ("b", "fair"):
                continue  # an edge's second end; fill's choice as a flag
            owners = [n for n in names if arg.arg in declared.get(n, {})]
            assert owners, f"{method.name}({arg.arg}) is no declared parameter of {names}"
            value = ast.literal_eval(default)
            if method.name != "simplify":  # its ratio and faces default to None: one of two
                assert value == declared[owners[0]][arg.arg], (method.name, arg.arg)
            checked += 1
    assert checked >= 10


def every_id(mesh):
    """The ids of every element of `mesh`, by handles over every row."""
    c = mesh.connectivity()
    kinds = [
        (mesh.vertex, len(c.vertex_halfedge)),
        (mesh.halfedge, len(c.next)),
        (mesh.edge, len(c.edge_halfedge)),
        (mesh.face, len(c.face_halfedge)),
    ]
    return {handle(row).id for handle, count in kinds for row in range(count)}


@pytest.mark.parametrize(
    "name, element, parameters",
    [
        ("split", lambda m: m.edge(5), {}),
        ("bisect", lambda m: m.edge(5), {}),
        ("collapse", lambda m: m.edge(5), {}),
        ("dissolve", lambda m: m.edge(5), {}),
        ("dissolve", lambda m: m.vertex(5), {}),
        ("extrude", lambda m: m.face(5), {"distance": 0.2}),
        ("inset", lambda m: [m.face(4), m.face(5)], {"amount": 0.3}),
        ("bevel", lambda m: m.vertex(5), {}),
        ("erase", lambda m: m.face(5), {}),
        ("split-face", lambda m: (m.face(5).vertices()[0].row, m.face(5).vertices()[2].row), {}),
    ],
)
def test_created_and_removed_are_what_the_edit_changed(name, element, parameters):
    mesh = pappus.load("shape:cube")
    before = every_id(mesh)
    out = mesh.run(name, element(mesh), **parameters)
    after = every_id(mesh)
    assert {x.id for x in out.created} == after - before, name
    assert {x.id for x in out.removed} == before - after, name
    assert mesh.validate() is None


def test_a_plys_other_vertex_properties_are_kept_and_saved(tmp_path):
    path = tmp_path / "scan.ply"
    path.write_text(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty float confidence\nproperty uchar intensity\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 0.5 10\n1 0 0 0.25 20\n1 1 0 1 30\n0 1 0 0 40\n3 0 1 2\n3 0 2 3\n"
    )
    mesh = pappus.load(path)
    assert list(mesh.vertex_data) == ["confidence", "intensity"]
    np.testing.assert_array_equal(mesh.vertex_data["confidence"], [0.5, 0.25, 1, 0])
    np.testing.assert_array_equal(mesh.vertex_data["intensity"], [10, 20, 30, 40])
    mesh.save(tmp_path / "again.ply")
    again = pappus.load(tmp_path / "again.ply")
    np.testing.assert_array_equal(again.vertex_data["intensity"], [10, 20, 30, 40])
    with pytest.warns(UserWarning, match="other vertex properties"):
        mesh.save(tmp_path / "scan.obj")


def test_a_plys_face_properties_and_a_scripts_face_array_travel(tmp_path):
    path = tmp_path / "labelled.ply"
    path.write_text(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
        "property uchar label\nproperty float quality\nend_header\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 7 0.5\n3 0 2 3 9 -1\n"
    )
    mesh = pappus.load(path)
    assert list(mesh.face_data) == ["label", "quality"]
    np.testing.assert_array_equal(mesh.face_data["label"], [7, 9])
    np.testing.assert_array_equal(mesh.face_data["quality"], [0.5, -1])
    # A flip keeps both faces, and their values.
    mesh.flip(_inner_edge(mesh))
    np.testing.assert_array_equal(np.sort(mesh.face_data["label"]), [7, 9])
    # A split's new faces take the value of the face they were cut from.
    out = mesh.split(_inner_edge(mesh))
    made = [x for x in out.created if isinstance(x, pappus.Face)]
    labels = mesh.face_data["label"]
    assert len(made) == 2 and sorted(labels) == [7, 7, 9, 9]
    mesh.save(tmp_path / "again.ply")
    np.testing.assert_array_equal(pappus.load(tmp_path / "again.ply").face_data["label"], labels)
    back = pickle.loads(pickle.dumps(mesh))
    np.testing.assert_array_equal(back.face_data["quality"], mesh.face_data["quality"])
    with pytest.warns(UserWarning, match="face properties"):
        mesh.save(tmp_path / "labelled.obj")
    with pytest.raises(ValueError, match="one value per face"):
        mesh.face_data["label"] = [1, 2]
    for name in ["vertex_indices", "texcoord", "two words", ""]:
        with pytest.raises(ValueError, match="PLY"):
            mesh.face_data[name] = labels
    assert isinstance(mesh.face_data, pappus.ElementData) and "face" in repr(mesh.face_data)


def _inner_edge(mesh):
    """The one edge of a two-triangle square that is not on its boundary."""
    (edge,) = [h.edge for h in mesh.face(0).halfedges() if not h.edge.is_boundary]
    return edge


def test_a_face_array_follows_each_face_to_its_children_in_subdivision():
    mesh = pappus.load("shape:icosphere:2")
    mesh.face_data["parent"] = np.arange(len(mesh.faces))
    mesh.face_data["some"] = np.where(np.arange(len(mesh.faces)) % 2 == 0, 1.0, np.nan)
    mesh.loop()
    # Loop cuts each triangle in four, listed one after another in the old face order; every
    # child reads the face its centroid lies on before, its parent.
    children = np.arange(len(mesh.faces)) // 4
    np.testing.assert_array_equal(mesh.face_data["parent"], children)
    # A face without a value gives its children none.
    assert np.isnan(mesh.face_data["some"][children % 2 == 1]).all()
    assert (mesh.face_data["some"][children % 2 == 0] == 1).all()
    quads = pappus.load("shape:torus")
    sides = np.array([len(f) for f in quads.faces])
    quads.face_data["parent"] = np.arange(len(sides))
    quads.catmull_clark()
    np.testing.assert_array_equal(quads.face_data["parent"], np.repeat(np.arange(len(sides)), sides))


def test_an_outcome_pickles_as_its_summary():
    mesh = pappus.load("shape:icosphere:2")
    out = mesh.simplify(ratio=0.5)
    back = pickle.loads(pickle.dumps(out))
    assert back == out and type(back) is str
    assert isinstance(mesh.split(mesh.edge(0)), pappus.Outcome)


def test_a_scripts_vertex_array_travels_through_a_split_a_loop_level_and_a_ply(tmp_path):
    mesh = pappus.load("shape:icosphere:1")
    heights = mesh.vertices[:, 2].astype(np.float64)
    mesh.vertex_data["height"] = heights
    assert "height" in mesh.vertex_data and list(mesh.vertex_data) == ["height"]
    np.testing.assert_array_equal(mesh.vertex_data["height"], heights.astype(np.float32))
    h = mesh.edge(0).halfedge
    a, b = h.from_vertex, h.to_vertex
    ends = (a.position[2], b.position[2])
    (made,) = [x for x in mesh.split(mesh.edge(0)).created if isinstance(x, pappus.Vertex)]
    # The midpoint of the split edge: the mean of its ends.
    assert mesh.vertex_data["height"][made.row] == pytest.approx(sum(ends) / 2, abs=1e-6)
    mesh.loop()
    carried = mesh.vertex_data["height"]
    # The vertices kept keep their values (though Loop moved them, by up to 0.05 here); the
    # new ones read the surface before under them, where the height was interpolated
    # linearly: within an edge's sag of their own height.
    assert carried[a.row] == np.float32(ends[0]) and not np.isnan(carried).any()
    assert np.abs(carried - mesh.vertices[:, 2]).max() < 0.1
    path = tmp_path / "heights.ply"
    mesh.save(path)
    np.testing.assert_array_equal(pappus.load(path).vertex_data["height"], carried)
    with pytest.raises(ValueError, match="one value per vertex"):
        mesh.vertex_data["height"] = heights
    # A vertex without a value keeps none through an edit that moves it.
    lonely = np.zeros(len(mesh.vertices))
    lonely[0] = np.nan
    mesh.vertex_data["lonely"] = lonely
    mesh.smooth()
    assert np.isnan(mesh.vertex_data["lonely"][0])
    # A name a PLY would read back as something else is refused.
    for name in ["x", "nz", "red", "u", "texture_v", "two words", ""]:
        with pytest.raises(ValueError, match="PLY"):
            mesh.vertex_data[name] = lonely
    del mesh.vertex_data["height"]
    assert 3 not in mesh.vertex_data and mesh.vertex_data.get("height") is None
    assert np.isnan(mesh.vertex_data.pop("lonely")[0]) and len(mesh.vertex_data) == 0
    mesh.vertex_data.update({"a": lonely, "b": lonely})
    assert list(mesh.vertex_data) == ["a", "b"]
    mesh.vertex_data.clear()
    assert len(mesh.vertex_data) == 0
    with pytest.raises(KeyError):
        mesh.vertex_data["height"]
