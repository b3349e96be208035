"""Tests of smalliso.remove_small_label_components: voxel for voxel against the brute-force reference
of the label-map rule (label_reference.py), with its mask and statistics."""

import numpy as np
import pytest

import smalliso
from label_reference import IDS, LABEL_DTYPES, SHAPES, random_labels, reference


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
