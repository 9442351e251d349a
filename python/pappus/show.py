"""``pappus.show``: a script's mesh in Pappus's editor, and what the user did there back.

The editor is Pappus's own program, ``pappus``, run as a child process (the Python package holds
the core only, not the window): the mesh goes to it as a PLY file with the arrays beside it,
and when the window closes the editor writes the mesh as the user left it and what was
selected, which this module reads back (``pappus --show``'s request and answer are described in
the editor's ``automation::show`` module).
"""

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from ._pappus import PappusError, load

__all__ = ["EditorUnavailable", "Selection", "show"]


class EditorUnavailable(PappusError):
    """The editor cannot be started: no ``pappus`` program, or no display to open it on. The
    message says what to install or set."""


class Selection:
    """What the user selected in the editor's window, by kind: handles (``vertices``,
    ``halfedges``, ``edges``, ``faces``, lists) and their rows (``vertex_rows``, ``halfedge_rows``,
    ``edge_rows``, ``face_rows``, int64 arrays), in the order they were selected. The rows are
    the mesh's when the window closed; the handles go stale with an edit, as any handle does."""

    def __init__(self, vertices, halfedges, edges, faces):
        self.vertices = vertices
        self.halfedges = halfedges
        self.edges = edges
        self.faces = faces

    @property
    def vertex_rows(self):
        return _rows(self.vertices)

    @property
    def halfedge_rows(self):
        return _rows(self.halfedges)

    @property
    def edge_rows(self):
        return _rows(self.edges)

    @property
    def face_rows(self):
        return _rows(self.faces)

    def __len__(self):
        return len(self.vertices) + len(self.halfedges) + len(self.edges) + len(self.faces)

    def __repr__(self):
        counts = ", ".join(
            f"{len(v)} {k}"
            for k, v in [
                ("vertices", self.vertices),
                ("halfedges", self.halfedges),
                ("edges", self.edges),
                ("faces", self.faces),
            ]
            if v
        )
        return f"<pappus.Selection: {counts or 'nothing'}>"


def _rows(handles):
    return np.array([h.row for h in handles], dtype=np.int64)


def show(mesh, quantities=None, *, screenshot=None, script=None, timeout=None):
    """Opens Pappus's editor on ``mesh``, blocks until its window closes, and returns ``mesh``
    as the user left it, with ``mesh.selection`` what they had selected (a :class:`Selection`).

    ``quantities`` maps names to arrays of one value per vertex (in the order of
    ``mesh.vertices``) or one per face (in the order of ``mesh.faces``; each face drawn in one
    colour), told apart by their length (per vertex where the counts are equal); NaN where
    there is none. Each is listed in the editor's Analysis section beside Pappus's own
    quantities, with its colour map and legend, and the mesh opens coloured by the first. The
    values stay on their elements through edits in the window (a new one has none and is
    drawn grey).

    When the user edited the mesh (anything in the undo history, even undone), ``mesh`` is
    rebuilt from what the editor hands back: its rows are then the editor's and every handle
    taken before is stale. The editor says which of the mesh's rows each vertex and face was,
    so input vertex numbers still name the same vertices and ``vertex_data`` and ``face_data``
    follow them (an element made in the window reads its value off the surface as it was, as
    after an edit in Python); what did not come back (what a PLY cannot hold, such as face
    groups) is named in a ``UserWarning``; seam marks do not come back.
    Without an edit, ``mesh`` is untouched.

    ``screenshot`` (a path) writes a PNG of the window once the mesh is drawn and closes it,
    for scripts and tests; ``script`` runs editor steps first (``PAPPUS_SCRIPT``'s syntax:
    ``"select-edge:0,5;select-face:+3"``; ending it with ``exit`` closes the window). Either runs
    under ``xvfb-run`` by itself when there is no display (and then closes the window after the
    script). ``timeout`` (seconds) stops a window that has not closed by then and raises; so
    does Ctrl+C, which stops the editor too.

    The editor is the program ``PAPPUS_EDITOR`` names, else ``pappus`` on ``PATH``.

    Raises :class:`EditorUnavailable` (no editor, no display: the message says what to install
    or set), ``ValueError`` for a quantity of the wrong length, :class:`PappusError` when the
    editor fails or times out (with the end of its output; the mesh is then untouched) or what
    it handed back cannot be read (kept in a folder the message names).
    """
    editor = _find_editor()
    names_and_values = _quantities(mesh, quantities or {})
    steps = ";".join(
        s for s in [script, f"wait:30;shot:{Path(screenshot).resolve()};exit" if screenshot else None] if s
    )
    command = _with_display([editor], headless=bool(steps))
    if command[0] != editor and not steps.rstrip().endswith("exit"):
        # Off-screen nobody can close the window: it closes after the script.
        steps += ";exit"
    with tempfile.TemporaryDirectory(prefix="pappus-show-") as folder:
        folder = Path(folder)
        mesh.save(folder / "mesh.ply")
        listed = []
        for i, (name, values, per) in enumerate(names_and_values):
            values.astype("<f8").tofile(folder / f"quantity{i}.f64")
            listed.append({"name": name, "per": per, "values": f"quantity{i}.f64"})
        request = {
            "mesh": "mesh.ply",
            "name": mesh.name,
            "quantities": listed,
            "hand_back": "back",
        }
        (folder / "show.json").write_text(json.dumps(request))
        environment = dict(os.environ)
        environment.pop("PAPPUS_SCRIPT", None)
        if steps:
            environment["PAPPUS_SCRIPT"] = steps
        code, output = _run(
            [*command, "--show", str(folder / "show.json")], environment, timeout
        )
        answer_path = folder / "back" / "answer.json"
        if code != 0 or not answer_path.exists():
            raise PappusError(
                f"the editor ended with code {code} without handing the mesh back;"
                " the mesh is unchanged" + _tail(output)
            )
        try:
            return _take_back(mesh, folder / "back")
        except Exception as e:
            kept = Path(tempfile.mkdtemp(prefix="pappus-show-kept-"))
            shutil.copytree(folder / "back", kept, dirs_exist_ok=True)
            raise PappusError(
                f"what the editor handed back could not be read ({e}); it is kept in {kept}"
                " (mesh.ply, answer.json)"
            ) from e


def _take_back(mesh, back):
    """Reads the editor's answer in ``back`` into ``mesh`` and its selection; ``mesh``."""
    answer = json.loads((back / "answer.json").read_text())
    for note in answer.get("notes", []):
        warnings.warn(f"pappus.show: {note}", UserWarning, stacklevel=3)
    if answer["mesh"] is None:
        warnings.warn(
            "pappus.show: the window closed with no mesh open; the mesh is unchanged",
            UserWarning,
            stacklevel=3,
        )
        mesh._set_selection(Selection([], [], [], []))
        return mesh
    if answer["edited"]:
        # Each element's row in the mesh shown: the script's vertex_data, face_data and input
        # numbers follow it (None when another file was opened in the window).
        sources = answer.get("vertex_sources")
        faces = answer.get("face_sources")
        lost = [] if faces is not None else [f"face_data[{n!r}]" for n in mesh.face_data]
        if sources is None:
            lost = [f"vertex_data[{n!r}]" for n in mesh.vertex_data] + lost
        mesh._take(load(str(back / answer["mesh"])), sources, faces)
        if lost:
            warnings.warn(
                f"pappus.show: {', '.join(lost)} did not come back: the mesh shown was"
                " replaced in the window",
                UserWarning,
                stacklevel=3,
            )
    mesh._set_selection(_selection(mesh, answer["selection"]))
    return mesh


def _run(command, environment, timeout):
    """Runs the editor in a session of its own, so that a timeout stops it and whatever it
    started (``xvfb-run``'s server) together; its exit code and output."""
    with subprocess.Popen(
        command,
        env=environment,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    ) as child:
        try:
            output, _ = child.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            output = _stop(child)
            raise PappusError(
                f"the editor's window was still open after {timeout} s; the mesh is unchanged"
                + _tail(output)
            ) from None
        except BaseException:
            # Ctrl+C reaches only this process (the editor has a session of its own).
            _stop(child)
            raise
    return child.returncode, output


def _stop(child):
    """Stops the editor and what it started: asked first (xvfb-run then cleans up its server),
    killed after five seconds. Its output."""
    def signal_all(number):
        if hasattr(os, "killpg"):
            try:
                os.killpg(child.pid, number)
            except ProcessLookupError:
                pass
        else:
            child.kill()

    signal_all(signal.SIGTERM)
    try:
        output, _ = child.communicate(timeout=5)
    except subprocess.TimeoutExpired:
        signal_all(signal.SIGKILL)
        output, _ = child.communicate()
    return output


def _find_editor():
    named = os.environ.get("PAPPUS_EDITOR")
    if named:
        if not (os.path.isfile(named) and os.access(named, os.X_OK)):
            raise EditorUnavailable(
                f"PAPPUS_EDITOR is {named!r}, which is no program: set it to the path of Pappus's"
                " `pappus` program (built by `cargo build --release` in a Pappus checkout)"
            )
        return named
    found = shutil.which("pappus")
    if found is None:
        raise EditorUnavailable(
            "pappus.show needs Pappus's editor, the `pappus` program, and none is on PATH:"
            " install it with `cargo install --path .` in a Pappus checkout (or build it with"
            " `cargo build --release`), or set PAPPUS_EDITOR to its path"
        )
    return found


def _with_display(command, headless):
    if not sys.platform.startswith("linux"):
        return command
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return command
    xvfb = shutil.which("xvfb-run")
    if headless and xvfb:
        return [xvfb, "-a", "-s", "-screen 0 1280x800x24", *command]
    if headless:
        raise EditorUnavailable(
            "no display (DISPLAY is not set) and no xvfb-run to draw without one: install xvfb"
            " (apt-get install xvfb), or set DISPLAY"
        )
    raise EditorUnavailable(
        "no display to open the editor's window on (DISPLAY is not set): run the script in a"
        " desktop session or set DISPLAY; pappus.show(..., screenshot='x.png') draws without one"
        " under xvfb-run"
    )


def _quantities(mesh, quantities):
    count, faces = len(mesh.vertices), len(mesh.faces)
    checked = []
    for name, values in quantities.items():
        if not isinstance(name, str) or not name.strip() or ";" in name:
            raise ValueError(f"a quantity's name must be a non-empty string without ';', not {name!r}")
        array = np.asarray(values, dtype=np.float64).reshape(-1)
        if array.shape[0] not in (count, faces):
            raise ValueError(
                f"quantity {name!r} has {array.shape[0]} values; the mesh has {count} vertices"
                f" and {faces} faces (one value per vertex, in the order of mesh.vertices, or"
                " one per face, in the order of mesh.faces)"
            )
        checked.append((name, array, "vertex" if array.shape[0] == count else "face"))
    return checked


def _selection(mesh, rows):
    def halfedge(pair):
        a, b = pair
        for h in mesh.vertex(a).outgoing():
            if h.to_vertex.row == b:
                return h
        raise PappusError(f"the editor handed back a halfedge from row {a} to row {b}, which the mesh lacks")

    halfedges = [halfedge(p) for p in rows["halfedges"]]
    edges = [halfedge(p).edge for p in rows["edges"]]
    return Selection(
        [mesh.vertex(r) for r in rows["vertices"]],
        halfedges,
        edges,
        [mesh.face(r) for r in rows["faces"]],
    )


def _tail(output, lines=12):
    if not output:
        return ""
    text = output.decode(errors="replace") if isinstance(output, bytes) else output
    return "\nthe editor's last output:\n" + "\n".join(text.splitlines()[-lines:])
