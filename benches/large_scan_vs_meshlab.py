#!/usr/bin/env python3
"""A million-face scan, Pappus against MeshLab (pymeshlab), side by side in one run: peak memory
to open and save, load time, QEM to 10 % and its cost per collapse against the bunny's.

The scan is built here: the Stanford bunny Loop-subdivided twice (1.1 M triangles) and an
icosphere of level 8 (1.3 M), each written as binary PLY by Pappus. Every figure comes from a
fresh process (peak memory is its maximum resident set, by `/usr/bin/time`), each tool in turn, median of RUNS:
- open and save: `pappus convert SCAN OUT.ply` against pymeshlab's `load_new_mesh` +
  `save_current_mesh` (and pymeshlab's process with only the import, its floor, apart);
- load: `pappus info --json`'s `load_ms` (read + build the halfedge entities; `read_ms` the
  parse) against `load_new_mesh`;
- the bunny's OBJ load, the same way (`pappus info --json`'s `load_ms` against `load_new_mesh`),
  the two alternating run by run;
- QEM to 10 %: `pappus process SCAN --json simplify:0.1`'s step time against
  `meshing_decimation_quadric_edge_collapse` (boundary preserved), and per collapse, against
  the same on the bunny.

With `--sizes`, two more: the ogre Loop-subdivided twice (2.0 M triangles) and an icosphere of
level 9 (5.2 M), for the cost per face across sizes; `--no-qem` leaves out the QEM columns (on
the 5.2 M icosphere MeshLab's QEM alone takes minutes).

Usage: python3 benches/large_scan_vs_meshlab.py [--runs N] [--sizes] [--no-qem]   (needs
pymeshlab, the `pappus` package and the release binary: cargo build --release)
"""
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import pappus
from meshlab_common import PAPPUS, ROOT, write_scans

RUNS = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 3
SIZES = "--sizes" in sys.argv
QEM = "--no-qem" not in sys.argv
BUNNY = os.path.join(ROOT, "../shared/models/stanford-bunny.obj")
MESHLAB = r"""
import json, sys, time
import pymeshlab
what, path, out = sys.argv[1:4]
ms = pymeshlab.MeshSet()
report = {}
if what != "import":
    start = time.perf_counter()
    ms.load_new_mesh(path)
    report["load_ms"] = (time.perf_counter() - start) * 1000
    report["faces"] = ms.current_mesh().face_number()
if what == "save":
    start = time.perf_counter()
    ms.save_current_mesh(out)
    report["save_ms"] = (time.perf_counter() - start) * 1000
if what == "qem":
    faces = ms.current_mesh().face_number()
    start = time.perf_counter()
    ms.meshing_decimation_quadric_edge_collapse(targetfacenum=round(faces * 0.1),
                                                preserveboundary=True, preservenormal=True)
    report["qem_ms"] = (time.perf_counter() - start) * 1000
    report["qem_faces"] = ms.current_mesh().face_number()
print(json.dumps(report))
"""


def measured(command):
    """Runs `command` in a fresh process: (wall seconds, peak resident MB, stdout). The peak is
    read by `/usr/bin/time`, whose child starts small: a child forked from this process would
    start its high-water mark at this process's size."""
    with tempfile.NamedTemporaryFile("r") as peak:
        start = time.perf_counter()
        result = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", peak.name, *command],
                                check=True, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                text=True)
        seconds = time.perf_counter() - start
        return seconds, int(peak.read().split()[-1]) / 1024, result.stdout


def meshlab(what, path, out=os.devnull):
    return measured([sys.executable, "-c", MESHLAB, what, path, out])


def medians(results):
    """The median of each figure over `results` (dicts with the same keys)."""
    return {k: statistics.median(r[k] for r in results) for k in results[0]}


def median_of(fn):
    return medians([fn() for _ in range(RUNS)])


def medians_alternating(a, b):
    """`median_of` of `a` and of `b`, run in turn, so that the machine's drift touches both."""
    pairs = [(a(), b()) for _ in range(RUNS)]
    return medians([p[0] for p in pairs]), medians([p[1] for p in pairs])


def pappus_open_save(path, out):
    seconds, mb, _ = measured([PAPPUS, "convert", path, out])
    return {"s": seconds, "mb": mb}


def meshlab_open_save(path, out):
    seconds, mb, text = meshlab("save", path, out)
    report = json.loads(text)
    return {"s": seconds, "mb": mb, "floor_mb": meshlab("import", path)[1],
            "in_ms": report["load_ms"] + report["save_ms"]}


def pappus_load(path):
    info = json.loads(measured([PAPPUS, "info", path, "--json"])[2])
    return {"load_ms": info["load_ms"], "read_ms": info["read_ms"], "faces": info["faces"]}


def pappus_qem(path, out):
    report = json.loads(measured([PAPPUS, "process", path, "-o", out, "--json", "simplify:0.1"])[2])
    step = report["steps"][0]
    collapses = int(re.search(r"in (\d+) collapses", step["summary"]).group(1))
    return {"ms": step["ms"], "collapses": collapses, "faces": report["result"]["faces"]}


def meshlab_qem(path):
    report = json.loads(meshlab("qem", path)[2])
    # An edge collapse of a closed triangle mesh removes two faces.
    return {"ms": report["qem_ms"], "load_ms": report["load_ms"],
            "collapses": (report["faces"] - report["qem_faces"]) / 2}


def main():
    folder = tempfile.mkdtemp(prefix="pappus-scan-")
    scans = write_scans(folder, icosphere_levels=(8, 9) if SIZES else (8,), ogre=SIZES)
    bunny_ply = os.path.join(folder, "bunny.ply")
    pappus.load(BUNNY).save(bunny_ply)
    out = os.path.join(folder, "out.ply")

    obj_p, obj_m = medians_alternating(lambda: pappus_load(BUNNY),
                                       lambda: json.loads(meshlab("load", BUNNY)[2]))
    print(f"bunny OBJ load: Pappus {obj_p['load_ms']:.0f} ms (read {obj_p['read_ms']:.0f}), "
          f"MeshLab {obj_m['load_ms']:.0f} ms ({obj_p['load_ms'] / obj_m['load_ms']:.2f}×)")
    if QEM:
        base_p = median_of(lambda: pappus_qem(bunny_ply, out))
        base_m = median_of(lambda: meshlab_qem(bunny_ply))
        per_p, per_m = base_p["ms"] / base_p["collapses"], base_m["ms"] / base_m["collapses"]
        print(f"bunny ({base_p['faces'] * 10:.0f} faces) QEM to 10 %: Pappus {base_p['ms']:.0f} ms, "
              f"MeshLab {base_m['ms']:.0f} ms ({base_p['ms'] / base_m['ms']:.2f}×); per collapse "
              f"{per_p * 1000:.2f} µs, MeshLab {per_m * 1000:.2f} µs")
    print("| scan | faces | open + save peak MB: Pappus / MeshLab (its import alone) | ratio | bytes per face: Pappus, MeshLab over its import "
          "| load ms: Pappus (parse) / MeshLab | ratio | QEM to 10 % ms: Pappus / MeshLab | ratio "
          "| per collapse / the bunny's: Pappus, MeshLab |")
    print("|---|---:|---|---:|---|---|---:|---|---:|---|")
    for name, path in scans:
        load_p, load_m = medians_alternating(lambda: pappus_load(path),
                                             lambda: json.loads(meshlab("load", path)[2]))
        ps, ml = medians_alternating(lambda: pappus_open_save(path, out),
                                     lambda: meshlab_open_save(path, out))
        faces = load_p["faces"]
        qem = "— / — | — | —"
        if QEM:
            pq = median_of(lambda: pappus_qem(path, out))
            mq = median_of(lambda: meshlab_qem(path))
            qem = (f"{pq['ms']:.0f} / {mq['ms']:.0f} | {pq['ms'] / mq['ms']:.2f} "
                   f"| {pq['ms'] / pq['collapses'] / per_p:.2f}, "
                   f"{mq['ms'] / mq['collapses'] / per_m:.2f}")
        print(f"| {name} | {faces:,} | {ps['mb']:.0f} / {ml['mb']:.0f} ({ml['floor_mb']:.0f}) "
              f"| {ps['mb'] / ml['mb']:.1f} | {ps['mb'] * 2**20 / faces:.0f} B, "
              f"{(ml['mb'] - ml['floor_mb']) * 2**20 / faces:.0f} B over its import "
              f"| {load_p['load_ms']:.0f} ({load_p['read_ms']:.0f}) / {load_m['load_ms']:.0f} "
              f"| {load_p['load_ms'] / load_m['load_ms']:.2f} | {qem} |", flush=True)

if __name__ == "__main__":
    main()
