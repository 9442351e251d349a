"""A folder of meshes three ways, in one run: `pappus process -j 2` (threads in one process), a
`dask.distributed` LocalCluster of two worker processes mapping `pappus.process_file`, and a
plain Python loop.

    python3 benches/dask_vs_process.py [BINARY] [--copies N] [--rounds N]

Needs the `pappus` package (`pip install ./`), `dask[distributed]`, and the release binary
(default `$CARGO_TARGET_DIR/release/pappus`). The folder is every shared model linked N times
(default 4) under new names, so it holds 10·N files. Steps: `triangulate simplify:0.5`.
Rounds (default 3) alternate the three ways so the machine's drift touches all alike; each
prints its seconds. The cluster's start (processes spawned, `pappus` imported) is timed apart
from the map, since a long-lived cluster pays it once. Every output is checked to be the same
bytes whichever way made it.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from dask.distributed import Client, LocalCluster

import pappus

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / ".." / "shared" / "models"
STEPS = ["triangulate", "simplify:0.5"]


def option(name, default):
    return int(sys.argv[sys.argv.index(name) + 1]) if name in sys.argv else default


def main():
    args = [a for i, a in enumerate(sys.argv[1:], 1)
            if not a.startswith("--") and not sys.argv[i - 1].startswith("--")]
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    binary = args[0] if args else str(target / "release" / "pappus")
    copies, rounds = option("--copies", 4), option("--rounds", 3)
    folder = Path(tempfile.mkdtemp(prefix="pappus-dask-"))
    inputs = folder / "in"
    inputs.mkdir()
    for model in sorted(MODELS.glob("*.obj")):
        for k in range(copies):
            (inputs / f"{model.stem}-{k}.obj").symlink_to(model.resolve())
    paths = sorted(str(p) for p in inputs.iterdir())
    print(f"{len(paths)} files, {sum(os.path.getsize(p) for p in paths) / 1e6:.0f} MB, "
          f"steps {' '.join(STEPS)}")

    times = {"process -j 2": [], "dask map": [], "dask start": [], "python loop": []}
    for round in range(rounds):
        out = folder / f"r{round}"
        start = time.perf_counter()
        subprocess.run([binary, "process", str(inputs / "*.obj"), "-o", str(out / "cli" / "{stem}.ply"),
                        "-j", "2", *STEPS], check=True, stdout=subprocess.DEVNULL)
        times["process -j 2"].append(time.perf_counter() - start)

        start = time.perf_counter()
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            client.run(lambda: __import__("pappus").__version__)
            times["dask start"].append(time.perf_counter() - start)
            start = time.perf_counter()
            client.gather(client.map(pappus.process_file, paths, steps=STEPS,
                                     output=str(out / "dask" / "{stem}.ply")))
            times["dask map"].append(time.perf_counter() - start)

        start = time.perf_counter()
        for p in paths:
            pappus.process_file(p, STEPS, out / "loop" / "{stem}.ply")
        times["python loop"].append(time.perf_counter() - start)

        for p in paths:
            name = pappus.output_stem(p) + ".ply"
            cli = (out / "cli" / name).read_bytes()
            assert cli == (out / "dask" / name).read_bytes() == (out / "loop" / name).read_bytes(), name
        print(f"round {round + 1}: " + ", ".join(f"{k} {v[-1]:.2f} s" for k, v in times.items()))

    median = {k: statistics.median(v) for k, v in times.items()}
    print("median: " + ", ".join(f"{k} {v:.2f} s" for k, v in median.items()))
    print(f"dask map / process -j 2: {median['dask map'] / median['process -j 2']:.2f}; "
          f"with its start: {(median['dask map'] + median['dask start']) / median['process -j 2']:.2f}; "
          f"python loop / process -j 2: {median['python loop'] / median['process -j 2']:.2f}")


if __name__ == "__main__":
    main()
