"""smalliso.dask.remove_small_label_components: the in-memory result, voxel for voxel, with its
voxel counts, for random label maps and chunkings, chunks smaller than K among them; errors."""

import dask
import dask.array as da
import numpy as np
import pytest
import zarr

import smalliso
import smalliso.dask
from test_dask import random_chunks
from label_reference import IDS, LABEL_DTYPES, random_labels


def voxel_counts(stats):
    """The in-memory statistics that add up over chunks, in the form the Dask function gives them."""
    labels = {label: {field: entry[field] for field in ("removed_voxels", "gained_voxels")}
              for label, entry in stats["labels"].items() if entry["removed_voxels"] or entry["gained_voxels"]}
    return {"labels": labels, **{field: stats[field]
                                 for field in ("modified_voxels", "unrepairable_voxels", "effective_max_size")}}


def check_case(labels, chunks, stored=False, **options):
    expected, expected_mask, expected_stats = smalliso.remove_small_label_components(
        labels, return_mask=True, return_stats=True, **options)
    chunks = da.core.normalize_chunks(chunks, labels.shape)
    source = zarr.array(labels, chunks=[c[0] for c in chunks]) if stored else da.from_array(labels, chunks=chunks)
    output, mask, stats = dask.compute(*smalliso.dask.remove_small_label_components(
        source, return_mask=True, return_stats=True, **options), scheduler="synchronous")
    case = f"{labels.dtype} shape {labels.shape} chunks {chunks} stored={stored} {options}"
    assert output.dtype == labels.dtype and np.array_equal(output, expected), case
    assert np.array_equal(mask, expected_mask), case
    assert stats == voxel_counts(expected_stats), case
    assert list(stats["labels"]) == sorted(stats["labels"]), case


def test_each_part_alone_is_the_same():
    labels = random_labels(np.random.default_rng(7), "int16", (9, 11, 8))
    source = da.from_array(labels, chunks=(4, 5, 3))
    expected, expected_mask, expected_stats = smalliso.remove_small_label_components(
        labels, max_size=3, return_mask=True, return_stats=True)
    output = smalliso.dask.remove_small_label_components(source, max_size=3)
    assert np.array_equal(output.compute(scheduler="synchronous"), expected)
    output, stats = dask.compute(*smalliso.dask.remove_small_label_components(source, max_size=3, return_stats=True),
                                 scheduler="synchronous")
    assert np.array_equal(output, expected) and stats == voxel_counts(expected_stats)
    assert stats["modified_voxels"] > 0 and all(isinstance(label, int) for label in stats["labels"])
    output, mask = dask.compute(*smalliso.dask.remove_small_label_components(source, max_size=3, return_mask=True),
                                scheduler="synchronous")
    assert np.array_equal(output, expected) and np.array_equal(mask, expected_mask)


@pytest.mark.parametrize("first", range(0, 120, 30))
def test_random_maps_and_chunkings_match_the_in_memory_result(first):
    for seed in range(first, first + 30):
        rng = np.random.default_rng(seed)
        ndim = (2, 3, 4)[seed % 3]
        shape = tuple(rng.integers(1, (40, 16, 7)[ndim - 2], size=ndim))
        dtype = LABEL_DTYPES[seed % len(LABEL_DTYPES)]
        ids = IDS[dtype]
        labels = random_labels(rng, dtype, shape)
        select = ("all", "islands", "holes", [int(ids[1]), int(ids[-1])])[seed % 4]
        options = dict(max_size=int(rng.choice([0, 1, 2, 3, 5])), fully_connected=bool(rng.integers(2)),
                       select=select)
        if seed % 5 == 0:
            options["max_sizes"] = {int(ids[-1]): int(rng.integers(0, 12))}
        check_case(labels, random_chunks(rng, shape), stored=seed % 7 == 6, **options)


def test_a_large_component_cut_by_the_box_is_kept():
    # A ring of label 1 (100 voxels) in a map wider than a box: each box sees only arcs of it, which
    # would be removed with K = 5 unless the faces of the box inside the map count them as large.
    labels = np.zeros((30, 30), np.uint8)
    labels[2, 2:28] = labels[27, 2:28] = labels[2:28, 2] = labels[2:28, 27] = 1
    labels[14, 14] = 1
    for chunks in ((2, 2), (1, 3), (4, 5)):
        for fully_connected in (False, True):
            check_case(labels, chunks, max_size=5, fully_connected=fully_connected)


def test_unrepairable_voxels_are_counted():
    # A cross of label 1 across the whole map: from its centre every walk leaves the map.
    labels = np.zeros((4, 5), np.uint8)
    labels[1, :] = labels[:, 2] = 1
    expected = smalliso.remove_small_label_components(labels, max_size=8, select="islands", return_stats=True)[1]
    assert expected["unrepairable_voxels"] == 1 and expected["modified_voxels"] == 7
    for chunks in ((1, 1), (2, 3), (4, 5)):
        check_case(labels, chunks, max_size=8, select="islands")


def test_keep_largest_and_bad_arguments_are_refused():
    labels = da.zeros((6, 6), np.uint8, chunks=3)
    with pytest.raises(ValueError, match="keep_largest is 1; it is not supported on Dask arrays"):
        smalliso.dask.remove_small_label_components(labels, keep_largest=1)
    with pytest.raises(TypeError, match="return_stats"):
        smalliso.dask.remove_small_label_components(labels, return_stats="yes")
    with pytest.raises(ValueError, match="select is 'specks'"):
        smalliso.dask.remove_small_label_components(labels, select="specks")
    with pytest.raises(TypeError, match="dtype float16 is not supported for label maps"):
        smalliso.dask.remove_small_label_components(labels.astype(np.float16))
