"""Pappus from Python: halfedge meshes with the command line's operations.

Load a mesh from a file or a procedural shape, or make one from NumPy arrays; edit it with the
same operations, parameters, defaults and refusals as ``pappus process`` (whole-mesh ones
release the GIL and report progress); read it back as arrays; save it; pickle it to other
processes.

>>> import pappus
>>> mesh = pappus.load("shape:icosphere:3")
>>> mesh.simplify(ratio=0.25)              # doctest: +SKIP
'1280 -> 320 faces in 480 collapses'
>>> vertices, faces = mesh.arrays()

Errors: :class:`Refused` (an operation refused; the mesh is untouched), :class:`ParseError` (a
malformed file, with the line), :class:`InvalidMesh` (``validate``), all :class:`PappusError`;
``ValueError`` for a parameter outside its range, ``OSError`` for the file system.

A folder of meshes on a cluster: :func:`process_file` is ``pappus process`` for one input, a
plain function of plain values, so any executor maps it (``dask.distributed``'s ``Client.map``,
``concurrent.futures``, ``multiprocessing``); see the README's recipe.
"""

import collections.abc
import time
import warnings
from pathlib import Path

from ._pappus import (
    SHAPES,
    Connectivity,
    Edge,
    Face,
    Halfedge,
    InvalidMesh,
    LabReport,
    Mesh,
    MeshEdit,
    PappusError,
    ParseError,
    Refused,
    StaleElement,
    Vertex,
    ElementData,
    __version__,
    lab,
    load,
    memory_budget,
    operations,
    set_memory_budget,
)
from .show import EditorUnavailable, Selection, show

# `mesh.vertex_data` and `mesh.face_data` are mappings: keys, items, values, get, pop, update,
# clear, `in`, `del`, assignment.
collections.abc.MutableMapping.register(ElementData)

__all__ = [
    "SHAPES",
    "Connectivity",
    "Edge",
    "EditorUnavailable",
    "ElementData",
    "Face",
    "Halfedge",
    "InvalidMesh",
    "LabReport",
    "Mesh",
    "MeshEdit",
    "Outcome",
    "PappusError",
    "ParseError",
    "Refused",
    "Selection",
    "StaleElement",
    "Vertex",
    "__version__",
    "lab",
    "load",
    "memory_budget",
    "operations",
    "output_stem",
    "process_file",
    "set_memory_budget",
    "show",
]


class Outcome(str):
    """What an operation did: its summary (this string, as ``pappus process`` prints it), with
    ``created`` and ``removed``, handles on the elements it made and removed (a removed one
    raises :class:`StaleElement` when read; its ``id`` still names it). A split's ``created``
    holds the new vertex, so an operation can follow on it. A whole-mesh operation keeps no
    record (both are None): take new handles from the mesh."""

    def __new__(cls, summary, made):
        outcome = super().__new__(cls, summary)
        outcome._made = made
        return outcome

    @property
    def created(self):
        """Handles on the elements the operation made (None after a whole-mesh operation)."""
        return self._made.created()

    @property
    def removed(self):
        """Handles on the elements the operation removed (None after a whole-mesh operation)."""
        return self._made.removed()

    def __reduce__(self):
        """Pickles (and copies) as the plain summary string: handles belong to their mesh."""
        return (str, (str(self),))


def _restore(state):
    """Rebuilds a pickled :class:`Mesh` from the state its ``__reduce__`` gave."""
    return Mesh._from_state(state)


def output_stem(source):
    """The ``{stem}`` of ``source`` as ``pappus process -o`` names it: a file's name without its
    extension, or a shape's name and sizes joined by dashes (``shape:icosphere:3`` →
    ``icosphere-3``)."""
    source = str(source)
    if source.startswith("shape:"):
        return source[len("shape:") :].replace(":", "-")
    return Path(source).stem


def process_file(source, steps, output=None, *, info=False):
    """Loads ``source``, runs ``steps`` in order, saves to ``output``: ``pappus process SOURCE
    -o OUTPUT STEP...`` for one input, as one call of plain values that an executor can send to
    another process or machine (the worker needs ``pappus`` installed and the files reachable).

    ``source``: a mesh file or ``"shape:NAME"``. ``steps``: step strings exactly as the command
    line writes them (``["triangulate", "simplify:0.5"]``). ``output``: a path, where ``{stem}``
    is replaced as ``-o`` does (:func:`output_stem`); its folder is created; ``None`` saves
    nothing. Returns a dict: ``source``, ``output`` (or None), ``steps`` (one dict per step:
    ``step``, ``outcome`` ``"applied"`` or ``"refused"``, ``summary`` or ``reason``, ``ms``),
    ``dropped`` (what the output format could not hold, as ``Mesh.save`` warns), ``vertices``
    and ``faces`` (the result's counts), ``info`` (with ``info=True``: the result's
    :meth:`Mesh.info`, whose curvature statistics can cost more than the steps; else None) and
    ``ms`` (the whole call). A refused step is reported and the
    rest go on, as on the command line; an unreadable input or unwritable output raises.
    """
    start = time.perf_counter()
    mesh = load(source)
    reports = []
    for step in steps:
        began = time.perf_counter()
        try:
            report = {"step": step, "outcome": "applied", "summary": mesh.step(step)}
        except Refused as refusal:
            report = {"step": step, "outcome": "refused", "reason": str(refusal)}
        report["ms"] = (time.perf_counter() - began) * 1000.0
        reports.append(report)
    dropped = []
    if output is not None:
        output = Path(str(output).replace("{stem}", output_stem(source)))
        output.parent.mkdir(parents=True, exist_ok=True)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            mesh.save(output)
        dropped = [str(w.message) for w in caught]
        output = str(output)
    vertices, faces = mesh.arrays()
    return {
        "source": str(source),
        "output": output,
        "steps": reports,
        "dropped": dropped,
        "vertices": len(vertices),
        "faces": len(faces),
        "info": mesh.info() if info else None,
        "ms": (time.perf_counter() - start) * 1000.0,
    }
