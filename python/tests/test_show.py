"""`pappus.show`: the editor opened on a script's mesh, with its arrays as colour maps, and the
mesh and the selection read back when the window closes.

The windowed tests run the editor this checkout built (`PAPPUS_EDITOR`, else `pappus` in the
Cargo target folder) under `xvfb-run`, as `show` does by itself without a display; without an
editor they skip, and under CI=true they fail instead."""

import os
import stat
import warnings
from pathlib import Path

import numpy as np
import pytest

import pappus


def built_editor():
    named = os.environ.get("PAPPUS_EDITOR")
    if named:
        return named
    target = os.environ.get("CARGO_TARGET_DIR") or str(Path.home() / ".cache/pappus/target")
    repository = Path(__file__).resolve().parents[2]
    for folder in [Path(target), repository / "target"]:
        for profile in ["debug", "release"]:
            candidate = folder / profile / "pappus"
            if candidate.exists():
                return str(candidate)
    return None


@pytest.fixture
def editor(monkeypatch, tmp_path):
    """The editor for `show`, with its remembered state (panel sections, recoveries) in a
    folder of the test's own."""
    found = built_editor()
    if found is None:
        if os.environ.get("CI") in ("true", "1"):
            pytest.fail("no built editor (cargo build), and under CI=true a test may not skip")
        pytest.skip("no built editor: run cargo build first")
    monkeypatch.setenv("PAPPUS_EDITOR", found)
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    # The window is drawn off-screen: show starts xvfb-run by itself.
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    return found


def test_without_an_editor_show_says_what_to_install_or_set(monkeypatch, tmp_path):
    mesh = pappus.load("shape:icosahedron")
    monkeypatch.delenv("PAPPUS_EDITOR", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(pappus.EditorUnavailable, match="cargo install --path ."):
        pappus.show(mesh)
    monkeypatch.setenv("PAPPUS_EDITOR", str(tmp_path / "nothing"))
    with pytest.raises(pappus.EditorUnavailable, match="PAPPUS_EDITOR"):
        pappus.show(mesh)


def test_without_a_display_a_window_is_refused_at_once(editor):
    mesh = pappus.load("shape:icosahedron")
    with pytest.raises(pappus.EditorUnavailable, match="no display"):
        pappus.show(mesh)


def test_a_quantity_has_one_value_per_vertex_or_per_face(editor):
    mesh = pappus.load("shape:icosahedron")
    with pytest.raises(ValueError, match="12 vertices and 20 faces"):
        pappus.show(mesh, {"seven": np.zeros(7)}, screenshot="x.png")
    with pytest.raises(ValueError, match="name"):
        pappus.show(mesh, {"": np.zeros(12)}, screenshot="x.png")


def test_an_editor_that_fails_or_never_closes_raises_and_the_mesh_is_unchanged(monkeypatch, tmp_path):
    mesh = pappus.load("shape:icosahedron")
    v = mesh.vertex(3)
    failing = tmp_path / "failing"
    failing.write_text("#!/bin/sh\necho 'no Vulkan here' >&2\nexit 3\n")
    hanging = tmp_path / "hanging"
    hanging.write_text("#!/bin/sh\nsleep 60\n")
    for program in [failing, hanging]:
        program.chmod(program.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("DISPLAY", ":99")
    monkeypatch.setenv("PAPPUS_EDITOR", str(failing))
    with pytest.raises(pappus.PappusError, match="code 3(.|\n)*no Vulkan here"):
        pappus.show(mesh)
    monkeypatch.setenv("PAPPUS_EDITOR", str(hanging))
    with pytest.raises(pappus.PappusError, match="still open after 1 s"):
        pappus.show(mesh, timeout=1)
    assert v.row == 3 and mesh.selection is None


def test_the_selection_comes_back_by_kind_and_row(editor):
    mesh = pappus.load("shape:icosphere:2")
    edge, face = mesh.edge(5), mesh.face(7)
    h = edge.halfedge
    a, b = h.from_vertex.row, h.to_vertex.row
    shown = pappus.show(
        mesh, script=f"select-edge:{a},{b};select-face:+7;select-vertex:+11;exit", timeout=300
    )
    assert shown is mesh
    selection = mesh.selection
    # Nothing was edited: the mesh and its handles are as they were.
    assert selection.edges == [edge] and selection.faces == [face]
    assert selection.vertices == [mesh.vertex(11)] and selection.halfedges == []
    assert list(selection.edge_rows) == [5] and list(selection.face_rows) == [7]
    assert list(selection.vertex_rows) == [11] and len(selection) == 3
    assert edge.halfedge.from_vertex.row in (a, b)


def test_an_edit_in_the_window_comes_back_and_ends_the_old_handles(editor):
    mesh = pappus.load("shape:icosphere:2")
    before = mesh.faces.copy()
    edge = mesh.edge(5)
    h = edge.halfedge
    h_vertex = h.from_vertex
    a, b = h.from_vertex.row, h.to_vertex.row
    # The corners opposite the edge: where the flipped edge runs.
    opposite = {h.next.to_vertex.row, h.twin.next.to_vertex.row}
    pappus.show(mesh, script=f"select-edge:{a},{b};key:Alt+R;exit", timeout=300)
    assert mesh.name == "icosphere:2"
    with pytest.raises(pappus.StaleElement):
        edge.halfedge
    # Vertex handles too: the mesh is another world's now, whatever its entities' numbers.
    with pytest.raises(pappus.StaleElement):
        h_vertex.position
    assert mesh.faces.shape == before.shape
    mesh.validate()
    # The flipped edge is what stays selected, now between the opposite corners.
    (flipped,) = mesh.selection.edges
    ends = {flipped.halfedge.from_vertex.row, flipped.halfedge.to_vertex.row}
    assert ends == opposite


def test_your_vertex_arrays_and_input_numbers_follow_an_edit_in_the_window(editor):
    mesh = pappus.load("shape:icosphere:2")
    positions = mesh.vertices.copy()
    mesh.vertex_data["height"] = positions[:, 2]
    faces = mesh.faces.copy()
    mesh.face_data["label"] = np.arange(len(faces))
    h = mesh.edge(5).halfedge
    a, b = h.from_vertex.row, h.to_vertex.row
    # A collapse in the window: one vertex goes, another takes its row in the editor's order.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pappus.show(mesh, script=f"select-edge:{a},{b};key:C;exit", timeout=300)
    assert len(mesh.vertices) == len(positions) - 1 and len(mesh.faces) == len(faces) - 2
    # Input numbers still name the vertices they named, wherever their rows went: each is
    # where it was, but the one the collapse kept (moved to the edge's midpoint) and the one
    # it removed (none).
    rows = mesh.__reduce__()[1][0]["input_rows"]
    assert (rows < 0).sum() == 1 and min(rows[a], rows[b]) == -1
    kept = max(rows[a], rows[b])
    moved = np.flatnonzero(np.any(mesh.vertices[rows] != positions, axis=1))
    np.testing.assert_array_equal(np.sort(moved), np.sort([a, b]))
    np.testing.assert_allclose(mesh.vertices[kept], (positions[a] + positions[b]) / 2, atol=1e-6)
    # vertex_data followed them: each vertex's height is its own, the kept one's its end's.
    height = mesh.vertex_data["height"]
    others = np.setdiff1d(np.arange(len(positions)), [a, b])
    np.testing.assert_array_equal(height[rows[others]], positions[others, 2])
    assert height[kept] in (positions[a, 2], positions[b, 2])
    # face_data followed the faces: each face away from the collapse has the corners, by input
    # number, of the face its label names.
    labels = mesh.face_data["label"]
    assert not np.isnan(labels).any() and len(set(labels)) == len(labels)
    number = np.full(len(mesh.vertices), -1)
    number[rows[rows >= 0]] = np.flatnonzero(rows >= 0)
    away = [f for f, corners in enumerate(mesh.faces) if kept not in corners]
    assert len(away) >= len(faces) - 12
    for f in away:
        assert set(number[mesh.faces[f]]) == set(faces[int(labels[f])])


def test_a_quantity_is_drawn_in_its_colour_map(editor, tmp_path):
    Image = pytest.importorskip("PIL.Image")  # installed by .ci/run: never skipped there
    mesh = pappus.load("shape:icosphere:3")
    heights = mesh.vertices[:, 1].astype(np.float64) + 1.0  # one sign: viridis
    # Per face: the height of each face's first corner.
    face_heights = heights[mesh.faces[:, 0]]
    plain, coloured = tmp_path / "plain.png", tmp_path / "coloured.png"
    faces = tmp_path / "faces.png"
    pappus.show(mesh, screenshot=plain, timeout=300)
    pappus.show(mesh, {"height": heights}, screenshot=coloured, timeout=300)
    pappus.show(mesh, {"face height": face_heights}, screenshot=faces, timeout=300)

    def greens(path):
        """The share of the window's pixels that viridis's green and yellow-green give (green
        well above red and at least blue), which neither the grey surface, the blue wireframe
        nor the dark background has."""
        pixels = np.asarray(Image.open(path).convert("RGB")).astype(int)
        r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
        return float(np.mean((g > r + 40) & (g >= b) & (g > 80)))

    assert greens(plain) < 0.002, greens(plain)
    assert greens(coloured) > 0.02, greens(coloured)
    assert greens(faces) > 0.02, greens(faces)
