"""A folder of meshes mapped over a cluster: `pappus.process_file` on a `dask.distributed`
`LocalCluster` of two worker processes gives exactly what a sequential loop gives, file for file
and byte for byte — the README's recipe, run."""

import os
from pathlib import Path

import pytest

import pappus

MODELS = Path(__file__).resolve().parents[2] / ".." / "shared" / "models"
STEPS = ["triangulate", "simplify:0.5", "smooth:taubin:2"]


def required(thing, why):
    """Skips for a missing `thing` outside CI; under CI=true a test may not skip, so it fails."""
    if os.environ.get("CI") in ("true", "1"):
        pytest.fail(f"{thing} is absent, and under CI=true a test may not skip")
    pytest.skip(f"{thing} is absent: {why}")


def test_process_file_is_the_command_lines_process_for_one_input(tmp_path):
    report = pappus.process_file("shape:icosphere:2", ["loop", "flip:0,1"], tmp_path / "{stem}.off")
    assert report["source"] == "shape:icosphere:2"
    assert report["output"] == str(tmp_path / "icosphere-2.off")
    loop, flip = report["steps"]
    assert (loop["step"], loop["outcome"]) == ("loop", "applied")
    assert loop["summary"] and loop["ms"] >= 0
    # Vertices 0 and 1 of an icosphere are not joined by an edge: refused, and the run goes on.
    assert flip["outcome"] == "refused" and flip["reason"]
    assert report["faces"] == 4 * 320 and report["info"] is None
    assert report["dropped"] == []
    saved = pappus.load(report["output"])
    assert saved.info()["faces"] == 4 * 320
    # What the output format cannot hold is reported, as `Mesh.save` warns.
    report = pappus.process_file("shape:cube", ["param:mean-value"], tmp_path / "out" / "c.off")
    assert Path(report["output"]).exists() and report["dropped"]
    assert pappus.output_stem(tmp_path / "scan.tar.ply") == "scan.tar"
    assert pappus.process_file("shape:torus", [])["output"] is None
    with pytest.raises(FileNotFoundError):
        pappus.process_file(tmp_path / "missing.obj", STEPS, tmp_path / "{stem}.ply")


def test_a_local_dask_cluster_matches_a_sequential_run(tmp_path):
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        required("dask.distributed", "pip install 'dask[distributed]'")
    if not MODELS.is_dir():
        required("../shared/models", "the shared models sit beside the repository")
    paths = sorted(str(p) for p in MODELS.glob("*.obj"))
    assert len(paths) >= 4

    sequential = [
        pappus.process_file(p, STEPS, tmp_path / "one" / "{stem}.ply", info=True) for p in paths
    ]
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, Client(cluster) as client:
        futures = client.map(
            pappus.process_file,
            paths,
            steps=STEPS,
            output=str(tmp_path / "two" / "{stem}.ply"),
            info=True,
        )
        distributed = client.gather(futures)
        workers = {who for who_has in client.who_has(futures).values() for who in who_has}

    assert len(workers) == 2, workers  # both processes took work
    assert [r["source"] for r in distributed] == paths
    for one, two in zip(sequential, distributed):
        assert one["info"]["valid"] and (one["vertices"], one["faces"]) == (
            two["vertices"],
            two["faces"],
        )
        assert one["info"] == {**two["info"], **{k: one["info"][k] for k in timing_keys(one)}}
        assert [s["outcome"] for s in one["steps"]] == [s["outcome"] for s in two["steps"]]
        assert [s.get("summary") for s in one["steps"]] == [s.get("summary") for s in two["steps"]]
        assert Path(one["output"]).read_bytes() == Path(two["output"]).read_bytes(), one["source"]


def timing_keys(report):
    """The keys of `info` that are timings (`read_ms`, …), which differ between two runs."""
    return [k for k in report["info"] if k.endswith("_ms")]
