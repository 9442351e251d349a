"""trimesh both ways (`Mesh.from_trimesh`, `mesh.to_trimesh()`): the rows stay trimesh's, the
positions its float32 values, and a mesh with polygons is refused rather than cut silently."""

import numpy as np
import pytest
import trimesh

import pappus


def test_a_trimesh_round_trips_with_its_rows():
    t = trimesh.creation.icosphere(subdivisions=2)
    mesh = pappus.Mesh.from_trimesh(t)
    vertices, faces = mesh.arrays()
    np.testing.assert_array_equal(vertices, t.vertices.astype(np.float32))
    np.testing.assert_array_equal(faces, t.faces)
    assert repr(mesh).startswith("<pappus.Mesh 'trimesh'")
    back = mesh.to_trimesh()
    assert isinstance(back, trimesh.Trimesh)
    np.testing.assert_array_equal(back.vertices, vertices)
    np.testing.assert_array_equal(back.faces, t.faces)
    assert back.is_watertight and abs(back.area - t.area) < 1e-5 * t.area
    # An edit shows in the next copy: a flip keeps the counts, changes two faces.
    mesh.flip(mesh.edge(0))
    flipped = mesh.to_trimesh()
    assert len(flipped.faces) == len(t.faces)
    assert (flipped.faces != t.faces).any(axis=1).sum() == 2


def test_polygons_are_refused_and_other_objects_named():
    quads = pappus.load("shape:cube")
    with pytest.raises(ValueError, match="triangulate"):
        quads.to_trimesh()
    quads.triangulate()
    assert len(quads.to_trimesh().faces) == 12
    with pytest.raises(AttributeError):
        pappus.Mesh.from_trimesh(object())
