#!/usr/bin/env python3
"""`with mesh.edit()` from Python: the hand-written flip of python/examples/halfedge_edits.py
against `mesh.flip`, on the same edges (every 97th of the first 20 × 97 the library flips both
ways), median ms each. The commit checks what the edit touched, so its time does not grow
with the mesh.

Usage: python3 benches/python_mesh_edit.py [MODEL ...]
       (default: the Stanford bunny and an icosphere of 1 280 faces)
Needs: the Pappus package (pip install ./).
"""
import statistics
import sys
import time
from pathlib import Path

import pappus

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python" / "examples"))
import halfedge_edits  # noqa: E402


def main():
    sources = sys.argv[1:] or [
        str(ROOT / ".." / "shared" / "models" / "stanford-bunny.obj"),
        "shape:icosphere:3",
    ]
    print("| mesh | faces | flip by hand + commit | `mesh.flip` | ratio |")
    print("|---|---:|---:|---:|---:|")
    for source in sources:
        mesh = pappus.load(source)
        by_hand, library = [], []
        for row in range(0, 20 * 97, 97):
            edge = mesh.edge(row)
            try:
                mesh.flip(edge)
                mesh.flip(edge)
            except pappus.Refused:
                continue
            start = time.perf_counter()
            halfedge_edits.flip(mesh, edge)
            by_hand.append(time.perf_counter() - start)
            start = time.perf_counter()
            mesh.flip(edge)
            library.append(time.perf_counter() - start)
        hand, lib = statistics.median(by_hand) * 1e3, statistics.median(library) * 1e3
        name = Path(source).stem if not source.startswith("shape:") else source
        print(f"| {name} | {len(mesh.faces)} | {hand:.2f} ms | {lib:.3f} ms | {hand / lib:.0f} |")


if __name__ == "__main__":
    main()
