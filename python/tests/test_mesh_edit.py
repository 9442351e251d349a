"""The checked low-level edit from Python (`with mesh.edit() as e:`): the hand-written flip and
split of python/examples/halfedge_edits.py equal `mesh.flip` and `mesh.split`; a mistake raises
`InvalidMesh` naming the rule with the mesh exactly as it was; nothing else reads the mesh while
an edit is open; setters refuse what is not an element of this mesh."""

import importlib.util
import pickle
from pathlib import Path

import numpy as np
import pytest

import pappus
from test_pappus import MODELS, models

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "halfedge_edits.py"
spec = importlib.util.spec_from_file_location("halfedge_edits", EXAMPLE)
edits = importlib.util.module_from_spec(spec)
spec.loader.exec_module(edits)


def canonical(mesh):
    """The faces as cycles of corner positions, each turned to start at its least, sorted."""
    vertices, faces = mesh.arrays()
    out = []
    for face in faces:
        cycle = [tuple(vertices[v].tolist()) for v in face]
        k = cycle.index(min(cycle))
        out.append(tuple(cycle[k:] + cycle[:k]))
    return sorted(out)


def state(mesh):
    """Everything the arrays say about the mesh, to compare before and after."""
    c = mesh.connectivity()
    names = ["next", "prev", "twin", "to_vertex", "edge", "face", "vertex_halfedge"]
    return [mesh.vertices.tolist()] + [getattr(c, n).tolist() for n in names]


def interior_edges(mesh, stride=1):
    c = mesh.connectivity()
    rows = range(0, len(c.edge_halfedge), stride)
    return [e for e in rows if c.face[c.twin[c.edge_halfedge[e]]] >= 0 and c.face[c.edge_halfedge[e]] >= 0]


@pytest.mark.parametrize("source, stride", [("shape:icosphere:2", 1), ("spot", 41)])
def test_the_flip_by_hand_is_mesh_flip(source, stride):
    if source == "spot":
        source = str(MODELS / "spot.obj") if models() else None
    by_hand, library = pappus.load(source), pappus.load(source)
    compared = 0
    for row in interior_edges(library, stride):
        try:
            library.flip(library.edge(row))
        except pappus.Refused:
            continue
        edits.flip(by_hand, by_hand.edge(row))
        assert canonical(by_hand) == canonical(library), row
        compared += 1
    assert compared > (300 if stride == 1 else 150)
    assert by_hand.validate() is None


def test_the_split_by_hand_is_mesh_split():
    by_hand, library = pappus.load("shape:icosphere:2"), pappus.load("shape:icosphere:2")
    for row in range(0, 480, 9):
        out = library.split(library.edge(row))
        m = edits.split(by_hand, by_hand.edge(row))
        assert canonical(by_hand) == canonical(library), row
        new = next(x for x in out.created if isinstance(x, pappus.Vertex))
        assert m.position == new.position and m.valence == 4
    assert by_hand.validate() is None and len(by_hand.vertices) == len(library.vertices)


def test_a_vertex_made_by_hand_reads_its_vertex_data_off_the_surface_before():
    mesh = pappus.load("shape:icosphere:1")
    mesh.vertex_data["across"] = mesh.vertices[:, 0]
    h = mesh.edge(3).halfedge
    ends = (h.from_vertex.position[0], h.to_vertex.position[0])
    m = edits.split(mesh, mesh.edge(3))
    assert mesh.vertex_data["across"][m.row] == pytest.approx(sum(ends) / 2, abs=1e-6)


def test_a_broken_flip_names_the_rule_and_leaves_the_mesh_as_it_was():
    mesh = pappus.load("shape:icosphere:1")
    before = state(mesh)
    h = mesh.edge(4).halfedge
    t = h.twin
    with pytest.raises(pappus.InvalidMesh, match="rolled back and the mesh is as it was") as raised:
        with mesh.edit() as e:
            e.set_to_vertex(h, t.next.to_vertex)
            e.set_next(h, t.next.next)  # half a flip: the faces no longer close
    assert h.id in str(raised.value) or "h" in str(raised.value)
    assert state(mesh) == before and mesh.validate() is None


def test_an_exception_in_the_block_rolls_back_and_goes_on():
    mesh = pappus.load("shape:icosphere:1")
    before = state(mesh)
    with pytest.raises(KeyError, match="mine"):
        with mesh.edit() as e:
            e.new_face()
            e.set_position(mesh.vertex(0), (9, 9, 9))
            raise KeyError("mine")
    assert state(mesh) == before
    mesh.flip(mesh.edge(0))  # the mesh runs operations again


def test_nothing_reads_the_mesh_whole_while_an_edit_is_open():
    mesh = pappus.load("shape:icosphere:1")
    v, edge = mesh.vertex(0), mesh.edit()
    with edge as e:
        for call in [
            lambda: mesh.flip(mesh.edge(0)),
            lambda: mesh.faces,
            lambda: mesh.connectivity(),
            lambda: mesh.quantity("valence"),
            lambda: pickle.dumps(mesh),
            lambda: mesh.save("never.ply"),
            lambda: mesh.edit().__enter__(),
        ]:
            with pytest.raises(RuntimeError, match="an edit of this mesh is open"):
                call()
        with pytest.raises(RuntimeError, match="a walk needs a valid mesh"):
            v.outgoing()
        assert v.halfedge.next.next.next == v.halfedge  # links read one by one
        e.set_position(v, [0, 0, 2])
    assert v.position == (0.0, 0.0, 2.0) and len(v.outgoing()) == 5
    with pytest.raises(RuntimeError, match="not open"):
        e.set_position(v, [0, 0, 3])


def test_setters_refuse_what_is_not_an_element_of_this_mesh():
    mesh, other = pappus.load("shape:icosphere:1"), pappus.load("shape:icosphere:1")
    h, v, f = mesh.halfedge(0), mesh.vertex(0), mesh.face(0)
    before = state(mesh)
    with pytest.raises(pappus.InvalidMesh, match="rolled back"):
        with mesh.edit() as e:
            with pytest.raises(TypeError, match="expected a pappus.Halfedge, not Vertex"):
                e.set_next(h, v)
            with pytest.raises(ValueError, match="is an element of another mesh"):
                e.set_twin(h, other.halfedge(1))
            with pytest.raises(ValueError, match="not a finite position"):
                e.set_position(v, [np.nan, 0, 0])
            e.remove(f)
            with pytest.raises(ValueError, match=f"{f.id} is not an element of this mesh"):
                e.set_face(h, f)
            with pytest.raises(ValueError, match=f"{f.id} is not an element of this mesh"):
                e.set_halfedge(f, h)
            # Leaving the block: the removed face's halfedges still name it.
    assert state(mesh) == before and mesh.validate() is None
