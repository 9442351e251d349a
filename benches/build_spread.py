#!/usr/bin/env python3
"""How much a scan's build time varies from run to run, and whether fresh pages are the cause.

For three scans made here — the Stanford bunny Loop-subdivided twice (1.1 M triangles), an
icosphere of level 8 (1.3 M) and of level 9 (5.2 M), each written as binary PLY by Pappus —
runs `pappus info SCAN --json` RUNS times in fresh processes, the scans in turn, and prints
for each: the build's time (`load_ms - read_ms`: the halfedge entities made from the parsed
soup) as min / median / max, its spread ((max - min) / median), its cost per million faces,
the process's minor page faults (each a fresh page the kernel handed out) and its time in the
kernel (both read by `/usr/bin/time`), with the correlation of the build's time with each over
the runs: faults that do not vary while the time does, and kernel time that follows it, say
the kernel's handing out of pages is where the spread comes from. Each run is made twice: as it
comes, and "warm", right after a child process touched and freed as much memory as the run
before it peaked at (plus 512 MB), so that the pages the build gets were in use a moment ago.
Last, the cost of a fresh page itself: a child touching 4 GB, then another at once. Beside them,
MeshLab's `load_new_mesh` of the same file, the same number of runs in turn, for its own spread.

Usage: python3 benches/build_spread.py [--runs N]   (default 10; needs the `pappus` package,
pymeshlab and the release binary: cargo build --release)
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

from meshlab_common import PAPPUS, write_scans

RUNS = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 10
TOUCH = r"""
import sys, time
import numpy as np
start = time.perf_counter()
a = np.ones(int(float(sys.argv[1]) * 2**20) // 8)
print((time.perf_counter() - start) * 1e6 / (a.nbytes / 4096))
"""
MESHLAB = r"""
import json, sys, time
import pymeshlab
ms = pymeshlab.MeshSet()
start = time.perf_counter()
ms.load_new_mesh(sys.argv[1])
print(json.dumps({"load_ms": (time.perf_counter() - start) * 1000}))
"""


def timed(command):
    """Runs `command` in a fresh process: (stdout, minor page faults, kernel seconds, peak MB)."""
    with tempfile.NamedTemporaryFile("r") as counts:
        result = subprocess.run(["/usr/bin/time", "-f", "%R %S %M", "-o", counts.name, *command],
                                check=True, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                text=True)
        faults, kernel, peak = counts.read().split()[-3:]
        return result.stdout, int(faults), float(kernel), int(peak) / 1024


def touch(mb):
    """A child touches `mb` MB of fresh memory and frees it: microseconds a 4 KB page."""
    return float(subprocess.run([sys.executable, "-c", TOUCH, str(mb)], check=True,
                                stdout=subprocess.PIPE, text=True).stdout)


def pappus_build(path):
    """(build ms, faces, minor faults, kernel s, peak MB) of one `pappus info`."""
    text, faults, kernel, peak = timed([PAPPUS, "info", path, "--json"])
    info = json.loads(text)
    return info["load_ms"] - info["read_ms"], info["faces"], faults, kernel, peak


def meshlab_load(path):
    return json.loads(timed([sys.executable, "-c", MESHLAB, path])[0])["load_ms"]


def row(name, runs, peers):
    """One table row: the build's spread and its kernel share over `runs`, MeshLab's beside."""
    builds = [r[0] for r in runs]
    faults = [r[2] for r in runs]
    kernel = [r[3] for r in runs]
    faces = runs[0][1]
    lo, mid, hi = min(builds), statistics.median(builds), max(builds)
    text = (f"| {name} | {faces} | {lo:.0f} / {mid:.0f} / {hi:.0f} | {100 * (hi - lo) / mid:.0f} % "
            f"| {mid / faces * 1e6:.0f} | {min(faults)} / {max(faults)} "
            f"| {statistics.median(kernel):.2f} "
            f"| {correlation(builds, faults):.2f} / {correlation(builds, kernel):.2f} |")
    if peers:
        m_lo, m_mid, m_hi = min(peers), statistics.median(peers), max(peers)
        text += f" {m_lo:.0f} / {m_mid:.0f} / {m_hi:.0f} | {100 * (m_hi - m_lo) / m_mid:.0f} % |"
    else:
        text += " — | — |"
    return text


def correlation(xs, ys):
    if len(xs) < 3 or statistics.pstdev(xs) == 0 or statistics.pstdev(ys) == 0:
        return float("nan")
    return statistics.correlation(xs, ys)


def main():
    folder = tempfile.mkdtemp(prefix="pappus-spread-")
    scans = write_scans(folder, icosphere_levels=(8, 9))
    # The scans just written are dirty pages the kernel writes back in the background, on the
    # cores the first runs are timed on: written back now, before any run.
    os.sync()
    runs = {name: [] for name, _ in scans}
    warm = {name: [] for name, _ in scans}
    peers = {name: [] for name, _ in scans}
    for r in range(RUNS):
        for name, path in scans:
            runs[name].append(pappus_build(path))
            touch(runs[name][-1][4] + 512)
            warm[name].append(pappus_build(path))
            peers[name].append(meshlab_load(path))
        print(f"run {r + 1} of {RUNS}", file=sys.stderr)
    print(f"| scan | faces | build ms: min / median / max | spread | ms per M faces (median) "
          f"| minor page faults: min / max | kernel s (median) | correlation of the build time "
          f"with faults / with kernel time | MeshLab load ms: min / median / max | its spread |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, _ in scans:
        print(row(name, runs[name], peers[name]))
        print(row(f"{name}, warm", warm[name], []))
    print("\nEach run's build ms, in order (as it comes; warm):")
    for name, _ in scans:
        print(f"- {name}: {' '.join(f'{r[0]:.0f}' for r in runs[name])}; "
              f"{' '.join(f'{r[0]:.0f}' for r in warm[name])}")
    cold, again = touch(4096), touch(4096)
    print(f"\nA fresh 4 KB page: {cold:.2f} us touched first, {again:.2f} us by the next process "
          f"at once (4 GB each).")


if __name__ == "__main__":
    main()
