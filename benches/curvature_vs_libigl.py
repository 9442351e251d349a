#!/usr/bin/env python3
"""Discrete curvature and smoothing: Pappus against libigl and MeshLab (pymeshlab), side by side
in one run, on the same input (default: the shared Stanford bunny). Prints two Markdown tables,
ready for a README: times, and how far Pappus's values are from libigl's and MeshLab's.

Every time is the median of 5 runs, in milliseconds, of the computation alone (no loading, no
writing): for Pappus the time its JSON reports, for the peers `time.perf_counter` around the
calls.

Pappus (the release build, or the binary named by `PAPPUS=/path/to/pappus`):
  - `pappus process MESH -o OUT.ply --json --quantity NAME` for NAME in mean, gaussian,
    angle-defect, max-curvature, min-curvature: the JSON's `quantity.ms` (extracting the mesh's
    tables and computing the quantity on every vertex). OUT.ply carries the values as the
    per-vertex `quality` (f32), read back with pymeshlab, which takes it as the vertex scalar.
    Curvature after Meyer et al. 2003: H = -1/2 (L x)_i . n_i / A_i (cotangent Laplacian L,
    mixed Voronoi areas A, angle-weighted normals n), the angle defect 2 pi - sum of angles
    (pi - ... on the boundary), K = defect / A, k1,2 = H +- sqrt(max(H^2 - K, 0)).
  - `pappus process MESH -o OUT.obj --json smooth:METHOD:1[:STEP]`: the step's `ms`, for the
    implicit step (lambda = 1), one cotangent step and one Taubin step (lambda = 0.5).

libigl (Python package `igl`), on the mesh with its unreferenced vertices removed
(`igl.remove_unreferenced`, as Pappus's loader drops them) and its positions rounded to f32
(as Pappus reads them), so that differences are the methods' and not the input's:
  - `igl.cotmatrix`, `igl.massmatrix(V, F, MASSMATRIX_TYPE_VORONOI)` (Meyer's mixed areas too);
  - mean curvature as in libigl's tutorial 203: HN = -M^-1 L V (the mean-curvature normal,
    2 H n), H = 1/2 |HN|, signed by HN . n with `igl.per_vertex_normals` (angle-weighted, as
    Pappus's). The tutorial itself takes |HN|, which is 2|H|. Timed as cotmatrix + massmatrix
    + normals + H together;
  - `igl.gaussian_curvature`: the raw angle defect 2 pi - sum of angles (not divided by an
    area), which is Pappus's `angle-defect` at interior vertices;
  - `igl.principal_curvature` (quadric fitting over a 5-ring: another estimator, compared
    loosely);
  - one implicit smoothing step as libigl's tutorial 205: S = M - delta L, solve S x = M v.
    Pappus's step solves (M + h K) x = M v with K = -L the positive semi-definite cotangent
    stiffness matrix (diagonal sum of weights, off-diagonal -w_ij) and h = lambda * l^2, l the
    mean edge length: the same matrix, so delta = lambda * l^2 here (lambda = 1). Differences:
    Pappus holds the boundary vertices (Dirichlet rows) and factors with faer's sparse
    Cholesky; the tutorial moves every vertex, and SciPy has no sparse Cholesky, so the solve
    is SuperLU's LU (`scipy.sparse.linalg.factorized`), factored once for the three
    coordinates. Timed as cotmatrix + massmatrix + mean edge length + factor + solve.

MeshLab (pymeshlab), on the mesh loaded with its unreferenced vertices removed:
  - `compute_scalar_by_discrete_curvature_per_vertex`, Mean and Gaussian (Meyer et al. too);
  - `apply_coord_laplacian_smoothing(stepsmoothnum=1, cotangentweight=True)`: one step of
    cotangent-weighted averaging (MeshLab's own step size, not lambda = 0.5);
  - `apply_coord_taubin_smoothing(stepsmoothnum=1)`: lambda 0.5, mu -0.53 (Pappus's mu is
    -0.5 / (1 - 0.5 * 0.1) = -0.526).

Agreement: Pappus's values are matched to the peers' vertices by position (f32, exactly; the
output drops unreferenced vertices and may order vertices its own way), and compared on interior
vertices (`igl.is_border_vertex`; the boundary's curvature is a convention, and the bunny has 5
holes) where both are finite. The relative difference is |a - b| / max(|b|, 1 % of the median
|b|), so that values near 0 are measured against the quantity's scale instead of themselves;
the correlation is the figure for libigl's principal curvatures, a smoother estimator (on a
scanned mesh the one-ring values and a 5-ring quadric fit differ vertex by vertex). Pappus
writes its values as f32, so 6e-8 relative is agreement to the last bit.

Usage: python3 benches/curvature_vs_libigl.py [MESH] [--peers-only]
       (default MESH: ../shared/models/stanford-bunny.obj, relative to the repository root;
       --peers-only skips Pappus: libigl and MeshLab times alone)
Needs: pip install libigl pymeshlab numpy scipy; cargo build --release (or PAPPUS=...).
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from importlib import metadata

import igl
import numpy as np
import pymeshlab
import scipy
import scipy.sparse.linalg
from scipy.spatial import cKDTree

from meshlab_common import PAPPUS as DEFAULT_PAPPUS
from meshlab_common import ROOT, meshset

RUNS = 5
PAPPUS = os.environ.get("PAPPUS") or DEFAULT_PAPPUS
QUANTITIES = ["mean", "gaussian", "angle-defect", "max-curvature", "min-curvature"]
SMOOTHING = {"implicit": "smooth:implicit:1:1", "cotan": "smooth:cotan:1",
             "taubin": "smooth:taubin:1"}


def median_ms(run):
    """The median of RUNS calls of `run`, each returning (ms, value), and the last value."""
    results = [run() for _ in range(RUNS)]
    return float(np.median([ms for ms, _ in results])), results[-1][1]


def stopwatch(work):
    """Runs `work()` and returns (its time in ms, its result)."""
    start = time.perf_counter()
    result = work()
    return (time.perf_counter() - start) * 1000, result


# --- Pappus -------------------------------------------------------------------------------

def pappus(*args):
    """Runs `pappus process ARGS...` and returns its JSON report; exits with a clear message when
    the binary is missing or too old for the interface this script uses."""
    command = [PAPPUS, "process", *args]
    try:
        result = subprocess.run(command, capture_output=True, text=True)
    except FileNotFoundError:
        sys.exit(f"no Pappus binary at {PAPPUS}: run `cargo build --release` (with the "
                 "CARGO_TARGET_DIR you use) or set PAPPUS=/path/to/pappus; "
                 "--peers-only runs libigl and MeshLab alone")
    if result.returncode != 0:
        err = result.stderr.strip()
        if "--quantity" in err and "unexpected argument" in err:
            sys.exit(f"{PAPPUS} has no `process --quantity` (built before it landed): rebuild "
                     f"it with `cargo build --release`.\npappus said: {err}")
        if "unknown step" in err and "smooth" in err:
            sys.exit(f"{PAPPUS} has no `smooth:...` step (built before it landed): rebuild it "
                     f"with `cargo build --release`.\npappus said: {err}")
        sys.exit(f"`{' '.join(command)}` failed (exit {result.returncode}):\n{err}")
    return json.loads(result.stdout)


def read_quality(path):
    """The vertices (f32) and per-vertex `quality` of a PLY file, as pymeshlab reads them."""
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(path)
    m = ms.current_mesh()
    if not m.has_vertex_scalar():
        sys.exit(f"{path}: no per-vertex quality (pymeshlab finds no vertex scalar)")
    return m.vertex_matrix().astype(np.float32), m.vertex_scalar_array().copy()


def pappus_side(mesh, tmp):
    """Pappus's times ({label: ms}) and per-vertex values ({quantity: (positions, values)})."""
    times, values = {}, {}
    for name in QUANTITIES:
        out = os.path.join(tmp, f"{name}.ply")

        def run():
            report = pappus(mesh, "-o", out, "--json", "--quantity", name)
            if "quantity" not in report:
                sys.exit(f"{PAPPUS}: the JSON has no `quantity` key: {sorted(report)}")
            return report["quantity"]["ms"], None

        times[name], _ = median_ms(run)
        values[name] = read_quality(out)
    for label, step in SMOOTHING.items():
        out = os.path.join(tmp, f"{label}.obj")
        times[label], _ = median_ms(
            lambda: (pappus(mesh, "-o", out, "--json", step)["steps"][0]["ms"], None))
    return times, values


# --- libigl -------------------------------------------------------------------------------

def load_for_libigl(mesh):
    """The mesh as libigl sees it once its unreferenced vertices are removed, positions rounded
    to f32 (as Pappus reads them): (V, F, V as f32)."""
    v, f = igl.read_triangle_mesh(mesh)
    v, f, _, _ = igl.remove_unreferenced(v, f)
    v32 = v.astype(np.float32)
    return v32.astype(np.float64), f, v32


def igl_mean_curvature(v, f):
    """H = 1/2 |HN| signed by HN . n, and Pappus's own definition -1/2 (L V)_i . n_i / A_i with
    libigl's matrices: (H, H projected)."""
    lap = igl.cotmatrix(v, f)
    mass = igl.massmatrix(v, f, igl.MASSMATRIX_TYPE_VORONOI)
    normals = igl.per_vertex_normals(v, f, igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_ANGLE)
    with np.errstate(divide="ignore", invalid="ignore"):
        hn = -(lap @ v) / mass.diagonal()[:, None]
    along = np.einsum("ij,ij->i", hn, normals)
    h = 0.5 * np.linalg.norm(hn, axis=1) * np.sign(along)
    return h, 0.5 * along


def igl_implicit_step(v, f, lam=1.0):
    """One backward Euler step of mean-curvature flow, tutorial 205's way, delta = lam * l^2."""
    lap = igl.cotmatrix(v, f)
    mass = igl.massmatrix(v, f, igl.MASSMATRIX_TYPE_VORONOI)
    e = igl.edges(f)
    mean_length = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1).mean()
    delta = lam * mean_length ** 2
    solve = scipy.sparse.linalg.factorized((mass - delta * lap).tocsc())
    rhs = mass @ v
    return np.column_stack([solve(rhs[:, k]) for k in range(3)])


def libigl_side(v, f):
    """libigl's times ({label: ms}) and values ({label: per-vertex array})."""
    times, values = {}, {}
    times["cotmatrix"], _ = median_ms(lambda: stopwatch(lambda: igl.cotmatrix(v, f)))
    times["massmatrix"], _ = median_ms(
        lambda: stopwatch(lambda: igl.massmatrix(v, f, igl.MASSMATRIX_TYPE_VORONOI)))
    times["mean"], (values["mean"], values["mean projected"]) = median_ms(
        lambda: stopwatch(lambda: igl_mean_curvature(v, f)))
    times["angle-defect"], values["angle-defect"] = median_ms(
        lambda: stopwatch(lambda: igl.gaussian_curvature(v, f)))
    times["principal"], principal = median_ms(
        lambda: stopwatch(lambda: igl.principal_curvature(v, f)))
    _, _, values["max-curvature"], values["min-curvature"], _ = principal
    times["implicit"], _ = median_ms(lambda: stopwatch(lambda: igl_implicit_step(v, f)))
    return times, values


# --- MeshLab ------------------------------------------------------------------------------

def meshlab_filter(mesh, apply):
    """The median time of `apply(ms)` on a freshly loaded MeshSet, and the vertices (f32) and
    vertex scalar after the last run (None when the filter leaves none)."""
    def run():
        ms = meshset(mesh)
        t, _ = stopwatch(lambda: apply(ms))
        m = ms.current_mesh()
        scalar = m.vertex_scalar_array().copy() if m.has_vertex_scalar() else None
        return t, (m.vertex_matrix().astype(np.float32), scalar)
    return median_ms(run)


def meshlab_side(mesh):
    """MeshLab's times ({label: ms}) and values ({label: (positions, values)})."""
    times, values = {}, {}
    for label, kind in [("mean", "Mean Curvature"), ("gaussian", "Gaussian Curvature")]:
        times[label], values[label] = meshlab_filter(
            mesh, lambda ms: ms.compute_scalar_by_discrete_curvature_per_vertex(curvaturetype=kind))
    times["cotan"], _ = meshlab_filter(
        mesh, lambda ms: ms.apply_coord_laplacian_smoothing(stepsmoothnum=1, cotangentweight=True))
    times["taubin"], _ = meshlab_filter(
        mesh, lambda ms: ms.apply_coord_taubin_smoothing(stepsmoothnum=1))
    return times, values


# --- agreement ----------------------------------------------------------------------------

def on_reference(points, values, reference):
    """`values` (one per point) moved onto the reference vertices they sit on (f32 position,
    exactly; NaN where no point, or two, sit), and how many points found no vertex."""
    lookup = {p.tobytes(): i for i, p in enumerate(reference)}
    index = np.array([lookup.get(p.tobytes(), -1) for p in points])
    if (index < 0).any():
        # A last resort for a position parsed one ulp apart: the nearest vertex, very close.
        scale = np.linalg.norm(reference.max(0) - reference.min(0))
        d, near = cKDTree(reference).query(points[index < 0], distance_upper_bound=1e-6 * scale)
        index[index < 0] = np.where(np.isfinite(d), near, -1)
    out = np.full(len(reference), np.nan)
    found = index >= 0
    counts = np.bincount(index[found], minlength=len(reference))
    single = found & (counts[np.maximum(index, 0)] == 1)
    out[index[single]] = values[single]
    return out, int((~found).sum())


def compare(a, b, mask):
    """Differences of a from b where mask holds and both are finite, as a table row's cells:
    count, median, p99 and max of rel = |a - b| / max(|b|, 1 % of the median |b|), max |a - b|,
    and Pearson's correlation (the measure for estimators that differ by design)."""
    keep = mask & np.isfinite(a) & np.isfinite(b)
    a, b = a[keep], b[keep]
    diff = np.abs(a - b)
    floor = 0.01 * np.median(np.abs(b))
    rel = diff / np.maximum(np.abs(b), floor)
    figures = [np.median(rel), np.percentile(rel, 99), rel.max(), diff.max()]
    return [str(len(a))] + [f"{x:.2e}" for x in figures] + [f"{np.corrcoef(a, b)[0, 1]:.6f}"]


# --- the tables ---------------------------------------------------------------------------

def cell(times, key, note=""):
    if times is None or key not in times:
        return "—"
    return f"{times[key]:.1f}{note}"


def version(package):
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "?"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mesh", nargs="?",
                        default=os.path.join(ROOT, "../shared/models/stanford-bunny.obj"))
    parser.add_argument("--peers-only", action="store_true",
                        help="skip Pappus: libigl and MeshLab alone")
    args = parser.parse_args()
    mesh = os.path.abspath(args.mesh)

    v, f, v32 = load_for_libigl(mesh)
    interior = ~np.array(igl.is_border_vertex(f), dtype=bool)

    with tempfile.TemporaryDirectory() as tmp:
        # Pappus first: a missing or old binary stops the script before the long part.
        p_times, p_values = (None, None) if args.peers_only else pappus_side(mesh, tmp)
        l_times, l_values = libigl_side(v, f)
        m_times, m_values = meshlab_side(mesh)

    print(f"Input: `{os.path.relpath(mesh, ROOT)}`: {len(v)} referenced vertices "
          f"({int((~interior).sum())} on the boundary), {len(f)} triangles. "
          f"Median of {RUNS} runs, ms; {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} logical CPUs.")
    print(f"Pappus: `{PAPPUS}`" if p_times else "Pappus: skipped (--peers-only)")
    print(f"libigl {version('libigl')}, pymeshlab {version('pymeshlab')}, "
          f"SciPy {scipy.__version__}, NumPy {np.__version__}.")
    print()
    print("| Operation | Pappus | libigl | MeshLab |")
    print("|---|---:|---:|---:|")
    rows = [
        ("Mean curvature H (cotangent Laplacian, mixed areas)", cell(p_times, "mean"),
         cell(l_times, "mean", " ¹"), cell(m_times, "mean")),
        ("Gaussian curvature K = defect / area", cell(p_times, "gaussian"), "—",
         cell(m_times, "gaussian")),
        ("Angle defect 2π − Σθ", cell(p_times, "angle-defect"),
         cell(l_times, "angle-defect"), "—"),
        ("Principal curvatures κ₁ / κ₂", f"{cell(p_times, 'max-curvature')} / "
         f"{cell(p_times, 'min-curvature')}" if p_times else "—",
         cell(l_times, "principal", " ²"), "—"),
        ("Cotangent matrix (`igl.cotmatrix`)", "—", cell(l_times, "cotmatrix"), "—"),
        ("Mass matrix, Voronoi (`igl.massmatrix`)", "—", cell(l_times, "massmatrix"), "—"),
        ("Implicit smoothing, 1 step, δ = ℓ²", cell(p_times, "implicit"),
         cell(l_times, "implicit", " ³"), "—"),
        ("Cotangent Laplacian smoothing, 1 step", cell(p_times, "cotan"), "—",
         cell(m_times, "cotan", " ⁴")),
        ("Taubin λ\\|μ smoothing, 1 step", cell(p_times, "taubin"), "—",
         cell(m_times, "taubin")),
    ]
    for row in rows:
        print("| " + " | ".join(row) + " |")
    print()
    print("- ¹ cotmatrix + massmatrix + angle-weighted normals + H = ½\\|M⁻¹LV\\|, signed.")
    print("- ² quadric fitting (radius 5), another estimator: both values in one call.")
    print("- ³ cotmatrix + massmatrix + mean edge length + SuperLU factor and solve (SciPy has "
          "no sparse Cholesky); Pappus holds the boundary, the tutorial does not.")
    print("- ⁴ MeshLab's own step (a cotangent-weighted average); Pappus's λ = 0.5.")

    if p_values is None:
        return
    print()
    print("| Pappus | against | vertices | median rel. | p99 rel. | max rel. | max abs. "
          "| correlation |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    pairs = [
        ("mean", "libigl ½\\|M⁻¹LV\\| signed", l_values["mean"]),
        ("mean", "libigl −½ (M⁻¹LV)·n", l_values["mean projected"]),
        ("angle-defect", "`igl.gaussian_curvature`", l_values["angle-defect"]),
        ("max-curvature", "`igl.principal_curvature` κ₁ (loose)", l_values["max-curvature"]),
        ("min-curvature", "`igl.principal_curvature` κ₂ (loose)", l_values["min-curvature"]),
    ]
    lost = {}
    for name, against, theirs in pairs:
        ours, lost[name] = on_reference(*p_values[name], v32)
        print("| " + " | ".join([name, against, *compare(ours, theirs, interior)]) + " |")
    for name, label in [("mean", "MeshLab mean"), ("gaussian", "MeshLab Gaussian")]:
        ours, lost[name] = on_reference(*p_values[name], v32)
        theirs, _ = on_reference(*m_values[name], v32)
        print("| " + " | ".join([name, label, *compare(ours, theirs, interior)]) + " |")
    if any(lost.values()):
        print(f"\nPappus vertices matching no input vertex: {lost}")


if __name__ == "__main__":
    main()
