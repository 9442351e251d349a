"""An edge flip and an edge split written by hand on Pappus's halfedge structure, as the
halfedge labs ask (CMU 15-462's MeshEdit, Scotty3D): each reads the elements it needs through
handles, then rewires them inside ``with mesh.edit() as e:``. Leaving the block checks the
whole structure; a mistake raises ``pappus.InvalidMesh`` naming the broken rule and the
element, and the mesh is exactly as it was before the block.

    python3 python/examples/halfedge_edits.py        # flips and splits an icosphere's edges

The tests (python/tests/test_mesh_edit.py) hold both to ``mesh.flip`` and ``mesh.split``.
"""

import pappus


def flip(mesh, edge):
    """Turns ``edge``, the diagonal of the two triangles (a, b, c) and (b, a, d) beside it,
    into the diagonal c-d: the triangles become (d, c, a) and (c, d, b)."""
    h = edge.halfedge  # a -> b, in face f
    t = h.twin  # b -> a, in face g
    h1, t1 = h.next, t.next  # b -> c, a -> d
    h2, t2 = h1.next, t1.next  # c -> a, d -> b
    a, b = h.from_vertex, h.to_vertex
    c, d = h1.to_vertex, t1.to_vertex
    f, g = h.face, t.face
    a_leaves_by_h, b_leaves_by_t = a.halfedge == h, b.halfedge == t
    with mesh.edit() as e:
        e.set_to_vertex(h, c)  # h: d -> c
        e.set_to_vertex(t, d)  # t: c -> d
        for x, y in [(h, h2), (h2, t1), (t1, h), (t, t2), (t2, h1), (h1, t)]:
            e.set_next(x, y)  # f: h, h2, t1; g: t, t2, h1
        e.set_face(t1, f)
        e.set_face(h1, g)
        e.set_halfedge(f, h)
        e.set_halfedge(g, t)
        if a_leaves_by_h:  # a no longer leaves by h
            e.set_halfedge(a, t1)
        if b_leaves_by_t:
            e.set_halfedge(b, h1)


def split(mesh, edge):
    """Puts a vertex m at the middle of ``edge`` (between the triangles (a, b, c) and
    (b, a, d)) and joins it to c and d: four triangles (a, m, c), (m, b, c), (b, m, d) and
    (m, a, d). As Pappus's split: the edge keeps h (now a -> m) with a new twin; t (now
    b -> m) moves to a new edge m-b with a new twin; f keeps (a, m, c), g keeps (b, m, d).
    Returns m."""
    h = edge.halfedge  # a -> b, in face f; becomes a -> m
    t = h.twin  # b -> a, in face g; becomes b -> m
    h1, t1 = h.next, t.next  # b -> c, a -> d
    h2, t2 = h1.next, t1.next  # c -> a, d -> b
    a, b = h.from_vertex, h.to_vertex
    c, d = h1.to_vertex, t1.to_vertex
    f, g = h.face, t.face
    middle = [(p + q) / 2 for p, q in zip(a.position, b.position)]
    with mesh.edit() as e:
        m = e.new_vertex(middle)
        mb, x, y = e.new_edge()  # x: m -> b, t's twin; y: m -> a, h's twin on the old edge
        _, p, q = e.new_edge()  # p: c -> m, q: m -> c
        _, r, s = e.new_edge()  # r: d -> m, s: m -> d
        f2, g2 = e.new_face(), e.new_face()
        e.set_twin(h, y)
        e.set_edge(y, edge)
        e.set_twin(t, x)
        e.set_edge(t, mb)
        e.set_halfedge(mb, t)
        for half, tip in [(h, m), (t, m), (x, b), (y, a), (p, m), (q, c), (r, m), (s, d)]:
            e.set_to_vertex(half, tip)
        faces = [(f, [h, q, h2]), (f2, [x, h1, p]), (g, [t, s, t2]), (g2, [y, t1, r])]
        for face, cycle in faces:
            for k, half in enumerate(cycle):
                e.set_next(half, cycle[(k + 1) % 3])
                e.set_face(half, face)
            e.set_halfedge(face, cycle[0])
        e.set_halfedge(m, x)
    return m


if __name__ == "__main__":
    sphere = pappus.load("shape:icosphere:2")
    for row in range(0, 30, 3):
        flip(sphere, sphere.edge(row))
    m = split(sphere, sphere.edge(1))
    print(sphere, "- the new vertex", m.id, "has", m.valence, "neighbours")
