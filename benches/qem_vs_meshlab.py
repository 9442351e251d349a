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
Times are the medians of RUNS (environment, default 5) runs of each, taken in turn, and the
ratios those medians' (one run varies by a fifth on the 2-core development machine).

Usage: python3 benches/qem_vs_meshlab.py [MESH] (default: ../shared/models/stanford-bunny.obj)
Needs: pip install pymeshlab libigl; cargo build --release.
"""
import os
import statistics
import tempfile
import time

from meshlab_common import MESH, hausdorff_text, meshset, run_pappus, spread


RUNS = int(os.environ.get("RUNS", "5"))


def meshlab_run(ratio, out):
    """MeshLab's simplification of MESH to `ratio` of its faces, saved to `out`: its ms and
    faces."""
    ms = meshset(MESH)
    faces = ms.current_mesh().face_number()
    start = time.perf_counter()
    ms.meshing_decimation_quadric_edge_collapse(targetfacenum=round(faces * ratio),
                                                preserveboundary=True, preservenormal=True)
    meshlab_ms = (time.perf_counter() - start) * 1000
    ms.save_current_mesh(out)
    return meshlab_ms, ms.current_mesh().face_number()


def main():
    with tempfile.TemporaryDirectory() as tmp:
        for ratio in (0.5, 0.25, 0.1):
            steps = {"plain": f"simplify:{ratio}", "check": f"simplify:{ratio}:8",
                     "fit": f"simplify:{ratio}:0:fit"}
            outs = {k: os.path.join(tmp, f"pappus-{ratio}-{k}.ply") for k in steps}
            theirs = os.path.join(tmp, f"meshlab-{ratio}.ply")
            times = {k: [] for k in (*steps, "meshlab")}
            faces = {}
            for _ in range(RUNS):
                for k, step in steps.items():
                    report = run_pappus(MESH, outs[k], step)
                    times[k].append(report["steps"][0]["ms"])
                    faces[k] = report["result"]["faces"]
                meshlab_ms, faces["meshlab"] = meshlab_run(ratio, theirs)
                times["meshlab"].append(meshlab_ms)
            theirs_ms = statistics.median(times["meshlab"])

            def ratio_text(k):
                return f"{statistics.median(times[k]) / theirs_ms:.2f}× MeshLab's"
            print(f"ratio {ratio}: Pappus {faces['plain']} faces in {spread(times['plain'])}, "
                  f"{ratio_text('plain')}, {hausdorff_text(MESH, outs['plain'])} | "
                  f"MeshLab {faces['meshlab']} faces in {spread(times['meshlab'])}, "
                  f"{hausdorff_text(MESH, theirs)}")
            print(f"  with the distance check: Pappus {faces['check']} faces in "
                  f"{spread(times['check'])}, {ratio_text('check')}, "
                  f"{hausdorff_text(MESH, outs['check'])}")
            print(f"  with the fit: Pappus {faces['fit']} faces in {spread(times['fit'])}, "
                  f"{ratio_text('fit')}, {hausdorff_text(MESH, outs['fit'])}")


if __name__ == "__main__":
    main()
