#!/usr/bin/env python3
"""How much a remesh's figures owe to its exact target length: `remesh:5:L` at the mean edge
length L times 0.995, 0.998, 1, 1.002 and 1.005, each result measured as
`remesh_vs_meshlab.py` measures it (the bounded Hausdorff distance to the input in % of the
diagonal, triangles under 30 degrees in %, interior vertices of valence 6 in %).

The remesh's farthest point is one spot, and lengths a few thousandths apart put it in other
places: a figure at one length says little unless the lengths beside it agree.

Usage: python3 benches/remesh_lengths.py [MESH] [PAPPUS ...] (default: the shared bunny and
the release build; several binaries are run side by side at each length, for an A/B).
Needs: pip install pymeshlab numpy libigl; cargo build --release.
"""
import os
import subprocess
import sys
import tempfile

from meshlab_common import MESH, PAPPUS, meshset
from remesh_vs_meshlab import mean_edge_length, quality
from surface_distance import hausdorff_pct

FACTORS = (0.995, 0.998, 1.0, 1.002, 1.005)


def main():
    binaries = sys.argv[2:] or [PAPPUS]
    with tempfile.TemporaryDirectory() as tmp:
        # Both tools' reading of the input: saved once by pymeshlab, as the other scripts do.
        path = os.path.join(tmp, "input.ply")
        meshset(MESH).save_current_mesh(path)
        length = mean_edge_length(path)
        print(f"{os.path.basename(MESH)}: mean edge length {length:.6f}; "
              "per binary: Hausdorff % / thin % / valence 6 %")
        for factor in FACTORS:
            row = []
            for binary in binaries:
                out = os.path.join(tmp, "out.ply")
                subprocess.run([binary, "process", path, "-o", out,
                                f"remesh:5:{length * factor}"], check=True, capture_output=True)
                thin, six, _ = quality(out)
                low, _ = hausdorff_pct(path, out)
                row.append(f"{low:.4f} / {thin:.3f} / {six:.2f}")
            print(f"x {factor}: " + "   ".join(row), flush=True)


if __name__ == "__main__":
    main()
