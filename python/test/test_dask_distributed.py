"""smalliso.dask on a dask.distributed cluster of two worker processes: the in-memory result and
statistics, and a Zarr array filtered through a client."""

import dask.array as da
import numpy as np
import pytest
import zarr
from distributed import Client, LocalCluster, get_task_stream

import smalliso
import smalliso.dask
from volumes import random_volume, same_bits, without_memory


@pytest.fixture(scope="module")
def client():
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as connected:
            yield connected


def test_two_worker_processes_give_the_in_memory_result(client):
    assert len(client.scheduler_info()["workers"]) == 2
    with get_task_stream(client) as stream:
        for seed, (dtype, side) in enumerate((("float32", "both"), ("int16", "above"), ("uint8", "below"))):
            check_on_cluster(client, seed, dtype, side)
    # The chunks were filtered by both workers.
    assert len({record["worker"] for record in stream.data}) == 2


def check_on_cluster(client, seed, dtype, side):
    volume, isovalue = random_volume(np.random.default_rng(seed), dtype, (14, 15, 16))
    expected, expected_mask, expected_stats = smalliso.remove_small_components(
        volume, isovalue, 5, side, seed == 1, return_mask=True, return_stats=True)
    parts = smalliso.dask.remove_small_components(da.from_array(volume, chunks=(5, 6, 7)), isovalue, 5, side,
                                                  seed == 1, return_mask=True, return_stats=True)
    output, mask, stats = client.gather(client.compute(list(parts)))
    assert same_bits(output, expected) and same_bits(mask, expected_mask)
    assert stats == without_memory(expected_stats)


def test_the_workers_count_as_processes_that_only_run_tasks(client):
    # Where the tasks keep the memory they free for the next (the user's process is not one).
    assert set(client.run(smalliso.dask._graph._in_distributed_worker).values()) == {True}
    assert not smalliso.dask._graph._in_distributed_worker()


def test_a_zarr_array_through_the_client(client, tmp_path):
    volume, isovalue = random_volume(np.random.default_rng(9), "float64", (12, 13, 11))
    zarr.save_array(str(tmp_path / "in.zarr"), volume, chunks=(4, 5, 6))
    stats = smalliso.dask.remove_small_components_zarr(tmp_path / "in.zarr", tmp_path / "out.zarr", isovalue, 3,
                                                       client=client)
    expected, expected_stats = smalliso.remove_small_components(volume, isovalue, 3, return_stats=True)
    assert same_bits(zarr.open_array(str(tmp_path / "out.zarr"), mode="r")[...], expected)
    assert stats == without_memory(expected_stats)
