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
"""

from ._pappus import (
    SHAPES,
    InvalidMesh,
    Mesh,
    PappusError,
    ParseError,
    Refused,
    __version__,
    load,
    memory_budget,
    set_memory_budget,
)

__all__ = [
    "SHAPES",
    "InvalidMesh",
    "Mesh",
    "PappusError",
    "ParseError",
    "Refused",
    "__version__",
    "load",
    "memory_budget",
    "set_memory_budget",
]


def _restore(state):
    """Rebuilds a pickled :class:`Mesh` from the state its ``__reduce__`` gave."""
    return Mesh._from_state(state)
