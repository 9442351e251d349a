#!/usr/bin/env python3
"""QEM simplification, Pappus against MeshLab (pymeshlab), side by side in one run.

For each ratio, runs `pappus process MESH -o OUT simplify:RATIO --json` (release build) and
pymeshlab's `meshing_decimation_quadric_edge_collapse` (boundary preserved) on the same input,
and Pappus again with the distance check (`simplify:RATIO:8`, `SimplifyParams::distance_weight`)
and with the fit to the input at the end (`simplify:RATIO:0:fit`, `SimplifyParams::fit_to_input`),
and prints times, face counts and the symmetric Hausdorff distance of each result to the input
as a percentage of the bounding-box diagonal: bounded to within 0.0005 % by
`surface_distance.py`, and pymeshlab's `get_hausdorff_distance` both ways, max, with its default
sampling (median of three) and with a million samples (`meshlab_common.hausdorff_pct`).

Usage: python3 benches/qem_vs_meshlab.py [MESH] (default: ../shared/models/stanford-bunny.obj)
Needs: pip install pymeshlab libigl; cargo build --release.
"""
import os
import tempfile
import time

from meshlab_common import MESH, hausdorff_text, meshset, run_pappus


def main():
    with tempfile.TemporaryDirectory() as tmp:
        for ratio in (0.5, 0.25, 0.1):
            ours = os.path.join(tmp, f"pappus-{ratio}.ply")
            report = run_pappus(MESH, ours, f"simplify:{ratio}")
            checked = os.path.join(tmp, f"pappus-{ratio}-distance.ply")
            checked_report = run_pappus(MESH, checked, f"simplify:{ratio}:8")
            fitted = os.path.join(tmp, f"pappus-{ratio}-fit.ply")
            fitted_report = run_pappus(MESH, fitted, f"simplify:{ratio}:0:fit")
            ms = meshset(MESH)
            faces = ms.current_mesh().face_number()
            start = time.perf_counter()
            ms.meshing_decimation_quadric_edge_collapse(targetfacenum=round(faces * ratio),
                                                        preserveboundary=True, preservenormal=True)
            meshlab_ms = (time.perf_counter() - start) * 1000
            theirs = os.path.join(tmp, f"meshlab-{ratio}.ply")
            ms.save_current_mesh(theirs)
            print(f"ratio {ratio}: Pappus {report['result']['faces']} faces in "
                  f"{report['steps'][0]['ms']:.0f} ms, {hausdorff_text(MESH, ours)} | "
                  f"MeshLab {ms.current_mesh().face_number()} faces in {meshlab_ms:.0f} ms, "
                  f"{hausdorff_text(MESH, theirs)}")
            print(f"  with the distance check: Pappus {checked_report['result']['faces']} faces in "
                  f"{checked_report['steps'][0]['ms']:.0f} ms "
                  f"({checked_report['steps'][0]['ms'] / meshlab_ms:.2f}× MeshLab's), "
                  f"{hausdorff_text(MESH, checked)}")
            print(f"  with the fit: Pappus {fitted_report['result']['faces']} faces in "
                  f"{fitted_report['steps'][0]['ms']:.0f} ms "
                  f"({fitted_report['steps'][0]['ms'] / meshlab_ms:.2f}× MeshLab's), "
                  f"{hausdorff_text(MESH, fitted)}")


if __name__ == "__main__":
    main()
