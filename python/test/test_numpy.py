"""smalliso.remove_small_components: the command-line tool's results voxel for voxel on random
arrays of every dtype, side and connectivity; in place, out=, Fortran order, the GIL, and errors."""

import json
import os
import subprocess
import threading
import time

import numpy as np
import pytest

import smalliso
from metaimage import read as read_mha, write as write_mha
from volumes import DTYPES, random_volume, same_bits, unaligned_copy, without_memory

TOOL = os.environ.get("SMALLISO_FILTER_TOOL")
needs_tool = pytest.mark.skipif(not TOOL, reason="SmallIsoComponentFilter was not built (SMALLISO_FILTER_TOOL unset)")


def run_tool(tmp_path, volume, isovalue, options, spacing=None):
    """The tool's output, mask and --stats statistics for ``volume``."""
    source, output, mask, stats = (tmp_path / name for name in ("in.mha", "out.mha", "mask.mha", "stats.json"))
    write_mha(source, volume, spacing)
    subprocess.run([TOOL, str(source), str(output), "--isovalue", repr(isovalue), "--removed-mask", str(mask),
                    "--stats", str(stats), "--quiet"] + options, check=True)
    with open(stats) as stream:
        document = json.load(stream)
    return read_mha(output), read_mha(mask), document


def as_tool_statistics(stats):
    """Our statistics in the tool's JSON form (histograms as [size, count] pairs)."""
    def side(counts):
        return dict(counts, size_histogram=[[s, c] for s, c in sorted(counts["size_histogram"].items())])

    return {"above": side(stats["above"]), "below": side(stats["below"]),
            "modified_voxels": stats["modified_voxels"], "unrepairable_voxels": stats["unrepairable_voxels"]}


@needs_tool
@pytest.mark.parametrize("dtype", DTYPES)
def test_matches_the_command_line_tool(tmp_path, dtype):
    rng = np.random.default_rng(list(DTYPES).index(dtype))
    for side in ("above", "below", "both"):
        for fully_connected in (False, True):
            for ndim in (2, 3) if side == "both" else (int(rng.integers(2, 4)),):
                shape = tuple(rng.integers(1, 14, size=ndim))
                volume, isovalue = random_volume(rng, dtype, shape)
                max_size = int(rng.choice([0, 1, 3, 8, 20, volume.size + 1]))
                options = ["--max-size", str(max_size), "--side", side] + (["--fully-connected"] if fully_connected else [])
                expected, expected_mask, document = run_tool(tmp_path, volume, isovalue, options)
                output, mask, stats = smalliso.remove_small_components(
                    volume, isovalue, max_size, side, fully_connected, return_mask=True, return_stats=True)
                case = f"{dtype} shape {shape} K={max_size} {side} fully={fully_connected} isovalue={isovalue}"
                assert same_bits(output, expected), case
                assert same_bits(mask, expected_mask), case
                tool = {key: document["statistics"][key] for key in ("above", "below", "modified_voxels",
                                                                      "unrepairable_voxels")}
                assert as_tool_statistics(stats) == tool, case
                assert stats["effective_max_size"] == document["parameters"]["effective_max_size"] == max_size


@needs_tool
def test_max_volume_and_spacing_match_the_tool(tmp_path):
    rng = np.random.default_rng(7)
    volume, isovalue = random_volume(rng, "int16", (9, 11, 13))
    spacing = (2.0, 0.5, 0.75)
    expected, _, document = run_tool(tmp_path, volume, isovalue, ["--max-volume", "3"], spacing)
    output, stats = smalliso.remove_small_components(volume, isovalue, max_volume=3, spacing=spacing,
                                                     return_stats=True)
    assert stats["effective_max_size"] == document["parameters"]["effective_max_size"] == 4
    assert same_bits(output, expected)


def test_returns_what_was_asked_for_in_order():
    volume = np.zeros((5, 6), np.uint8)
    volume[2, 3] = 9
    output = smalliso.remove_small_components(volume, 5)
    assert isinstance(output, np.ndarray) and output[2, 3] < 5 and volume[2, 3] == 9
    output, mask = smalliso.remove_small_components(volume, 5, return_mask=True)
    assert mask.dtype == np.uint8 and mask[2, 3] == 1 and mask.sum() == 1
    output, stats = smalliso.remove_small_components(volume, 5, return_stats=True)
    assert stats["above"]["removed_components"] == 1 and stats["above"]["size_histogram"] == {1: 1}
    output, mask, stats = smalliso.remove_small_components(volume, 5, return_mask=True, return_stats=True)
    assert stats["modified_voxels"] == 1 and stats["peak_extra_bytes"] > 0


@pytest.mark.parametrize("dtype", DTYPES)
def test_in_place_and_out_give_the_same_result(dtype):
    rng = np.random.default_rng(100 + list(DTYPES).index(dtype))
    volume, isovalue = random_volume(rng, dtype, (7, 8, 9))
    expected, expected_mask = smalliso.remove_small_components(volume, isovalue, 5, return_mask=True)
    in_place = volume.copy()
    returned, mask = smalliso.remove_small_components(in_place, isovalue, 5, in_place=True, return_mask=True)
    assert returned is in_place and same_bits(in_place, expected) and same_bits(mask, expected_mask)
    out = np.empty_like(volume)
    returned = smalliso.remove_small_components(volume, isovalue, 5, out=out)
    assert returned is out and same_bits(out, expected)
    same = volume.copy()
    assert smalliso.remove_small_components(same, isovalue, 5, out=same) is same and same_bits(same, expected)


def test_a_fortran_ordered_array_is_filtered_in_its_own_memory():
    rng = np.random.default_rng(3)
    for dtype in DTYPES:
        volume, isovalue = random_volume(rng, dtype, (6, 7, 8))
        fortran = np.asfortranarray(volume)
        output, mask = smalliso.remove_small_components(fortran, isovalue, 6, return_mask=True)
        assert output.flags.f_contiguous and mask.flags.f_contiguous
        # The same buffer seen as a C-ordered array (the transpose) is the same ITK image.
        expected, expected_mask = smalliso.remove_small_components(fortran.T, isovalue, 6, return_mask=True)
        assert same_bits(output, expected.T) and same_bits(mask, expected_mask.T)
        if np.dtype(dtype).kind in "iu":
            # Integer results do not depend on the order in which a mean's values are summed.
            assert same_bits(output, smalliso.remove_small_components(volume, isovalue, 6))
        smalliso.remove_small_components(fortran, isovalue, 6, in_place=True)
        assert same_bits(fortran, output)


def test_a_strided_view_is_copied_and_refused_in_place():
    rng = np.random.default_rng(4)
    volume, isovalue = random_volume(rng, "float32", (8, 10, 12))
    view = volume[:, ::2, 1:]
    assert same_bits(smalliso.remove_small_components(view, isovalue, 4),
                     smalliso.remove_small_components(view.copy(), isovalue, 4))
    with pytest.raises(ValueError, match="neither C- nor Fortran-contiguous.*ascontiguousarray"):
        smalliso.remove_small_components(view, isovalue, 4, in_place=True)


@pytest.mark.parametrize("dtype", [dtype for dtype in DTYPES if np.dtype(dtype).alignment > 1])
def test_samples_not_aligned_for_their_dtype_are_copied_and_refused_in_place(dtype):
    rng = np.random.default_rng(5)
    volume, isovalue = random_volume(rng, dtype, (9, 8, 7))
    unaligned = unaligned_copy(volume)
    output, stats = smalliso.remove_small_components(unaligned, isovalue, 4, return_stats=True)
    assert output.flags.aligned
    assert same_bits(output, smalliso.remove_small_components(volume, isovalue, 4))
    assert stats["modified_voxels"] > 0
    assert same_bits(unaligned, volume)
    with pytest.raises(ValueError, match="not aligned for its dtype.*numpy.require"):
        smalliso.remove_small_components(unaligned, isovalue, 4, in_place=True)
    with pytest.raises(ValueError, match="not aligned for its dtype.*numpy.require"):
        smalliso.remove_small_components(volume, isovalue, 4, out=unaligned_copy(volume))
    # The compiled core refuses such an array itself rather than reading it sample by sample.
    with pytest.raises(ValueError, match="not aligned for its dtype"):
        smalliso._core.filter(unaligned, isovalue, 4, None, "both", False, [1.0, 1.0, 1.0], False, False, 0)


def test_the_gil_is_released_while_the_filter_runs():
    # Dense noise, large enough that the call takes well over the 0.05 s asked below.
    volume = np.random.default_rng(5).random((224, 224, 224), dtype=np.float32)
    ticks = []
    running = threading.Event()

    def tick():
        running.set()
        while running.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    ticker = threading.Thread(target=tick)
    ticker.start()
    running.wait()
    try:
        begin = time.perf_counter()
        smalliso.remove_small_components(volume, 0.5, 3, threads=1)
        end = time.perf_counter()
    finally:
        running.clear()
        ticker.join()
    during = sum(begin < t < end for t in ticks)
    # Holding the GIL, the ticker could not run at all during the call.
    assert end - begin > 0.05 and during >= 10, (end - begin, during)


def test_output_does_not_depend_on_the_threads():
    rng = np.random.default_rng(6)
    volume, isovalue = random_volume(rng, "float64", (30, 31, 32))
    one = smalliso.remove_small_components(volume, isovalue, 8, return_stats=True, threads=1)
    three = smalliso.remove_small_components(volume, isovalue, 8, return_stats=True, threads=3)
    assert same_bits(one[0], three[0]) and without_memory(one[1]) == without_memory(three[1])


@pytest.mark.parametrize("arguments, error, message", [
    (dict(array=np.zeros((3, 3), np.int64)), TypeError, "dtype int64 is not supported.*double precision"),
    (dict(array=np.zeros((3, 3), bool)), TypeError, "dtype bool is not supported"),
    (dict(array=np.zeros((3, 3), ">i2")), TypeError, "byte order.*newbyteorder"),
    (dict(isovalue=float("nan")), ValueError, "isovalue is NaN"),
    (dict(isovalue="high"), TypeError, "isovalue must be a real number"),
    (dict(max_size=-1), ValueError, "max_size is -1; it must be >= 0"),
    (dict(max_size=2.5), TypeError, "max_size must be a whole number"),
    (dict(side="up"), ValueError, "side is 'up'; expected 'above', 'below' or 'both'"),
    (dict(side=1), TypeError, "side must be one of the strings"),
    (dict(array=np.zeros(5, np.uint8)), ValueError, "1-D.*expected a 2-D or 3-D array"),
    (dict(array=np.zeros((2, 2, 2, 2), np.uint8)), ValueError, "4-D.*expected a 2-D or 3-D array"),
    (dict(array=np.zeros((0, 4), np.uint8)), ValueError, "empty"),
    (dict(spacing=(1.0, 0.0)), ValueError, "spacing.*expected 2 positive finite numbers"),
    (dict(spacing=(1.0, 1.0, 1.0)), ValueError, "spacing.*expected 2 positive"),
    (dict(spacing="ab"), ValueError, "spacing must be a sequence"),
    (dict(spacing=(1e-300, 1e-300), max_volume=1.0), ValueError, "voxel volume 0.0 is not a normal"),
    (dict(spacing=(1e200, 1e200)), ValueError, "voxel volume inf is not a normal"),
    (dict(max_volume=-2.0), ValueError, "max_volume is -2.0; it must be a volume >= 0"),
    (dict(threads=0), ValueError, "threads is 0"),
    (dict(in_place=True, out=np.zeros((4, 5), np.uint8)), ValueError, "give out or in_place"),
    (dict(out=np.zeros((5, 4), np.uint8)), ValueError, "out has shape"),
    (dict(out=np.zeros((4, 5), np.int8)), ValueError, "dtype int8"),
    (dict(out=[[0] * 5] * 4), TypeError, "out must be a NumPy array"),
    (dict(array=[[0] * 5] * 4, in_place=True), TypeError, "array must be a NumPy array"),
    # A string flag would be true whatever it says.
    (dict(fully_connected="no"), TypeError, "fully_connected must be True or False, not 'no'"),
    (dict(return_mask="false"), TypeError, "return_mask must be True or False, not 'false'"),
    (dict(return_stats=None), TypeError, "return_stats must be True or False, not None"),
    (dict(in_place="no"), TypeError, "in_place must be True or False, not 'no'"),
    (dict(array=np.ma.masked_array(np.zeros((4, 5), np.uint8), mask=True)), TypeError, "masked array"),
])
def test_bad_arguments_give_clear_errors(arguments, error, message):
    call = dict(array=np.zeros((4, 5), np.uint8), isovalue=1.0)
    call.update(arguments)
    array = call["array"].copy() if isinstance(call["array"], np.ndarray) else None
    with pytest.raises(error, match=message):
        smalliso.remove_small_components(**call)
    if array is not None:
        assert np.array_equal(call["array"], array)


def test_flags_take_one_and_zero_as_true_and_false():
    volume, isovalue = random_volume(np.random.default_rng(9), "int16", (6, 7, 8))
    ones = smalliso.remove_small_components(volume, isovalue, 3, fully_connected=1, return_mask=np.int64(1))
    trues = smalliso.remove_small_components(volume, isovalue, 3, fully_connected=True, return_mask=True)
    assert all(same_bits(a, b) for a, b in zip(ones, trues))
    assert same_bits(smalliso.remove_small_components(volume, isovalue, 3, fully_connected=0),
                     smalliso.remove_small_components(volume, isovalue, 3, fully_connected=False))
    with pytest.raises(TypeError, match="fully_connected must be True or False, not 2"):
        smalliso.remove_small_components(volume, isovalue, 3, fully_connected=2)


def test_read_only_and_overlapping_targets_are_refused():
    volume = np.zeros((4, 5), np.uint8)
    volume.flags.writeable = False
    with pytest.raises(ValueError, match="read-only"):
        smalliso.remove_small_components(volume, 1.0, in_place=True)
    writable = np.zeros((4, 5), np.uint8)
    with pytest.raises(ValueError, match="out overlaps the input"):
        smalliso.remove_small_components(writable, 1.0, out=writable[:])
