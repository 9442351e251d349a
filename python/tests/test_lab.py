"""Lab mode from Python (`pappus.lab`): the hand-written flip and split of
python/examples/halfedge_edits.py, checked against `flip` and `split` on copies of the mesh, are
the same each time; a flip with a mistake is reported by what is wrong (the first difference, or
the broken rule naming the element by the mesh's own id, or the exception), and the mesh itself
never changes."""

import importlib.util
from pathlib import Path

import pytest

import pappus
from test_pappus import MODELS, models

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "halfedge_edits.py"
spec = importlib.util.spec_from_file_location("halfedge_edits", EXAMPLE)
edits = importlib.util.module_from_spec(spec)
spec.loader.exec_module(edits)


def interior_edges(mesh, step):
    """Every `step`th interior edge."""
    rows = range(0, len(mesh.connectivity().edge_halfedge), step)
    return [mesh.edge(r) for r in rows if not mesh.edge(r).is_boundary]


def unchanged(mesh):
    """What must not change: the arrays and every element's id."""
    vertices, faces = mesh.arrays()
    c = mesh.connectivity()
    ids = [mesh.halfedge(h).id for h in range(len(c.next))]
    return vertices.tolist(), [list(f) for f in faces], c.next.tolist(), ids


@pytest.mark.parametrize("source", ["shape:icosphere:2", "spot.obj"])
def test_the_examples_flip_and_split_are_pappus_own(source):
    if source.endswith(".obj") and models():
        source = str(MODELS / source)
    mesh = pappus.load(source)
    before = unchanged(mesh)
    same = 0
    for edge in interior_edges(mesh, 1 + mesh.info()["faces"] // 40):
        for name, function in [("flip", edits.flip), ("split", edits.split)]:
            report = pappus.lab(mesh, name, function, edge)
            assert report.verdict in ("same", "both-refused"), str(report)
            assert report.reference == name
            same += report.same
    assert same >= 40
    assert unchanged(mesh) == before


def flip_the_other_way(mesh, edge):
    """Turns the edge clockwise: a valid mesh, but the two faces hold each other's triangles."""
    h = edge.halfedge
    t = h.twin
    h1, t1 = h.next, t.next
    h2, t2 = h1.next, t1.next
    a, b = h.from_vertex, h.to_vertex
    c, d = h1.to_vertex, t1.to_vertex
    f, g = h.face, t.face
    a_out, b_out = a.halfedge == h, b.halfedge == t
    with mesh.edit() as e:
        e.set_to_vertex(h, d)
        e.set_to_vertex(t, c)
        for x, y in [(h, t2), (t2, h1), (h1, h), (t, h2), (h2, t1), (t1, t)]:
            e.set_next(x, y)
        e.set_face(t2, f)
        e.set_face(h2, g)
        e.set_halfedge(f, h)
        e.set_halfedge(g, t)
        if a_out:
            e.set_halfedge(a, t1)
        if b_out:
            e.set_halfedge(b, h1)


def flip_forgetting_a_face(mesh, edge):
    """The example's flip, with `h1` left on its old face."""
    f = edge.halfedge.face
    h1 = edge.halfedge.next
    edits.flip(mesh, edge)
    with mesh.edit() as e:
        e.set_face(h1, f)


def test_a_flip_with_a_mistake_is_told_what_is_wrong_and_the_mesh_is_as_it_was():
    mesh = pappus.load("shape:icosphere:2")
    edge = interior_edges(mesh, 1)[5]
    h = edge.halfedge
    before = unchanged(mesh)
    report = pappus.lab(mesh, "flip", flip_the_other_way, edge)
    assert report.verdict == "different", str(report)
    assert report.detail.startswith(f"{h.face.id}: corners "), report.detail
    assert str(report).startswith("valid, but not what flip makes: ")
    report = pappus.lab(mesh, "flip", flip_forgetting_a_face, edge)
    assert report.verdict == "invalid", str(report)
    wings = [h, h.next, h.prev, h.twin, h.twin.next, h.twin.prev]
    assert any(report.detail.startswith(f"{x.id}: ") for x in wings), report.detail
    assert str(report).endswith("; the mesh is as it was")

    def raises(mesh, edge):
        raise ValueError(f"not yet written ({edge.id})")

    report = pappus.lab(mesh, "flip", raises, edge)
    assert report.verdict == "raised"
    assert report.detail.startswith("ValueError: not yet written (e")
    assert not report.same
    assert unchanged(mesh) == before


def test_a_copy_is_the_functions_only_while_it_runs_and_bad_calls_are_refused():
    mesh = pappus.load("shape:icosphere:1")
    kept = []

    def keeps(copy, edge):
        kept.append((copy, edge))
        edits.flip(copy, edge)

    edge = interior_edges(mesh, 1)[0]
    assert pappus.lab(mesh, "flip", keeps, edge).same
    copy, handle = kept[0]
    with pytest.raises(pappus.StaleElement):
        handle.halfedge
    with pytest.raises(ValueError, match="no operation is called `flop`"):
        pappus.lab(mesh, "flop", edits.flip, edge)
    with pytest.raises(ValueError):
        pappus.lab(mesh, "flip", edits.flip, mesh.vertex(0))
    with mesh.edit():
        with pytest.raises(RuntimeError, match="edit"):
            pappus.lab(mesh, "flip", edits.flip, edge)
    boundary = pappus.load("shape:grid")
    rim = next(boundary.edge(r) for r in range(8) if boundary.edge(r).is_boundary)
    report = pappus.lab(boundary, "flip", edits.flip, rim)
    assert report.verdict in ("both-refused", "raised"), str(report)
