"""smalliso.dask.remove_small_components: the in-memory result, voxel for voxel, and its
statistics, on hundreds of random volumes and chunkings, on Dask's local schedulers; errors."""

import multiprocessing
import os
import resource
import subprocess
import sys

import dask
import dask.array as da
import numpy as np
import pytest
import zarr

import smalliso
import smalliso.dask
from volumes import DTYPES, random_volume, same_bits, unaligned_copy, without_memory


def random_chunks(rng, shape):
    """Random cuts along each axis: chunks of one voxel along an axis now and then."""
    chunks = []
    for extent in shape:
        if rng.random() < 0.2:
            chunks.append((1,) * extent)
            continue
        cuts = sorted(set(rng.integers(1, extent, size=rng.integers(0, 4)).tolist())) if extent > 1 else []
        edges = [0] + cuts + [extent]
        chunks.append(tuple(b - a for a, b in zip(edges, edges[1:])))
    return tuple(chunks)


def check_case(volume, isovalue, max_size, side, fully_connected, chunks, scheduler="synchronous", stored=False):
    """Compares with the in-memory result: a Dask array of ``chunks``, or with ``stored`` a Zarr
    array (in memory) of regular chunks of the first size along each axis, read box by box."""
    expected, expected_mask, expected_stats = smalliso.remove_small_components(
        volume, isovalue, max_size, side, fully_connected, return_mask=True, return_stats=True)
    chunks = da.core.normalize_chunks(chunks, volume.shape)
    source = zarr.array(volume, chunks=[c[0] for c in chunks]) if stored else da.from_array(volume, chunks=chunks)
    output, mask, stats = smalliso.dask.remove_small_components(
        source, isovalue, max_size, side, fully_connected, return_mask=True, return_stats=True)
    output, mask, stats = dask.compute(output, mask, stats, scheduler=scheduler)
    case = (f"{volume.dtype} shape {volume.shape} chunks {chunks} stored={stored} K={max_size} {side} "
            f"fully={fully_connected} isovalue={isovalue}")
    assert same_bits(output, expected), case
    assert same_bits(mask, expected_mask), case
    assert stats == without_memory(expected_stats), case


@pytest.mark.parametrize("first", range(0, 600, 50))
def test_random_volumes_and_chunkings_match_the_in_memory_result(first):
    for seed in range(first, first + 50):
        rng = np.random.default_rng(seed)
        ndim = 2 if seed % 3 == 0 else 3
        shape = tuple(rng.integers(1, 21 if ndim == 2 else 12, size=ndim))
        volume, isovalue = random_volume(rng, DTYPES[seed % len(DTYPES)], shape)
        max_size = int(rng.choice([0, 1, 2, 3, 5, volume.size + 3]))
        side = ("above", "below", "both")[seed % 3 if seed % 7 else 2]
        check_case(volume, isovalue, max_size, side, bool(rng.integers(2)), random_chunks(rng, shape),
                   stored=seed % 5 == 4)


def test_chunks_of_one_voxel():
    rng = np.random.default_rng(1000)
    for ndim, shape in ((2, (5, 6)), (3, (3, 4, 4))):
        for side in ("above", "below", "both"):
            volume, isovalue = random_volume(rng, "float32", shape)
            check_case(volume, isovalue, 2, side, ndim == 3, (1,) * ndim)


def test_a_speck_across_a_chunk_corner_and_a_diagonal_chain():
    volume = np.zeros((9, 9, 9), np.uint8)
    volume[2:4, 2:4, 2:4] = 200  # 8 voxels, one in each of the 8 chunks meeting at (3, 3, 3)
    for k in range(4):
        volume[5 + k % 2, 5 + k // 2 % 2, 4 + k] = 200  # corner-connected only: one component when fully connected
    for max_size in (3, 4, 7, 8):
        for fully_connected in (False, True):
            check_case(volume, 100, max_size, "above", fully_connected, (3, 3, 3))
            check_case(volume, 100, max_size, "both", fully_connected, (3, 2, 4))


def test_bubbles_in_specks_across_chunk_faces():
    # A hollow speck (a 3x3x3 shell of 26 voxels around a one-voxel bubble) cut by chunk faces: with
    # K >= 26 the speck goes and its bubble joins the outside; with K < 26 only the bubble goes.
    volume = np.zeros((8, 9, 10), np.int16)
    volume[2:5, 3:6, 3:6] = 500
    volume[3, 4, 4] = 0
    volume[5:8, 6:9, 6:9] = 500  # a second speck without a bubble, touching the border
    for max_size in (1, 25, 26, 27, 30):
        for chunks in ((3, 4, 4), (4, 5, 5), (1, 9, 10), (8, 1, 5)):
            check_case(volume, 250, max_size, "both", False, chunks)
            check_case(volume, 250, max_size, "below", True, chunks)


def test_chunks_whose_samples_are_not_aligned_for_their_dtype():
    """Chunks can arrive at any address (a view of raw bytes, a message from another worker):
    the tasks hand the core aligned copies and the result is the in-memory one."""
    rng = np.random.default_rng(1001)
    for dtype in ("float32", "int16", "float64"):
        volume, isovalue = random_volume(rng, dtype, (7, 9, 8))
        expected, expected_stats = smalliso.remove_small_components(volume, isovalue, 3, return_stats=True)
        source = da.from_array(unaligned_copy(volume), chunks=(3, 4, 5))
        output, stats = smalliso.dask.remove_small_components(source, isovalue, 3, return_stats=True)
        output, stats = dask.compute(output, stats, scheduler="synchronous")
        assert same_bits(output, expected), dtype
        assert stats == without_memory(expected_stats), dtype


def test_the_local_schedulers():
    rng = np.random.default_rng(2000)
    volume, isovalue = random_volume(rng, "float64", (10, 12, 14))
    for scheduler, stored in (("threads", True), ("threads", False), ("processes", False)):
        check_case(volume, isovalue, 4, "both", False, (4, 5, 6), scheduler, stored)


def test_threads_in_each_task_and_a_numpy_input():
    rng = np.random.default_rng(3000)
    volume, isovalue = random_volume(rng, "uint16", (12, 13, 14))
    expected = smalliso.remove_small_components(volume, isovalue, 6)
    result = smalliso.dask.remove_small_components(volume, isovalue, 6, threads=2).compute()
    assert same_bits(result, expected)
    chunked = smalliso.dask.remove_small_components(da.from_array(volume, chunks=5), isovalue, 6, threads=2)
    assert same_bits(chunked.compute(scheduler="threads"), expected)


def test_chunks_rechunks_a_dask_array_and_sets_the_tasks_of_a_stored_one():
    rng = np.random.default_rng(3500)
    volume, isovalue = random_volume(rng, "float32", (11, 12, 13))
    expected = smalliso.remove_small_components(volume, isovalue, 4)
    for source in (da.from_array(volume, chunks=3), zarr.array(volume, chunks=(2, 3, 4))):
        result = smalliso.dask.remove_small_components(source, isovalue, 4, chunks=(4, 6, 8))
        assert result.chunks == da.core.normalize_chunks((4, 6, 8), volume.shape)
        assert same_bits(result.compute(scheduler="synchronous"), expected)


def test_max_volume_gives_the_in_memory_k():
    rng = np.random.default_rng(4000)
    volume, isovalue = random_volume(rng, "int32", (9, 10, 11))
    spacing = (0.5, 2.0, 1.5)
    expected, expected_stats = smalliso.remove_small_components(volume, isovalue, max_volume=7.5, spacing=spacing,
                                                                return_stats=True)
    output, stats = smalliso.dask.remove_small_components(da.from_array(volume, chunks=4), isovalue, max_volume=7.5,
                                                          spacing=spacing, return_stats=True)
    output, stats = dask.compute(output, stats, scheduler="synchronous")
    assert stats["effective_max_size"] == expected_stats["effective_max_size"] == 5
    assert same_bits(output, expected) and stats == without_memory(expected_stats)
    # Without a spacing, one unit per axis, as in memory.
    output = smalliso.dask.remove_small_components(da.from_array(volume, chunks=4), isovalue, max_volume=7.5)
    assert same_bits(output.compute(scheduler="synchronous"),
                     smalliso.remove_small_components(volume, isovalue, max_volume=7.5))


def test_the_result_keeps_the_chunks_and_no_task_holds_more_than_two_summaries():
    volume = np.zeros((10, 11, 12), np.uint8)
    x = da.from_array(volume, chunks=(3, 4, 5))
    output, stats = smalliso.dask.remove_small_components(x, 1.0, 2, return_stats=True)
    assert output.chunks == x.chunks and output.dtype == x.dtype
    graph = dict(stats.__dask_graph__())
    merges = [task for key, task in graph.items() if isinstance(key, tuple) and key[0].startswith("smalliso-merge-")]
    summaries = [key for key in graph if isinstance(key, tuple) and key[0].startswith("smalliso-summary-")]
    # A tree of pairwise merges over n leaves has n - 1 merges of two summaries each.
    assert len(summaries) == 4 * 3 * 3 and len(merges) == len(summaries) - 1
    assert all(len(task) == 3 for task in merges)


def test_each_chunk_is_filtered_once_when_the_parts_are_computed_together(monkeypatch, tmp_path):
    calls = []

    def counted(plan, pieces, original=smalliso.dask._graph._filter_box):
        calls.append(plan.crop_begin)
        return original(plan, pieces)

    monkeypatch.setattr(smalliso.dask._graph, "_filter_box", counted)
    volume, isovalue = random_volume(np.random.default_rng(5000), "uint8", (9, 10, 11))
    x = da.from_array(volume, chunks=4)
    chunks = x.npartitions
    for asked in ((True, True), (False, True), (True, False)):
        parts = smalliso.dask.remove_small_components(x, isovalue, 3, return_mask=asked[0], return_stats=True)
        for together in (parts, parts[-1:]) if asked[1] else (parts,):
            calls.clear()
            dask.compute(*together, scheduler="synchronous")
            assert len(calls) == chunks, (asked, len(together))
    calls.clear()
    zarr.save_array(str(tmp_path / "in.zarr"), volume, chunks=4)
    with dask.config.set(scheduler="synchronous"):
        smalliso.dask.remove_small_components_zarr(tmp_path / "in.zarr", tmp_path / "out.zarr", isovalue, 3,
                                                   removed_mask=tmp_path / "mask.zarr")
    assert len(calls) == chunks


@pytest.mark.parametrize("arguments, error, message", [
    (dict(array=da.zeros((3, 3), dtype=np.int64, chunks=2)), TypeError, "dtype int64 is not supported"),
    (dict(isovalue=float("nan")), ValueError, "isovalue is NaN"),
    (dict(max_size=-3), ValueError, "max_size is -3"),
    (dict(side="inside"), ValueError, "side is 'inside'"),
    (dict(array=da.zeros((2, 2, 2, 2), dtype=np.uint8, chunks=1)), ValueError, "4-D"),
    (dict(array=da.zeros((4, 0), dtype=np.uint8, chunks=2)), ValueError, "empty"),
    (dict(spacing=(1.0,)), ValueError, "spacing"),
    (dict(threads=0), ValueError, "threads is 0"),
    (dict(spacing=(1e-300, 1e-300), max_volume=1.0), ValueError, "voxel volume 0.0 is not a normal"),
    (dict(chunks=0), ValueError, "chunks is 0.*expected positive chunk edges"),
    (dict(chunks=(2, 0)), ValueError, r"chunks is \(2, 0\).*expected positive chunk edges"),
    (dict(chunks=-1.5), ValueError, "chunks is -1.5"),
    (dict(fully_connected="no"), TypeError, "fully_connected must be True or False, not 'no'"),
    (dict(return_stats="false"), TypeError, "return_stats must be True or False, not 'false'"),
    (dict(chunks=(2, float("nan"))), ValueError, r"chunks is \(2, nan\).*expected positive chunk edges"),
    (dict(array=da.zeros((4, 5), dtype=np.uint8, chunks=2)[da.arange(4, chunks=2) > 0], chunks=2), ValueError,
     "unknown chunk sizes"),
    (dict(array=da.ma.masked_greater(da.arange(20, dtype=np.uint8, chunks=5).reshape(4, 5), 10)), TypeError,
     "array is a Dask array of masked arrays, whose mask the filter cannot honour"),
    (dict(array=np.ma.masked_array(np.zeros((4, 5), np.uint8), mask=True)), TypeError, "masked arrays"),
])
def test_bad_arguments_give_clear_errors(arguments, error, message):
    call = dict(array=da.zeros((4, 5), dtype=np.uint8, chunks=2), isovalue=1.0)
    call.update(arguments)
    with pytest.raises(error, match=message):
        smalliso.dask.remove_small_components(**call)
    with pytest.raises(error) as raised:
        smalliso.dask.remove_small_components(**call)
    assert "\n" not in str(raised.value)


@pytest.mark.parametrize("chunks", [0, (2, 0), ((2, 1), (5,))])
def test_bad_chunks_of_a_stored_array_give_clear_errors(tmp_path, chunks):
    stored = zarr.open_array(str(tmp_path / "in.zarr"), mode="w", shape=(4, 5), chunks=(2, 2), dtype=np.uint8)
    with pytest.raises(ValueError, match="chunks is .*expected"):
        smalliso.dask.remove_small_components(stored, 1.0, chunks=chunks)


def test_unknown_chunk_sizes_are_refused():
    x = da.from_array(np.arange(20, dtype=np.uint8).reshape(4, 5), chunks=2)
    unknown = x[x[:, 0] > 3]
    with pytest.raises(ValueError, match="unknown chunk sizes.*compute_chunk_sizes"):
        smalliso.dask.remove_small_components(unknown, 1.0)


def test_a_dask_array_of_masked_arrays_is_refused_as_a_masked_array_is():
    volume = np.arange(1000, dtype=np.uint16).reshape(10, 10, 10)
    with pytest.raises(TypeError, match="array is a masked array") as in_memory:
        smalliso.remove_small_components(np.ma.masked_greater(volume, 500), 300.0)
    masked = da.ma.masked_greater(da.from_array(volume, chunks=5), 500)
    for call in (lambda: smalliso.dask.remove_small_components(masked, 300.0),
                 lambda: smalliso.dask.remove_small_components(masked, 300.0, return_mask=True, chunks=10)):
        with pytest.raises(TypeError, match="masked arrays, whose mask the filter cannot honour") as raised:
            call()
        # The same advice as the in-memory function's, in Dask's terms.
        assert str(raised.value).endswith(str(in_memory.value).split("; ", 1)[1].replace(
            "array.filled(value)", "dask.array.ma.filled(array, value)"))


def faults_of_a_second_fresh_block_after_a_filtering():
    """Minor page faults of filling a 64 MiB block the second time, after a filtering ran here:
    about none where the first block's memory was kept, at least 32 (2 MiB pages) where it went
    back to the system."""
    smalliso.dask.remove_small_components(da.from_array(np.zeros((8, 8, 8), np.uint8), chunks=4), 0.5).compute(
        scheduler="synchronous")

    def fill():
        block = np.ones(64 << 20, np.uint8)
        del block
    fill()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    fill()
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before


def test_a_process_that_runs_tasks_reuses_the_memory_its_tasks_free():
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        assert pool.apply(faults_of_a_second_fresh_block_after_a_filtering) < 16
    # The user's own process (a fresh interpreter, nobody's worker) is left as it is.
    here = os.path.dirname(os.path.abspath(__file__))
    code = "import test_dask; print(test_dask.faults_of_a_second_fresh_block_after_a_filtering())"
    user = subprocess.run([sys.executable, "-c", code], cwd=here, capture_output=True, text=True, check=True)
    assert int(user.stdout) >= 32
