#!/usr/bin/env python3
"""The halfedge structure from Python, timed in one run: `Mesh.connectivity()` against
`Mesh.arrays()` (the issue's bar: at most 2x), and a walk over every vertex's outgoing halfedges
through the arrays (one Python step a halfedge) and through handles (`mesh.vertex(v).outgoing()`,
one handle a halfedge).
Prints a Markdown table, ready for docs/performance.md.

Each time is the median of 7 calls (the walk: of 3). The walk visits each vertex's fan by
`h = twin[prev[h]]` from `vertex_halfedge[v]` until it comes back, on Python ints (the arrays
turned to lists first, as a student's loop would), and checks that it visited every halfedge
once.

Then the cost of a local operation's record of what it made: an edge split by a step (input
vertex numbers, a summary) against `mesh.run("split", edge)` (a handle, and `.created` /
`.removed` read from the world's change tracking, which scans every element once).

Usage: python3 benches/python_halfedge.py [MODEL ...]
       (default: the Stanford bunny, homer and the 655 362-vertex icosphere:8)
Needs: numpy and the Pappus package (pip install ./).
"""
import statistics
import sys
import time
from pathlib import Path

import pappus

MODELS = Path(__file__).resolve().parents[1] / ".." / "shared" / "models"


def median_ms(call, repeats):
    """The median wall time of `call()` in ms over `repeats` calls."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(times)


def walk_every_fan(c):
    """Visits every vertex's outgoing halfedges; returns how many it visited."""
    vertex_halfedge = c.vertex_halfedge.tolist()
    twin, prev = c.twin.tolist(), c.prev.tolist()
    visited = 0
    for start in vertex_halfedge:
        if start < 0:
            continue
        h = start
        while True:
            visited += 1
            h = twin[prev[h]]
            if h == start:
                break
    return visited


def walk_every_fan_by_handles(mesh):
    """Visits every vertex's outgoing halfedges through handles (`v.outgoing()`)."""
    return sum(len(mesh.vertex(v).outgoing()) for v in range(len(mesh.vertices)))


def split_cost(source, count=200):
    """ms per edge split on `source`: by a step naming input vertex numbers (no record of what
    it made), and by `mesh.run` on a handle (with `.created` and `.removed`), 200 edges each."""
    results = []
    for by_run in (False, True):
        mesh = pappus.load(source)
        stride = max(1, len(mesh.connectivity().edge_halfedge) // count)
        edges = [mesh.edge(e) for e in range(0, stride * count, stride)]
        ends = [tuple(v.row for v in e.vertices()) for e in edges]
        start = time.perf_counter()
        for edge, (a, b) in zip(edges, ends):
            try:
                mesh.run("split", edge) if by_run else mesh.step(f"split:{a},{b}")
            except pappus.Refused:
                pass
        results.append((time.perf_counter() - start) * 1000.0 / count)
    return results


def main():
    sources = sys.argv[1:] or [
        str(MODELS / "stanford-bunny.obj"),
        str(MODELS / "homer.obj"),
        "shape:icosphere:8",
    ]
    print(
        "| mesh | faces | `arrays()` ms | `connectivity()` ms | ratio "
        "| every fan walked, arrays ms | by handles ms |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|")
    for source in sources:
        mesh = pappus.load(source)
        faces = len(mesh.faces)
        arrays = median_ms(mesh.arrays, 7)
        connectivity = median_ms(mesh.connectivity, 7)
        c = mesh.connectivity()
        assert walk_every_fan(c) == len(c.next)
        walk = median_ms(lambda: walk_every_fan(c), 3)
        assert walk_every_fan_by_handles(mesh) == len(c.next)
        by_handles = median_ms(lambda: walk_every_fan_by_handles(mesh), 3)
        name = Path(source).stem if not source.startswith("shape:") else source
        print(
            f"| {name} | {faces} | {arrays:.1f} | {connectivity:.1f} | "
            f"{connectivity / arrays:.2f} | {walk:.0f} | {by_handles:.0f} |"
        )


    print()
    print("| mesh | split by step ms | split by `run`, tracked ms | ratio |")
    print("|---|---:|---:|---:|")
    for source in sources[:2]:
        step, run = split_cost(source)
        name = Path(source).stem
        print(f"| {name} | {step:.3f} | {run:.3f} | {run / step:.2f} |")


if __name__ == "__main__":
    main()
