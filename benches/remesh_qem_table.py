#!/usr/bin/env python3
"""Remeshing and QEM against MeshLab on every shared model, one run, as a Markdown table.

Each model is read by pymeshlab (polygons triangulated, unreferenced vertices dropped) and
saved as the PLY both tools then read, so that both work on the same triangles. Then:

- remeshing: `pappus process IN -o OUT remesh:5:L` against pymeshlab's
  `meshing_isotropic_explicit_remeshing(iterations=5, targetlen=L)`, L the mean edge length;
- QEM to 25 % of the faces: `pappus process IN -o OUT simplify:0.25` against
  `meshing_decimation_quadric_edge_collapse` (boundary and normals preserved), as
  `qem_vs_meshlab.py` runs them, and Pappus again fitted to the input at the end
  (`simplify:0.25:0:fit`), against the same MeshLab run.

Times are Pappus's step (`--json`) and the pymeshlab call alone; the ratio is Pappus's over
MeshLab's. Distances are the symmetric Hausdorff distance to the input, bounded to within
0.0005 % of the bounding-box diagonal (`surface_distance.py`), in % of that diagonal.

Usage: python3 benches/remesh_qem_table.py [MODEL ...] (default: every OBJ in ../shared/models)
Needs: pip install pymeshlab numpy libigl; cargo build --release.
"""
import glob
import os
import sys
import tempfile
import time

import numpy as np
import pymeshlab

from meshlab_common import ROOT, run_pappus
from surface_distance import hausdorff_pct as bounded_hausdorff, text as bounded_text


def mean_edge_length(ms):
    m = ms.current_mesh()
    v, f = m.vertex_matrix(), m.face_matrix()
    edges = np.unique(np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), 1),
                      axis=0)
    return float(np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1).mean())


def timed(call):
    start = time.perf_counter()
    call()
    return (time.perf_counter() - start) * 1000


def row(model, tmp):
    name = os.path.splitext(os.path.basename(model))[0]
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(model)
    ms.meshing_remove_unreferenced_vertices()
    source = os.path.join(tmp, f"{name}.ply")
    ms.save_current_mesh(source)
    faces = ms.current_mesh().face_number()
    length = mean_edge_length(ms)
    cells = [name, f"{faces}"]

    ours = os.path.join(tmp, f"{name}-remesh-pappus.ply")
    try:
        ours_ms = run_pappus(source, ours, f"remesh:5:{length}")["steps"][0]["ms"]
    except Exception as refused:  # a refusal is a cell of the table, not the end of the run
        ours_ms = None
        print(f"{name}: Pappus refused remesh: {refused}", file=sys.stderr)
    theirs = os.path.join(tmp, f"{name}-remesh-meshlab.ply")
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(source)
    meshlab_ms = timed(lambda: ms.meshing_isotropic_explicit_remeshing(
        iterations=5, targetlen=pymeshlab.PureValue(length)))
    ms.save_current_mesh(theirs)
    cells += remesh_or_qem_cells(source, ours, ours_ms, theirs, meshlab_ms)

    ours = os.path.join(tmp, f"{name}-qem-pappus.ply")
    ours_ms = run_pappus(source, ours, "simplify:0.25")["steps"][0]["ms"]
    theirs = os.path.join(tmp, f"{name}-qem-meshlab.ply")
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(source)
    meshlab_ms = timed(lambda: ms.meshing_decimation_quadric_edge_collapse(
        targetfacenum=round(faces * 0.25), preserveboundary=True, preservenormal=True))
    ms.save_current_mesh(theirs)
    cells += remesh_or_qem_cells(source, ours, ours_ms, theirs, meshlab_ms)
    fitted = os.path.join(tmp, f"{name}-qem-fit-pappus.ply")
    fitted_ms = run_pappus(source, fitted, "simplify:0.25:0:fit")["steps"][0]["ms"]
    cells += [f"{fitted_ms:.0f}", f"{fitted_ms / meshlab_ms:.2f}",
              bounded_text(bounded_hausdorff(source, fitted))]
    return "| " + " | ".join(cells) + " |"


def remesh_or_qem_cells(source, ours, ours_ms, theirs, meshlab_ms):
    """Times with the ratio, and both distances, as table cells."""
    if ours_ms is None:
        return [f"refused / {meshlab_ms:.0f}", "—", "—",
                bounded_text(bounded_hausdorff(source, theirs))]
    return [f"{ours_ms:.0f} / {meshlab_ms:.0f}", f"{ours_ms / meshlab_ms:.2f}",
            bounded_text(bounded_hausdorff(source, ours)),
            bounded_text(bounded_hausdorff(source, theirs))]


def main():
    models = sys.argv[1:] or sorted(glob.glob(os.path.join(ROOT, "../shared/models/*.obj")))
    print("| model | faces | remesh ms: Pappus / MeshLab | ratio | Hausdorff %: Pappus | MeshLab "
          "| QEM 25 % ms: Pappus / MeshLab | ratio | Hausdorff %: Pappus | MeshLab "
          "| fitted (`:0:fit`) ms | ratio | Hausdorff % |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for model in models:
            print(row(model, tmp), flush=True)


if __name__ == "__main__":
    main()
