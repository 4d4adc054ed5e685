# Bakes spread over a dask.distributed cluster of two worker processes give the files that one
# process per map of the command-line tool gives, byte for byte.
import shutil
import pytest

import ndfmip
from conftest import BUNDLED_MAP, SHARED_MAPS, assert_same_folders, run_cli

distributed = pytest.importorskip("distributed")


def test_local_cluster_bakes_equal_cli_bakes(cli, tmp_path):
    maps = tmp_path / "maps"
    maps.mkdir()
    jobs = []
    for i in range(6):  # copies under distinct names, baked with two methods
        copy = maps / f"wall_{i}.png"
        shutil.copyfile(BUNDLED_MAP, copy)
        jobs.append((copy, "toksvig" if i % 2 else "vmf"))
    shared = sorted(SHARED_MAPS.glob("*.png"), key=lambda p: p.stat().st_size)[:2] if SHARED_MAPS.is_dir() else []
    for path in shared:
        jobs.append((path, "toksvig"))
    while len(jobs) < 8:
        copy = maps / f"extra_{len(jobs)}.png"
        shutil.copyfile(BUNDLED_MAP, copy)
        jobs.append((copy, "naive"))

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=40) as cluster, distributed.Client(cluster) as client:
        # ndfmip.bake_to travels by reference: each worker process imports ndfmip itself.
        futures = [client.submit(ndfmip.bake_to, str(src), str(tmp_path / "dask" / f"{src.stem}.bake"), method,
                                 pure=False) for src, method in jobs]
        assert [r["status"] for r in client.gather(futures)] == ["baked"] * len(jobs)

    for src, method in jobs:
        run_cli(cli, "bake", str(src), "--method", method, "-o", tmp_path / "cli" / f"{src.stem}.bake", "-q")
        assert_same_folders(tmp_path / "cli" / f"{src.stem}.bake", tmp_path / "dask" / f"{src.stem}.bake")
