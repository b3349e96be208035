# ==========================================================================
#
#   Copyright SmallIsoComponent contributors
#
#   Licensed under the Apache License, Version 2.0 (the "License");
#   you may not use this file except in compliance with the License.
#   You may obtain a copy of the License at
#
#          http://www.apache.org/licenses/LICENSE-2.0.txt
#
#   Unless required by applicable law or agreed to in writing, software
#   distributed under the License is distributed on an "AS IS" BASIS,
#   WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
#   See the License for the specific language governing permissions and
#   limitations under the License.
#
# ==========================================================================
"""The filter's rules in plain NumPy, written to be obviously right rather than fast, for
the Python tests to compare the wrapped filter with (the C++ tests have their own
reference, test/itkSmallIsoComponentReference.h).

Arrays are in NumPy's order, so ITK's axis 0 (x) is the last NumPy axis. A voxel is above
when its value, as a double, is >= the isovalue (NaN is below). Components are found by a
flood fill over single voxels; a component of at most K voxels is removed by giving each
voxel the mean of the first other-side values met walking along each axis (-x, +x, -y, ...),
read before the pass, NaN never counted, rounded half up for integers. Side "both" runs the
below pass on the result of the above pass.

Only volumes where every removed voxel finds a value are covered: a voxel that finds none
raises ValueError (the filter's fallback for it is tested in C++).

Needs NumPy only: `python3 small_iso_component_reference.py` checks it on hand-made cases."""

import collections
import itertools
import math
import sys

import numpy as np


def is_above(values, iso_value):
    """The side of each value: True for above (value >= iso_value, compared as double)."""
    with np.errstate(invalid="ignore"):
        return np.asarray(values, dtype=np.float64) >= iso_value


def neighbour_offsets(dimension, fully_connected):
    """The offsets to a voxel's neighbours: along one axis (face), or every one in {-1, 0, 1}^N."""
    offsets = []
    for offset in itertools.product((-1, 0, 1), repeat=dimension):
        moved = sum(1 for o in offset if o != 0)
        if moved == 1 or (moved > 1 and fully_connected):
            offsets.append(offset)
    return offsets


def label_components(member, fully_connected):
    """Labels the voxels where member is True by flood fill; returns (labels, sizes), with
    label -1 for the other voxels."""
    offsets = neighbour_offsets(member.ndim, fully_connected)
    labels = np.full(member.shape, -1, dtype=np.int64)
    sizes = []
    for seed in zip(*np.nonzero(member)):
        if labels[seed] >= 0:
            continue
        component = len(sizes)
        labels[seed] = component
        stack = [seed]
        size = 0
        while stack:
            voxel = stack.pop()
            size += 1
            for offset in offsets:
                neighbour = tuple(v + o for v, o in zip(voxel, offset))
                inside = all(0 <= n < extent for n, extent in zip(neighbour, member.shape))
                if inside and member[neighbour] and labels[neighbour] < 0:
                    labels[neighbour] = component
                    stack.append(neighbour)
        sizes.append(size)
    return labels, sizes


def repair_value(before, voxel, iso_value, removed_are_above):
    """The new value of a voxel of a removed component: the mean of the first values on the
    other side along each axis direction, x first, read from before."""
    total = 0.0
    found = 0
    for axis in reversed(range(before.ndim)):
        for step in (-1, 1):
            position = list(voxel)
            while True:
                position[axis] += step
                if not 0 <= position[axis] < before.shape[axis]:
                    break
                value = before[tuple(position)]
                if bool(is_above(value, iso_value)) != removed_are_above:
                    if value == value:
                        total += float(value)
                        found += 1
                    break
    if found == 0:
        raise ValueError(f"voxel {voxel} finds no value on the other side; the reference does not cover that")
    mean = total / found
    if np.issubdtype(before.dtype, np.integer):
        return before.dtype.type(math.floor(mean + 0.5))
    return before.dtype.type(mean)


def removal_pass(image, iso_value, max_size, above, active, fully_connected, mask, mask_value):
    """Labels one side of image and, when active, removes its components of at most
    max_size voxels in place (marking them in mask); returns the side's statistics."""
    labels, sizes = label_components(is_above(image, iso_value) == above, fully_connected)
    statistics = {
        "components": len(sizes),
        "removed_components": 0,
        "removed_voxels": 0,
        "histogram": dict(collections.Counter(sizes)),
    }
    if not active:
        return statistics
    removed = [size <= max_size for size in sizes]
    statistics["removed_components"] = sum(removed)
    statistics["removed_voxels"] = sum(size for size in sizes if size <= max_size)
    before = image.copy()
    for voxel in zip(*np.nonzero(labels >= 0)):
        if removed[labels[voxel]]:
            image[voxel] = repair_value(before, voxel, iso_value, above)
            mask[voxel] = mask_value
    return statistics


def run(values, iso_value, max_size, side="both", fully_connected=False, output_dtype=None):
    """The filter's result on values: a dict with output, mask (0 kept, 1 removed above, 2
    removed below), the statistics of each side ("above", "below") and modified_voxels."""
    output = np.array(values, dtype=output_dtype or values.dtype)
    mask = np.zeros(values.shape, dtype=np.uint8)
    result = {}
    if side == "above":
        # Only the above pass changes the image; the below statistics describe the input.
        result["below"] = removal_pass(output, iso_value, max_size, False, False, fully_connected, mask, 2)
    result["above"] = removal_pass(output, iso_value, max_size, True, side != "below", fully_connected, mask, 1)
    if side != "above":
        result["below"] = removal_pass(output, iso_value, max_size, False, True, fully_connected, mask, 2)
    result["output"] = output
    result["mask"] = mask
    result["modified_voxels"] = int(np.count_nonzero(mask))
    return result


def hand_made_failures():
    """Checks the reference on cases worked out by hand; returns the failed checks."""
    failures = []

    def check(condition, message):
        if not condition:
            failures.append(message)

    check(list(is_above(np.array([49.0, 50.0, np.nan]), 50.0)) == [False, True, False],
          "above means >= the isovalue; NaN is below")

    # A block with a one-voxel bubble inside and a two-voxel speck outside: with K = 5 both
    # go, the speck to 0 (its walks meet zeros) and the bubble to 100 (its neighbours).
    values = np.zeros((8, 10, 12), dtype=np.int16)
    values[1:7, 2:8, 3:9] = 100
    values[4, 5, 6] = 0
    values[6, 8, 0:2] = 100
    result = run(values, 50.0, 5)
    expected = np.zeros_like(values)
    expected[1:7, 2:8, 3:9] = 100
    check(np.array_equal(result["output"], expected), "scene: speck and bubble removed, nothing else changed")
    check(result["output"].dtype == np.int16, "scene: the pixel type is kept")
    check(result["mask"][6, 8, 0] == 1 and result["mask"][6, 8, 1] == 1 and result["mask"][4, 5, 6] == 2
          and result["modified_voxels"] == 3, "scene: the mask marks the speck 1 and the bubble 2")
    check(result["above"] == {"components": 2, "removed_components": 1, "removed_voxels": 2,
                              "histogram": {215: 1, 2: 1}}, f"scene: above statistics {result['above']}")
    check(result["below"]["components"] == 2 and result["below"]["removed_voxels"] == 1,
          f"scene: below statistics {result['below']}")

    # One speck between 10 and 11: the mean 10.5 rounds half up to 11. Side both then sees
    # one below component of three voxels, so the two one-voxel below components of the
    # input are not removed (on the input they would be).
    values = np.array([[10, 200, 11]], dtype=np.uint8)
    result = run(values, 100.0, 1)
    check(list(result["output"][0]) == [10, 11, 11], f"rounding half up: {result['output']}")
    check(result["below"] == {"components": 1, "removed_components": 0, "removed_voxels": 0,
                              "histogram": {3: 1}}, "both: the below pass sees the above pass's result")
    result = run(values, 100.0, 1, side="above")
    check(result["below"]["components"] == 2, "side above: the below statistics describe the input")
    result = run(values, 100.0, 1, side="below")
    check(list(result["output"][0]) == [200, 200, 200] and result["above"]["removed_components"] == 0,
          f"side below: the below voxels become the above value: {result['output']}")

    # The walks read the values before the pass: the second voxel of the speck walks through
    # the first one to the 0, whatever the first one has become.
    result = run(np.array([[0, 100, 100, 30]], dtype=np.uint8), 50.0, 2, side="above")
    check(list(result["output"][0]) == [0, 15, 15, 30], f"walks read the values before the pass: {result['output']}")

    # A walk that stops on NaN finds nothing; NaN itself is below and can be repaired.
    values = np.array([[np.nan, 5.0, 1.0, 3.0]], dtype=np.float32)
    result = run(values, 2.0, 1, side="above")
    check(np.array_equal(result["output"], np.array([[np.nan, 1.0, 1.0, 1.0]], dtype=np.float32), equal_nan=True),
          f"NaN is never a repair value: {result['output']}")
    result = run(np.array([[7.0, np.nan, 8.0]], dtype=np.float32), 2.0, 1, side="below")
    check(result["output"][0, 1] == 7.5, "a NaN voxel of a small below component gets the mean")

    # Two above voxels touching at a corner: two components with face connectivity, one
    # with full connectivity.
    values = np.array([[100, 0, 0], [0, 100, 0], [0, 0, 0]], dtype=np.uint8)
    check(run(values, 50.0, 1)["above"]["removed_components"] == 2, "face: corner neighbours are apart")
    full = run(values, 50.0, 1, fully_connected=True)
    check(full["above"]["components"] == 1 and full["above"]["removed_components"] == 0,
          "full: corner neighbours are one component of two voxels")

    # Integer in, float out: the mean is not rounded.
    result = run(np.array([[1, 9, 2]], dtype=np.int16), 5.0, 1, side="above", output_dtype=np.float32)
    check(result["output"].dtype == np.float32 and result["output"][0, 1] == 1.5, "integer to float keeps the mean")

    try:
        run(np.array([[100]], dtype=np.uint8), 50.0, 1)
        check(False, "a voxel that finds no value raises")
    except ValueError:
        pass
    return failures


if __name__ == "__main__":
    found = hand_made_failures()
    for failure in found:
        print("FAILED: " + failure)
    print(f"{len(found)} check(s) failed" if found else "the reference passes its hand-made cases")
    sys.exit(1 if found else 0)
