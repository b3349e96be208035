"""Tests of smalliso.remove_small_label_components: voxel for voxel against a brute-force reference
of the label-map rule written here (flood fill, walks, votes), with its mask and statistics."""

import itertools
from collections import deque

import numpy as np
import pytest

import smalliso

LABEL_DTYPES = ("uint8", "int8", "uint16", "int16", "uint32", "int32", "uint64", "int64", "float32", "float64")
# Ids of each dtype: its extremes, negative and sparse ones (a background 0 always among them).
IDS = {"uint8": [0, 3, 200, 255], "int8": [-128, -5, 0, 7, 127], "uint16": [0, 2, 12175, 65535],
       "int16": [-32768, -1, 0, 12175], "uint32": [0, 5, 2**32 - 1], "int32": [-2**31, 0, 41, 2**31 - 1],
       "uint64": [0, 9, 2**63 + 5, 2**64 - 1], "int64": [-2**63, 0, 12175, 2**62 + 3],
       "float32": [0.0, 2.0, -3.0, 1e6], "float64": [0.0, -7.0, 4.0, 2.0**52]}
SHAPES = {2: (9, 11), 3: (5, 6, 7), 4: (3, 4, 5, 4)}


def random_labels(rng, dtype, shape):
    """Blocks of 2 voxels per axis of random ids, with about a fifth of the voxels changed to
    random ids: components of every size, islands and holes."""
    ids = np.array(IDS[dtype], dtype=dtype)
    coarse = ids[rng.integers(len(ids), size=[(n + 1) // 2 for n in shape])]
    labels = coarse
    for axis in range(len(shape)):
        labels = np.repeat(labels, 2, axis=axis)
    labels = np.ascontiguousarray(labels[tuple(slice(0, n) for n in shape)])
    noise = rng.random(shape) < 0.2
    labels[noise] = ids[rng.integers(len(ids), size=int(noise.sum()))]
    return labels


def reference(labels, max_size, fully_connected=False, select="all", background=0, max_sizes=None,
              keep_largest=0):
    """(filtered, mask, stats) by the rule of docs/labels.md, voxel by voxel."""
    shape, values = labels.shape, labels.tolist() if labels.ndim == 0 else labels.ravel().tolist()
    values = [int(v) for v in values]
    coordinates = list(np.ndindex(shape))
    flat = {c: i for i, c in enumerate(coordinates)}
    steps = [d for d in itertools.product((-1, 0, 1), repeat=len(shape)) if any(d)
             and (fully_connected or sum(map(abs, d)) == 1)]
    component = [-1] * len(values)
    sizes, component_labels = [], []
    for start in range(len(values)):
        if component[start] >= 0:
            continue
        component[start] = len(sizes)
        queue, size = deque([start]), 0
        while queue:
            at = queue.popleft()
            size += 1
            for d in steps:
                neighbour = tuple(c + s for c, s in zip(coordinates[at], d))
                n = flat.get(neighbour)
                if n is not None and component[n] < 0 and values[n] == values[start]:
                    component[n] = len(sizes)
                    queue.append(n)
        sizes.append(size)
        component_labels.append(values[start])
    removed = _removed_components(sizes, component_labels, max_size, select, background, max_sizes or {},
                                  keep_largest)
    output, mask = list(values), [0] * len(values)
    stats = {"labels": {}, "modified_voxels": 0, "unrepairable_voxels": 0}
    for label in set(component_labels):
        own = [s for s, l in zip(sizes, component_labels) if l == label]
        gone = [s for s, l, r in zip(sizes, component_labels, removed) if l == label and r]
        stats["labels"][label] = {"components": len(own), "removed_components": len(gone),
                                  "removed_voxels": sum(gone), "gained_voxels": 0,
                                  "size_histogram": {s: own.count(s) for s in set(own)}}
    for v, c in enumerate(component):
        if not removed[c]:
            continue
        mask[v] = 1
        votes = _votes(v, c, coordinates, flat, component, values, removed)
        if not votes:
            stats["unrepairable_voxels"] += 1
            continue
        output[v] = _elect(votes)
        stats["labels"][output[v]]["gained_voxels"] += 1
        stats["modified_voxels"] += 1
    as_array = np.array(output, dtype=object).astype(labels.dtype).reshape(shape)
    return as_array, np.array(mask, np.uint8).reshape(shape), stats


def _removed_components(sizes, component_labels, max_size, select, background, max_sizes, keep_largest):
    def selected(label):
        if select == "all":
            return True
        if select == "islands":
            return label != background
        if select == "holes":
            return label == background
        return label in [int(s) for s in select]

    smallest_kept = {}
    if keep_largest > 0:
        for label in set(component_labels):
            own = sorted((s for s, l in zip(sizes, component_labels) if l == label), reverse=True)
            if len(own) >= keep_largest:
                smallest_kept[label] = own[keep_largest - 1]
    return [selected(label) and (size <= max_sizes.get(label, max_size) or size < smallest_kept.get(label, 0))
            for size, label in zip(sizes, component_labels)]


def _votes(v, c, coordinates, flat, component, values, removed):
    """(label, steps, kept) of the first voxel outside component c on each axis walk from v."""
    votes = []
    for axis, direction in itertools.product(range(len(coordinates[v])), (-1, 1)):
        at, steps = list(coordinates[v]), 0
        while True:
            at[axis] += direction
            steps += 1
            w = flat.get(tuple(at))
            if w is None:
                break
            if component[w] != c:
                votes.append((values[w], steps, not removed[component[w]]))
                break
    return votes


def _elect(votes):
    if any(kept for _, _, kept in votes):
        votes = [vote for vote in votes if vote[2]]
    labels = {label for label, _, _ in votes}
    return min(labels, key=lambda label: (-sum(1 for l, _, _ in votes if l == label),
                                          min(s for l, s, _ in votes if l == label), label))


def check_case(labels, **options):
    expected, expected_mask, expected_stats = reference(labels, **options)
    filtered, mask, stats = smalliso.remove_small_label_components(labels, return_mask=True, return_stats=True,
                                                                   **options)
    assert filtered.dtype == labels.dtype and np.array_equal(filtered, expected)
    assert np.array_equal(mask, expected_mask)
    assert stats.pop("effective_max_size") == options["max_size"]
    assert stats == expected_stats


@pytest.mark.parametrize("dtype", LABEL_DTYPES)
@pytest.mark.parametrize("ndim", (2, 3, 4))
def test_matches_the_reference(dtype, ndim):
    rng = np.random.default_rng([ndim, LABEL_DTYPES.index(dtype)])
    ids = IDS[dtype]
    for case in range(4):
        labels = random_labels(rng, dtype, SHAPES[ndim])
        select = ["all", "islands", "holes", [int(ids[-1]), int(ids[1])]][case]
        options = dict(max_size=int(rng.integers(0, 9)), fully_connected=bool(case % 2), select=select)
        if case >= 2:
            options["max_sizes"] = {int(ids[-1]): int(rng.integers(0, 30)), int(ids[0]): 1}
        if case == 1:
            options["background"] = int(ids[-1])
        check_case(labels, **options)


@pytest.mark.parametrize("fully_connected", (False, True))
@pytest.mark.parametrize("keep_largest", (1, 2))
def test_keep_largest_matches_the_reference(fully_connected, keep_largest):
    rng = np.random.default_rng(keep_largest)
    for dtype, ndim in (("int16", 2), ("uint8", 3), ("float32", 4)):
        labels = random_labels(rng, dtype, SHAPES[ndim])
        check_case(labels, max_size=int(rng.integers(0, 4)), fully_connected=fully_connected,
                   keep_largest=keep_largest, select="islands")


def test_unrepairable_voxels_keep_their_label():
    labels = np.array([[5, 5, 5]], np.uint8).reshape(1, 3)
    check_case(labels, max_size=3)
    filtered, stats = smalliso.remove_small_label_components(labels, 3, return_stats=True)
    assert np.array_equal(filtered, labels) and stats["unrepairable_voxels"] == 3


def test_max_volume_and_spacing_give_k():
    labels = random_labels(np.random.default_rng(3), "int32", SHAPES[3])
    # Voxel volume 1.5: K = floor(10 / 1.5) = 6.
    by_volume, stats = smalliso.remove_small_label_components(labels, max_volume=10.0, spacing=(0.5, 2.0, 1.5),
                                                              return_stats=True)
    assert stats["effective_max_size"] == 6
    assert np.array_equal(by_volume, smalliso.remove_small_label_components(labels, 6))


@pytest.mark.parametrize("dtype", ("uint16", "float64", "int64"))
def test_in_place_out_and_fortran_order_give_the_same_result(dtype):
    labels = random_labels(np.random.default_rng(4), dtype, (12, 13, 14))
    expected = smalliso.remove_small_label_components(labels, 5)
    into = np.empty_like(labels)
    assert smalliso.remove_small_label_components(labels, 5, out=into) is into and np.array_equal(into, expected)
    own = labels.copy()
    assert smalliso.remove_small_label_components(own, 5, in_place=True) is own and np.array_equal(own, expected)
    fortran = np.asfortranarray(labels)
    result = smalliso.remove_small_label_components(fortran, 5)
    assert result.flags.f_contiguous and np.array_equal(result, expected)
    strided = np.zeros((12, 13, 28), dtype)
    strided[:, :, ::2] = labels
    assert np.array_equal(smalliso.remove_small_label_components(strided[:, :, ::2], 5), expected)


def test_output_does_not_depend_on_the_threads():
    labels = random_labels(np.random.default_rng(5), "uint32", (30, 31, 32))
    one = smalliso.remove_small_label_components(labels, 8, return_mask=True, return_stats=True, threads=1)
    three = smalliso.remove_small_label_components(labels, 8, return_mask=True, return_stats=True, threads=3)
    assert np.array_equal(one[0], three[0]) and np.array_equal(one[1], three[1]) and one[2] == three[2]


@pytest.mark.parametrize("bad", (0.5, np.inf, np.nan))
def test_a_float_map_of_other_than_whole_numbers_is_refused(bad):
    labels = np.zeros((4, 5, 6), np.float32)
    labels[2, 3, 1] = bad
    with pytest.raises(ValueError, match=r"sample at index \(2, 3, 1\) is .*whole numbers only"):
        smalliso.remove_small_label_components(labels)
    with pytest.raises(ValueError, match=r"sample at index \(2, 3, 1\)"):
        smalliso.remove_small_label_components(np.asfortranarray(labels))


@pytest.mark.parametrize("arguments, error, message", [
    (dict(labels=np.zeros((3, 3), np.float16)), TypeError, "dtype float16 is not supported for label maps"),
    (dict(labels=np.zeros((3, 3), bool)), TypeError, "dtype bool is not supported"),
    (dict(labels=np.zeros((3, 3), ">i2")), TypeError, "byte order.*newbyteorder"),
    (dict(labels=np.zeros(5, np.uint8)), ValueError, "1-D.*expected a 2-D, 3-D or 4-D array"),
    (dict(labels=np.zeros((1,) * 5, np.uint8)), ValueError, "5-D.*expected a 2-D, 3-D or 4-D array"),
    (dict(labels=np.zeros((0, 4), np.uint8)), ValueError, "empty"),
    (dict(max_size=-1), ValueError, "max_size is -1; it must be >= 0"),
    (dict(select="specks"), ValueError, "select is 'specks'; expected 'all', 'islands', 'holes' or a list"),
    (dict(select=3), TypeError, "select must be 'all', 'islands', 'holes' or a list of labels, not 3"),
    (dict(select=[]), ValueError, "select is an empty list"),
    (dict(select=[1, 300]), ValueError, "a label of select is 300, which a label map of dtype uint8 cannot hold"),
    (dict(select=[1.5]), ValueError, "a label of select is 1.5; a label is a whole number"),
    (dict(select=["a"]), TypeError, "a label of select must be a label"),
    (dict(background=-1), ValueError, "background is -1, which a label map of dtype uint8 cannot hold"),
    (dict(background=None), TypeError, "background must be a label"),
    (dict(max_sizes=[(1, 2)]), TypeError, "max_sizes must be a dict label -> K"),
    (dict(max_sizes={1: -2}), ValueError, r"max_sizes\[1\]: max_size is -2"),
    (dict(max_sizes={256: 2}), ValueError, "a label of max_sizes is 256"),
    (dict(keep_largest=-1), ValueError, "keep_largest is -1; it must be >= 0"),
    (dict(keep_largest=1.5), TypeError, "keep_largest must be a whole number"),
    (dict(spacing=(1.0,)), ValueError, "spacing.*expected 2 positive"),
    (dict(max_volume=-2.0), ValueError, "max_volume is -2.0"),
    (dict(threads=0), ValueError, "threads is 0"),
    (dict(in_place=True, out=np.zeros((4, 5), np.uint8)), ValueError, "give out or in_place"),
    (dict(out=np.zeros((4, 5), np.int8)), ValueError, "dtype int8"),
    (dict(fully_connected="no"), TypeError, "fully_connected must be True or False"),
    (dict(labels=np.ma.masked_array(np.zeros((4, 5), np.uint8), mask=True)), TypeError, "masked array"),
])
def test_bad_arguments_give_clear_errors(arguments, error, message):
    call = dict(labels=np.zeros((4, 5), np.uint8))
    call.update(arguments)
    with pytest.raises(error, match=message):
        smalliso.remove_small_label_components(**call)


def test_float_labels_must_be_held_exactly():
    labels = np.zeros((4, 5), np.float32)
    with pytest.raises(ValueError, match="16777217, which a label map of dtype float32 cannot hold"):
        smalliso.remove_small_label_components(labels, select=[2**24 + 1])
    assert np.array_equal(smalliso.remove_small_label_components(labels, select=[2**24, 1e6]), labels)
