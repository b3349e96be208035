#!/usr/bin/env python3
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
"""The label filter from Python: the wrapped types, the object API (parameters, the selection, per-label K, the
removed mask, per-label statistics) and the functional API, held voxel for voxel to the brute-force reference of
the label-map rule (python/test/label_reference.py) on random maps of every wrapped type, 2-D and 3-D."""

import os
import sys

import itk
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python", "test"))
from label_reference import IDS, SHAPES, random_labels, reference  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED: " + message)


Selection = itk.SmallIsoComponentLabelEnums
PIXELS = {"uint8": itk.UC, "uint16": itk.US, "int16": itk.SS, "uint32": itk.UI}

# The wrapped instantiations: the label types of ITK's wheels and unsigned int, 2-D and 3-D.
instantiated = [key if isinstance(key, tuple) else (key,) for key in itk.SmallIsoComponentLabelImageFilter.keys()]
for dimension in (2, 3):
    for pixel in PIXELS.values():
        check((itk.Image[pixel, dimension],) in instantiated, f"instantiated for {itk.Image[pixel, dimension]}")
check(int(Selection.Selection_All) == 0 and int(Selection.Selection_Islands) == 1
      and int(Selection.Selection_Holes) == 2 and int(Selection.Selection_Listed) == 3,
      "Selection values are All = 0, Islands = 1, Holes = 2, Listed = 3")


def run_filter(labels, pixel, max_size, fully_connected=False, select="all", background=0, max_sizes=None,
               keep_largest=0):
    """The object API with the reference's options; returns the filter after its update."""
    image = itk.image_from_array(labels)
    image.SetSpacing([0.5] * labels.ndim)
    filter = itk.SmallIsoComponentLabelImageFilter[itk.Image[pixel, labels.ndim]].New(Input=image)
    filter.SetMaximumComponentSize(max_size)
    filter.SetFullyConnected(fully_connected)
    if isinstance(select, list):
        filter.SetSelection(Selection.Selection_Listed)
        filter.SetSelectedLabels(select)
    else:
        filter.SetSelection(getattr(Selection, "Selection_" + select.capitalize()))
    filter.SetBackgroundValue(background)
    for label, size in (max_sizes or {}).items():
        filter.SetMaximumComponentSizeOfLabel(label, size)
    filter.SetKeepLargestComponents(keep_largest)
    filter.GenerateRemovedMaskOn()
    filter.Update()
    check(tuple(itk.spacing(filter.GetOutput())) == (0.5,) * labels.ndim, "spacing kept")
    return filter


def check_against_reference(labels, pixel, what, **options):
    expected, expected_mask, expected_stats = reference(labels, **options)
    filter = run_filter(labels, pixel, **options)
    check(np.array_equal(itk.array_view_from_image(filter.GetOutput()), expected), what + ": output")
    check(np.array_equal(itk.array_view_from_image(filter.GetRemovedMask()), expected_mask), what + ": mask")
    check(list(filter.GetLabels()) == sorted(expected_stats["labels"]), what + ": labels")
    for label, entry in expected_stats["labels"].items():
        found = {"components": filter.GetNumberOfComponents(label),
                 "removed_components": filter.GetNumberOfRemovedComponents(label),
                 "removed_voxels": filter.GetNumberOfRemovedVoxels(label),
                 "gained_voxels": filter.GetNumberOfGainedVoxels(label),
                 "size_histogram": dict(filter.GetComponentSizeHistogram(label))}
        check(found == entry, f"{what}: statistics of label {label}: {found} != {entry}")
    check(filter.GetNumberOfModifiedVoxels() == expected_stats["modified_voxels"], what + ": modified voxels")
    check(filter.GetNumberOfUnrepairableVoxels() == expected_stats["unrepairable_voxels"],
          what + ": unrepairable voxels")
    return expected_stats["modified_voxels"]


rng = np.random.default_rng(42)
modified = 0
for dtype, pixel in PIXELS.items():
    ids = IDS[dtype]
    for ndim in (2, 3):
        for case in range(4):
            labels = random_labels(rng, dtype, SHAPES[ndim])
            options = dict(max_size=int(rng.integers(0, 9)), fully_connected=bool(case % 2),
                           select=["all", "islands", "holes", [int(ids[-1]), int(ids[1])]][case])
            if case >= 2:
                options["max_sizes"] = {int(ids[-1]): int(rng.integers(0, 30)), int(ids[0]): 1}
            if case == 1:
                options["background"] = int(ids[-1])
            modified += check_against_reference(labels, pixel, f"{dtype} {ndim}-D case {case}", **options)
        labels = random_labels(rng, dtype, SHAPES[ndim])
        modified += check_against_reference(labels, pixel, f"{dtype} {ndim}-D keep-largest", max_size=1,
                                            keep_largest=1, select="islands")
check(modified > 0, "the random maps had voxels to repair")

# K from a physical volume: voxels of 0.125 mm^3, so 0.5 mm^3 is K = 4.
labels = random_labels(rng, "uint8", SHAPES[3])
filter = run_filter(labels, itk.UC, 0)
filter.SetMaximumComponentVolume(0.5)
filter.Update()
check(filter.GetEffectiveMaximumComponentSize() == 4, "K from the volume")
expected, _, _ = reference(labels, max_size=4)
check(np.array_equal(itk.array_view_from_image(filter.GetOutput()), expected), "output with K from the volume")

# The functional API gives the output and the mask; a NumPy array in gives arrays out.
labels = random_labels(rng, "uint8", SHAPES[3])
expected, expected_mask, _ = reference(labels, max_size=3)
result, removed = itk.small_iso_component_label_image_filter(itk.image_from_array(labels), maximum_component_size=3,
                                                             generate_removed_mask=True)
check(isinstance(result, itk.Image[itk.UC, 3]), "functional API keeps the pixel type")
check(np.array_equal(itk.array_view_from_image(result), expected), "functional API output")
check(np.array_equal(itk.array_view_from_image(removed), expected_mask), "functional API mask")
array_result, _ = itk.small_iso_component_label_image_filter(labels, maximum_component_size=3)
check(isinstance(array_result, np.ndarray) and np.array_equal(array_result, expected),
      "functional API on a NumPy array")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
