"""The readers' speed, two Pappus binaries side by side: the bunny as OBJ, PLY, GLB and DAE.

    python3 benches/reader_speed_ab.py OLD_PAPPUS NEW_PAPPUS [MESH] [--runs N]

Writes MESH (default the shared Stanford bunny) as `.obj`, `.ply` and `.glb` with NEW_PAPPUS
and as `.dae` with trimesh (Pappus does not write COLLADA; needs trimesh and pycollada, as in
`benches/reader_corpus.py`'s venv), then runs `pappus info --json` on each file N times
(default 7), the two binaries alternating run by run so that the machine's drift touches both
alike, and prints the median `read_ms` (the parse into a soup) and `load_ms` (parse and build)
of each, with NEW / OLD as a ratio.
"""

import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNS = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 7
ARGS = [a for i, a in enumerate(sys.argv[1:], 1)
        if not a.startswith("--") and sys.argv[i - 1] != "--runs"]
if len(ARGS) < 2:
    sys.exit(__doc__)
OLD, NEW = ARGS[0], ARGS[1]
MESH = ARGS[2] if len(ARGS) > 2 else os.path.join(ROOT, "../shared/models/stanford-bunny.obj")


def info(binary, path):
    out = subprocess.run([binary, "info", "--json", path], capture_output=True, text=True,
                         check=True)
    report = json.loads(out.stdout)
    return report["read_ms"], report["load_ms"]


def files(folder):
    paths = {}
    for ext in ["obj", "ply", "glb"]:
        paths[ext] = os.path.join(folder, f"mesh.{ext}")
        subprocess.run([NEW, "process", MESH, "-o", paths[ext]], check=True,
                       capture_output=True)
    import trimesh  # only for the COLLADA file

    paths["dae"] = os.path.join(folder, "mesh.dae")
    trimesh.load(paths["obj"], force="mesh", process=False).export(paths["dae"])
    return paths


def main():
    paths = files(tempfile.mkdtemp(prefix="pappus-readers-"))
    times = {(who, ext): ([], []) for who in ["old", "new"] for ext in paths}
    for _ in range(RUNS):
        for ext, path in paths.items():
            for who, binary in [("old", OLD), ("new", NEW)]:
                read_ms, load_ms = info(binary, path)
                times[(who, ext)][0].append(read_ms)
                times[(who, ext)][1].append(load_ms)
    print(f"{os.path.basename(MESH)}, median of {RUNS}, alternating (ms)")
    print(f"{'file':<6} {'old read':>9} {'new read':>9} {'ratio':>6}   "
          f"{'old load':>9} {'new load':>9} {'ratio':>6}")
    for ext in paths:
        old_read, old_load = map(statistics.median, times[("old", ext)])
        new_read, new_load = map(statistics.median, times[("new", ext)])
        print(f"{ext:<6} {old_read:9.1f} {new_read:9.1f} {new_read / old_read:6.2f}   "
              f"{old_load:9.1f} {new_load:9.1f} {new_load / old_load:6.2f}")


if __name__ == "__main__":
    main()
