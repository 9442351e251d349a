#!/usr/bin/env python3
"""Bulk operations, A/B: two (or more) builds of `pappus`, alternating run by run, each
operation's own time (the `process --json` step's `ms`, or `info --json`'s `load_ms` for loading),
median / p90 / max over RUNS runs. For changes that must not trade a faster median for stalls.

Usage: python3 benches/bulk_ab.py BINARY [BINARY ...]   (RUNS=10 by default, env RUNS=N;
ONLY=Loop,load runs only the cases whose label holds one of those words)
Uses ../shared/models (the bunny, beast).
"""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = os.path.join(ROOT, "../shared/models")
RUNS = int(os.environ.get("RUNS", "10"))
BUNNY = os.path.join(MODELS, "stanford-bunny.obj")
BEAST = os.path.join(MODELS, "beast.obj")

# (label, input, steps, which step's time): a step index, or "load" for info's load_ms.
CASES_ALL = [
    ("load the bunny (read + build)", BUNNY, None, "load"),
    ("Loop x1, bunny", BUNNY, ["loop:1"], 0),
    ("Loop x2, bunny", BUNNY, ["loop:2"], 0),
    ("Catmull-Clark x1, beast", BEAST, ["catmull-clark:1"], 0),
    ("QEM to 25 %, bunny", BUNNY, ["simplify:0.25"], 0),
    ("remesh, bunny", BUNNY, ["remesh"], 0),
    ("refine back after simplify:0.01, bunny", BUNNY, ["simplify:0.01", "refine"], 1),
]
# ONLY=word[,word...] keeps the cases whose label contains one of the words (e.g. ONLY=Loop,load).
ONLY = [w for w in os.environ.get("ONLY", "").split(",") if w]
CASES = [c for c in CASES_ALL if not ONLY or any(w in c[0] for w in ONLY)]


def one(binary, source, steps, which, out):
    if which == "load":
        result = subprocess.run([binary, "info", source, "--json"], capture_output=True, text=True)
        return json.loads(result.stdout)["load_ms"]
    result = subprocess.run([binary, "process", source, "-o", out, "--json", *steps],
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{binary}: {result.stderr[-2000:]}")
    return json.loads(result.stdout)["steps"][which]["ms"]


def stats(times):
    times = sorted(times)
    at = lambda q: times[round((len(times) - 1) * q)]
    return at(0.5), at(0.9), times[-1]


def main():
    binaries = sys.argv[1:]
    if not binaries:
        sys.exit(__doc__)
    print(f"median / p90 / max of {RUNS} runs, ms, binaries alternating run by run")
    print()
    print("| operation | " + " | ".join(os.path.basename(b) for b in binaries) + " |")
    print("|---|" + "---:|" * len(binaries))
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.obj")
        for label, source, steps, which in CASES:
            if not os.path.exists(source):
                print(f"| {label} | (missing {source}) |")
                continue
            times = {b: [] for b in binaries}
            for _ in range(RUNS):
                for b in binaries:
                    times[b].append(one(b, source, steps, which, out))
            cells = ["%.0f / %.0f / %.0f" % stats(times[b]) for b in binaries]
            print(f"| {label} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
