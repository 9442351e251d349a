"""Type stubs for ``pappus``: what each call accepts, returns, and raises."""

import os
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
#: The procedural shapes ``load("shape:NAME")`` knows (sizes after colons: ``"shape:torus:64:32"``).
SHAPES: List[str]

#: A progress callback: called with the fraction done (0 to 1) at least once per level, pass,
#: iteration or solve phase. Returning False stops the operation where that is safe: simplify
#: and remesh stop after the pass (a valid, partly simplified or remeshed mesh), smooth after
#: the iteration (the summary says "stopped after k of n iterations"), loop and catmull_clark
#: only at their first call, before anything changed (Refused: "stopped by the progress
#: callback"); triangulate, parameterize and refine cannot stop and run to their end. An
#: exception raised by the callback never leaves a half-told result: the operation runs to its
#: end (the callback is not called again) and the exception is re-raised with a note (PEP 678)
#: saying that the edit completed, or that it was refused and the mesh is unchanged.
Progress = Optional[Callable[[float], Optional[bool]]]
#: A vertex by its input number; an edge ``(a, b)``; a face ``(a, b, c, ...)`` (consecutive corners).
Element = Union[int, Sequence[int], "Vertex", "Halfedge", "Edge", "Face"]
#: One element, or several.
Elements = Union[Element, Sequence[Element]]
#: Faces as an M×k integer array, or one index sequence per face (polygons of any sizes).
FacesLike = Union[npt.ArrayLike, Sequence[Sequence[int]]]

class PappusError(Exception):
    """The base of every error Pappus raises itself."""

class Refused(PappusError):
    """An operation was refused; the message is the reason. The mesh is exactly as it was."""

class ParseError(PappusError):
    """A mesh file is malformed or uses a variant Pappus does not read."""

    path: str
    #: ``"line N"`` (text formats) or ``"byte N"`` (binary, 0-based).
    location: str
    #: The 1-based line for text formats, else None.
    line: Optional[int]

class StaleElement(PappusError):
    """A handle names an element an edit removed (``"v12v0 is gone"``); nothing was read or
    changed. A collapse removes elements; subdivision ends every handle but vertices'."""

class InvalidMesh(PappusError):
    """``Mesh.validate`` found a broken invariant; the message names the rule and the element."""

def load(path: Union[str, os.PathLike]) -> "Mesh":
    """Loads a mesh from .obj/.off/.ply/.stl or ``"shape:NAME"``, repaired as the command line does.

    Raises ParseError (naming the line), FileNotFoundError/OSError, or ValueError (unknown
    extension or shape, no usable face). The GIL is released while reading and building.
    """

def set_memory_budget(limit: Union[int, str, None] = None) -> int:
    """Sets the memory budget of every operation in this process; returns the limit in bytes.

    ``limit``: bytes, a size such as ``"2G"`` or ``"512M"``, a share such as ``"50%"``, or None
    for the default (75 % of the available memory). An operation whose result would pass it
    (subdivision levels, a remeshing length, shape sizes, extrusions) raises Refused with its
    estimate before it starts.
    """

def memory_budget() -> Tuple[int, str]:
    """The budget now: ``(limit_bytes, how_it_was_chosen)``."""

def operations() -> List[Dict[str, Any]]:
    """Every operation that declares itself whole, as the command line, the editor's keys and
    panel know them: ``{"name", "title", "help", "key", "job", "parameters": [...]}``, in the
    panel's order, each parameter ``{"name", "kind", "default", "automatic"}`` with ``"min"``
    and ``"max"`` for a ``"real"`` or ``"whole"`` kind and ``"choices"`` for a ``"choice"``;
    the default as a step writes it (a number, a choice's word, or ``"auto"``, where
    ``"automatic"`` says what the operation then does). Each runs as
    ``mesh.step("NAME[:VALUE...]")``, missing values taking their defaults."""

def lab(
    mesh: "Mesh",
    reference: str,
    function: Callable[..., Any],
    *elements: Any,
    **parameters: Any,
) -> "LabReport":
    """Checks ``function(copy, *handles)``, a student's operation written with
    ``with copy.edit()``, against the registered operation ``reference`` on these elements: both
    run on copies of ``mesh`` with the same element ids, and the report says whether the result
    is valid and the same, or what differs, or the broken rule, or the exception. ``mesh`` is
    never changed. ``ValueError`` for an unknown reference or elements it does not take."""

class ElementData:
    """``Mesh.vertex_data`` and ``Mesh.face_data``: a mutable mapping of names to float32
    arrays by row of the vertices or the faces (a copy on read); assigning takes one value per
    element (``ValueError`` otherwise, or for a name a PLY file would read back as another
    property)."""

    def __getitem__(self, name: str) -> npt.NDArray[np.float32]: ...
    def __setitem__(self, name: str, values: npt.ArrayLike) -> None: ...
    def __delitem__(self, name: str) -> None: ...
    def __contains__(self, name: object) -> bool: ...
    def __len__(self) -> int: ...
    def __iter__(self) -> Iterable[str]: ...
    def keys(self) -> List[str]: ...
    def values(self) -> List[npt.NDArray[np.float32]]: ...
    def items(self) -> List[Tuple[str, npt.NDArray[np.float32]]]: ...
    def get(self, name: str, default: Any = None) -> Any: ...
    def pop(self, name: str, default: Any = ...) -> Any: ...
    def update(self, columns: Any) -> None: ...
    def clear(self) -> None: ...

class EditorUnavailable(PappusError):
    """The editor cannot be started: no ``pappus`` program, or no display. The message says what
    to install or set."""

class Selection:
    """What the user selected in the editor's window, by kind, in the order selected; rows as
    the mesh's when the window closed."""

    vertices: List["Vertex"]
    halfedges: List["Halfedge"]
    edges: List["Edge"]
    faces: List["Face"]
    @property
    def vertex_rows(self) -> npt.NDArray[np.int64]: ...
    @property
    def halfedge_rows(self) -> npt.NDArray[np.int64]: ...
    @property
    def edge_rows(self) -> npt.NDArray[np.int64]: ...
    @property
    def face_rows(self) -> npt.NDArray[np.int64]: ...
    def __len__(self) -> int: ...

def show(
    mesh: "Mesh",
    quantities: Optional[Dict[str, npt.ArrayLike]] = None,
    *,
    screenshot: Union[str, os.PathLike, None] = None,
    script: Optional[str] = None,
    timeout: Optional[float] = None,
) -> "Mesh":
    """Opens Pappus's editor on ``mesh`` with ``quantities`` (one value per vertex, or per face) as
    colour maps, blocks until the window closes, and returns ``mesh`` as the user left it
    (rebuilt when edited: old handles stale), ``mesh.selection`` what was selected.
    ``screenshot`` writes a PNG and closes; ``script`` runs editor steps (``PAPPUS_SCRIPT``'s
    syntax). The editor is ``PAPPUS_EDITOR``, else ``pappus`` on PATH. Raises
    EditorUnavailable, ValueError (a quantity's length), PappusError (the editor failed or
    timed out; the mesh unchanged)."""

class LabReport:
    """What :func:`lab` found; ``str(report)`` is the report as the editor says it."""

    verdict: str
    detail: Optional[str]
    reference: str
    @property
    def same(self) -> bool: ...

def output_stem(source: Union[str, os.PathLike]) -> str:
    """``{stem}`` as ``pappus process -o`` names it: a file's name without its extension, or a
    shape's name and sizes joined by dashes (``"shape:icosphere:3"`` → ``"icosphere-3"``)."""

def process_file(
    source: Union[str, os.PathLike],
    steps: Iterable[str],
    output: Union[str, os.PathLike, None] = None,
    *,
    info: bool = False,
) -> Dict[str, Any]:
    """``pappus process SOURCE -o OUTPUT STEP...`` for one input, as a call of plain values for an
    executor (``dask.distributed``'s ``Client.map``, ``concurrent.futures``, ``multiprocessing``).

    ``output``: ``{stem}`` replaced as ``-o`` does, its folder created; None saves nothing.
    Returns ``source``, ``output``, ``steps`` (``step``, ``outcome``, ``summary`` or ``reason``,
    ``ms`` each), ``dropped`` (what the format could not hold), ``vertices`` and ``faces`` (counts),
    ``info`` (``Mesh.info()`` with ``info=True``, else None; its curvature statistics can cost more
    than the steps), ``ms``.
    A refused step is reported and the others run; an unreadable input or unwritable output raises.
    """

class Connectivity:
    """The halfedge structure of a mesh when ``Mesh.connectivity()`` was called: int64 arrays,
    −1 where there is no element. Vertex and face rows are those of ``Mesh.vertices`` and
    ``Mesh.faces``: walking ``next`` from ``face_halfedge[f]`` visits ``faces[f]``'s corners in
    order, each halfedge's ``from_vertex`` being the corner. A snapshot: later edits leave it."""

    #: Per halfedge: the next halfedge round its face (or boundary loop).
    next: npt.NDArray[np.int64]
    #: Per halfedge: the previous halfedge round its face (or boundary loop).
    prev: npt.NDArray[np.int64]
    #: Per halfedge: the opposite halfedge of its edge.
    twin: npt.NDArray[np.int64]
    #: Per halfedge: the vertex it points to (its tip).
    to_vertex: npt.NDArray[np.int64]
    #: Per halfedge: the vertex it leaves (``to_vertex[twin]``).
    from_vertex: npt.NDArray[np.int64]
    #: Per halfedge: its edge.
    edge: npt.NDArray[np.int64]
    #: Per halfedge: its face, −1 on the boundary.
    face: npt.NDArray[np.int64]
    #: Per vertex: an outgoing halfedge, the boundary one on a boundary; −1 when isolated.
    vertex_halfedge: npt.NDArray[np.int64]
    #: Per edge: one of its halfedges, an interior one where it has one.
    edge_halfedge: npt.NDArray[np.int64]
    #: Per face: the halfedge leaving the first corner of its row of ``faces``.
    face_halfedge: npt.NDArray[np.int64]

class Vertex:
    """One vertex of a mesh. Every read checks that it still exists (:class:`StaleElement`)."""

    #: The editor inspector's id (``"v12v0"``): the same vertex for as long as it exists.
    id: str
    #: Its row of ``Mesh.vertices`` now.
    row: int
    #: Its position; setting it moves the vertex as one edit (ValueError when not finite).
    position: Tuple[float, float, float]
    #: An outgoing halfedge, the boundary one on a boundary.
    halfedge: "Halfedge"
    is_boundary: bool
    #: Its number of edges.
    valence: int
    def outgoing(self) -> List["Halfedge"]:
        """Its outgoing halfedges, counter-clockwise (``h.prev.twin`` after ``h``)."""
    def neighbours(self) -> List["Vertex"]:
        """The vertices its edges lead to, in the order of ``outgoing()``."""
    def faces(self) -> List["Face"]:
        """The faces around it, in the order of ``outgoing()`` (a boundary gap skipped)."""

class Halfedge:
    """One side of an edge, pointing at ``to_vertex``."""

    id: str
    #: Its row of ``Mesh.connectivity()``'s halfedge arrays now.
    row: int
    next: "Halfedge"
    prev: "Halfedge"
    twin: "Halfedge"
    #: Its tip.
    to_vertex: Vertex
    #: Its tail.
    from_vertex: Vertex
    edge: "Edge"
    #: None on the boundary.
    face: Optional["Face"]
    is_boundary: bool

class Edge:
    """A pair of twin halfedges."""

    id: str
    row: int
    #: One of its halfedges, an interior one where it has one.
    halfedge: Halfedge
    is_boundary: bool
    def vertices(self) -> Tuple[Vertex, Vertex]:
        """``halfedge``'s tail, then its tip."""
    def faces(self) -> List["Face"]:
        """The faces on its sides: two inside the mesh, one on a boundary."""

class Face:
    """A cycle of halfedges."""

    id: str
    #: Its row of ``Mesh.faces`` now.
    row: int
    #: The halfedge leaving its first corner.
    halfedge: Halfedge
    #: Whether one of its edges lies on a boundary.
    is_boundary: bool
    def halfedges(self) -> List[Halfedge]:
        """Its halfedges in order, from ``halfedge``."""
    def vertices(self) -> List[Vertex]:
        """Its corners in order: its row of ``Mesh.faces``."""

AnyElement = Union[Vertex, Halfedge, Edge, Face]

class MeshEdit:
    """A low-level edit, used as ``with mesh.edit() as e:``. Inside, the setters rewire the
    structure freely (each journalled); leaving the block checks every invariant: a broken one
    raises InvalidMesh naming the rule and the element, the mesh rolled back to exactly what it
    was; an exception inside the block rolls back too. While it is open the mesh runs nothing
    that reads it whole (RuntimeError), and handles read their links but walk no circulator.
    Each setter raises TypeError for a handle of another kind, ValueError for an element not of
    this mesh (another mesh's, or one removed in this edit), StaleElement for a stale handle.
    See python/examples/halfedge_edits.py for a flip and a split written with it."""

    def __enter__(self) -> "MeshEdit": ...
    def __exit__(self, kind: Any, value: Any, traceback: Any) -> bool: ...
    def set_next(self, h: Halfedge, next: Halfedge) -> None:
        """``h.next = next`` and ``next.prev = h``."""
    def set_twin(self, a: Halfedge, b: Halfedge) -> None:
        """Makes ``a`` and ``b`` each other's twin."""
    def set_to_vertex(self, h: Halfedge, v: Vertex) -> None: ...
    def set_edge(self, h: Halfedge, edge: Edge) -> None: ...
    def set_face(self, h: Halfedge, face: Optional[Face]) -> None:
        """None makes ``h`` a boundary halfedge."""
    def set_halfedge(self, x: Union[Vertex, Edge, Face], h: Halfedge) -> None:
        """A vertex's outgoing halfedge, an edge's or a face's halfedge."""
    def set_position(self, v: Vertex, position: Sequence[float]) -> None: ...
    def new_vertex(self, position: Sequence[float]) -> Vertex:
        """A new vertex; set its halfedge before leaving the block."""
    def new_edge(self) -> Tuple[Edge, Halfedge, Halfedge]:
        """A new edge and its two halfedges, twins, each its own next and prev, on no face."""
    def new_face(self) -> Face:
        """A new face; set its halfedge before leaving the block."""
    def remove(self, x: AnyElement) -> None:
        """Removes an element when the block is left (links still naming it break the check)."""

class Outcome(str):
    """An operation's summary (this string), with handles on what it made and removed."""

    @property
    def created(self) -> Optional[List[AnyElement]]:
        """The elements it made (a split's new vertex, edges and faces); None after a
        whole-mesh operation, which keeps no record."""
    @property
    def removed(self) -> Optional[List[AnyElement]]:
        """The elements it removed (each raises StaleElement when read; ``id`` names it);
        None after a whole-mesh operation."""

class Mesh:
    """One halfedge mesh (polygons allowed).

    Operations name elements by the numbers of the vertices the mesh was made from (the file's
    vertex numbers or the rows of the constructor's ``vertices``), as ``pappus process`` steps
    do. Each returns the command line's summary string; a refusal raises :class:`Refused` and
    leaves the mesh untouched; a parameter out of range raises ValueError.
    """

    @staticmethod
    def from_trimesh(t: Any) -> "Mesh":
        """``Mesh(t.vertices, t.faces)`` from a ``trimesh.Trimesh``, its rows in trimesh's order."""
    @property
    def selection(self) -> Optional[Selection]:
        """What the user selected in the editor when :func:`show` last returned; None before."""
    def to_trimesh(self) -> Any:
        """This mesh as a ``trimesh.Trimesh`` (``process=False``: rows kept); ``ValueError``
        for a mesh with polygons (``triangulate()`` first)."""
    def __init__(self, vertices: npt.ArrayLike, faces: FacesLike) -> None:
        """From an N×3 float array and M×3 / M×4 integer faces (or a list of polygons).

        Repaired as a file is; ValueError for an index out of range, a wrong shape, or no face
        left.
        """
    @property
    def vertices(self) -> npt.NDArray[np.float32]:
        """N×3 float32 positions (a copy), in table order."""
    @vertices.setter
    def vertices(self, value: npt.ArrayLike) -> None:
        """Every position at once, as one edit: an N×3 array of any float dtype. ValueError
        for another shape or a coordinate that is not finite (naming its row); the mesh is
        then untouched."""
    @property
    def vertex_normals(self) -> npt.NDArray[np.float32]:
        """N×3 float32 normals by row: the file's while no edit changed the surface, else
        angle-weighted ones (what a save writes)."""
    @property
    def vertex_data(self) -> "ElementData":
        """Named per-vertex scalars, float32 by row: the source's (a PLY's ``quality``) and the
        script's (``mesh.vertex_data["d"] = array``). Each value follows its vertex through
        edits; a vertex an edit made gets the value interpolated at its place on the surface
        before (a split's midpoint: the mean of its edge's ends). A PLY save writes them."""
    @property
    def face_data(self) -> "ElementData":
        """Named per-face scalars, float32 by row of ``faces``: the source's (a PLY's face
        properties) and the script's (``mesh.face_data["label"] = array``). Each value follows
        its face through edits (a flip keeps both faces); a face an edit made takes the value
        of the face it was cut from (the one its centroid lay on). A PLY save writes them."""
    def quantity(self, name: str, *, to: Optional["Mesh"] = None) -> npt.NDArray[np.float64]:
        """A per-vertex quantity by row, as the editor colours by and ``pappus process
        --quantity NAME`` writes: ``mean``, ``gaussian``, ``angle-defect``, ``max-curvature``,
        ``min-curvature``, ``valence``, ``min-angle`` (degrees), ``edge-length`` (the mean of
        the vertex's edges), ``distance`` (to the mesh ``to``, which only it takes).
        ValueError for an unknown name or a misplaced ``to``."""
    @property
    def faces(self) -> Union[npt.NDArray[np.int64], List[npt.NDArray[np.int64]]]:
        """M×k int64 rows of ``vertices`` when every face has k sides, else a list of arrays."""
    @property
    def corner_uvs(self) -> Optional[npt.NDArray[np.float32]]:
        """K×2 float32 UVs, one per face corner in the order of ``faces``; None without UVs."""
    @property
    def face_groups(self) -> Optional[Dict[str, Any]]:
        """Each face's object, group, material and smoothing group (OBJ's ``o g usemtl s``):
        ``{"groups": [{"object", "group", "material", "smoothing"}, ...], "face": uint32 row per
        face in the order of ``faces``, "material_libraries": [...]}``; None without groups."""
    @property
    def name(self) -> str:
        """The file name, the shape's name, or ``"arrays"``."""
    def arrays(
        self,
    ) -> Tuple[npt.NDArray[np.float32], Union[npt.NDArray[np.int64], List[npt.NDArray[np.int64]]]]:
        """``(vertices, faces)`` in one pass."""
    def connectivity(self) -> Connectivity:
        """The halfedge structure as arrays (see :class:`Connectivity`)."""
    def edit(self) -> MeshEdit:
        """A checked low-level edit: ``with mesh.edit() as e: e.set_next(h, n) …``."""
    def vertex(self, row: int) -> Vertex:
        """The vertex in ``row`` of ``vertices`` (negative rows from the end); IndexError outside."""
    def halfedge(self, row: int) -> Halfedge:
        """The halfedge in ``row`` of ``connectivity()``'s halfedge arrays; IndexError outside."""
    def edge(self, row: int) -> Edge:
        """The edge in ``row`` of ``connectivity()``'s edge arrays; IndexError outside."""
    def face(self, row: int) -> Face:
        """The face in ``row`` of ``faces``; IndexError outside."""
    def element(self, id: str) -> AnyElement:
        """The element the editor's inspector calls ``id`` (``"v12v0"``, ``"h7v0"``, …).
        ValueError for text that is no element id, StaleElement for one no longer here."""
    def info(self) -> dict:
        """The keys of ``pappus info --json`` (counts, genus, validity, repairs, curvature, …)."""
    def validate(self) -> None:
        """Returns None when every invariant holds; raises InvalidMesh otherwise."""
    def save(self, path: Union[str, os.PathLike]) -> None:
        """Writes .obj/.off/.ply/.stl (by extension) atomically; ValueError/OSError on failure.

        The old file survives any failure byte for byte (no space, the file-size limit, no
        permission; the OSError says which); a symbolic link is followed and kept; the old
        file's permissions are kept; two threads saving one path leave one whole file.
        """
    def step(self, step: str, *, progress: Progress = None) -> str:
        """Runs one ``pappus process`` step written as on the command line (``"flip:3,17"``)."""
    # Whole-mesh operations: the GIL is released, ``progress`` is called now and then.
    def simplify(
        self,
        ratio: Optional[float] = None,
        faces: Optional[int] = None,
        distance: float = 0.0,
        fit: bool = False,
        *,
        progress: Progress = None,
    ) -> "Outcome":
        """QEM to ``ratio`` (0, 1] of the faces or to ``faces`` faces (neither: 0.5);
        ``distance`` > 0 weighs how far each collapse takes the input away (8: closer, about
        three times the time); ``fit=True`` fits the result's vertices to the input at the
        end."""
    def remesh(
        self, iterations: int = 5, length: Optional[float] = None, *, progress: Progress = None
    ) -> "Outcome":
        """Isotropic remeshing; ``length`` defaults to the mean edge length."""
    def loop(self, levels: int = 1, *, progress: Progress = None) -> "Outcome":
        """Loop subdivision (triangles only), 1 to 8 levels."""
    def catmull_clark(self, levels: int = 1, *, progress: Progress = None) -> "Outcome":
        """Catmull–Clark subdivision (any polygons, gives quads), 1 to 8 levels."""
    def triangulate(self, *, progress: Progress = None) -> "Outcome":
        """Cuts every polygon into triangles."""
    def reverse(self) -> "Outcome":
        """Turns every face round: corners in the opposite order, normals the other way."""
    def orient_outside(self) -> "Outcome":
        """Turns round each part (faces joined across edges) whose faces point inward."""
    def smooth(
        self,
        method: str = "uniform",
        iterations: int = 1,
        step: Optional[float] = None,
        *,
        progress: Progress = None,
    ) -> "Outcome":
        """``uniform``, ``cotan``, ``implicit`` or ``taubin`` smoothing; the boundary stays."""
    def parameterize(
        self, method: str = "mean-value", boundary: str = "circle", *, progress: Progress = None
    ) -> "Outcome":
        """UVs per corner: ``uniform``, ``mean-value``, ``harmonic`` (``circle``/``square``), ``lscm``."""
    def refine(self, faces: Optional[int] = None, *, progress: Progress = None) -> "Outcome":
        """Splits the last simplification back (to ``faces`` faces, or all)."""
    def deform(
        self,
        method: str,
        fixed: Sequence[int],
        handle: Sequence[int],
        offset: Tuple[float, float, float],
        iterations: int = 10,
    ) -> str:
        """``arap`` or ``laplace`` (thin plate): ``fixed`` stays, ``handle`` moves by ``offset``."""
    def fair(self, vertices: Sequence[Element], k: int = 2) -> "Outcome":
        """The vertices solve the k-harmonic equation (k 1–3), every other vertex held."""
    # Local operations: an element by handle, or by input vertex numbers (``a, b`` an edge).
    # Each returns an Outcome: the summary, with ``created`` and ``removed`` handles.
    def flip(self, a: Element, b: Optional[int] = None) -> "Outcome": ...
    def split(self, a: Element, b: Optional[int] = None) -> "Outcome": ...
    def bisect(self, a: Element, b: Optional[int] = None) -> "Outcome": ...
    def collapse(self, a: Element, b: Optional[int] = None) -> "Outcome": ...
    def dissolve(self, a: Element, b: Optional[int] = None) -> "Outcome": ...
    def fill_hole(self, a: Element, b: Optional[int] = None, *, fair: bool = False) -> "Outcome":
        """The hole beside edge a–b as one face, or with ``fair`` a faired patch of triangles."""
    def fill_holes(self, fair: bool = True) -> "Outcome":
        """Every hole: faired patches of triangles (``fair``), or one face each."""
    def split_face(self, a: Element, b: Optional[int] = None) -> "Outcome": ...
    def seam(self, a: Element, b: Optional[int] = None) -> "Outcome": ...
    def extrude(self, faces: Elements, distance: float) -> "Outcome": ...
    def inset(self, faces: Elements, amount: float, depth: float = 0.0) -> "Outcome": ...
    def bevel(self, element: Element, amount: float = 0.25, depth: float = 0.0) -> "Outcome": ...
    def erase(self, elements: Elements) -> "Outcome": ...
    def dissolve_vertex(self, a: Element) -> "Outcome": ...
    def collapse_face(self, face: Element) -> "Outcome": ...
    def weld(self, first: Element, second: Element) -> "Outcome": ...
    def run(
        self, name: str, *elements: Elements, progress: Progress = None, **parameters: Any
    ) -> "Outcome":
        """Runs the operation ``name`` (as :func:`operations` lists it; ``_`` reads as ``-``) on
        ``elements`` (handles or input vertex numbers) with its declared parameters as keywords
        (lower case; a choice by its word; None for automatic; the rest their defaults).
        ValueError for an unknown name, elements it does not name, an unknown keyword or a
        value out of range; StaleElement for a removed handle; Refused when it refuses."""
    def copy(self) -> "Mesh":
        """An independent copy (no simplification history, no seam marks)."""
    def __copy__(self) -> "Mesh": ...
    def __deepcopy__(self, memo: object) -> "Mesh": ...
    def __reduce__(self) -> tuple: ...
