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
"""The filter from Python: wrapped types, the object API (parameters, statistics, the
removed mask), the functional API and the image metadata.

The scene: a 12 x 10 x 8 image of zeros holding a 6 x 6 x 6 block of 100 with a one-voxel
bubble (0) at its centre, and outside the block a two-voxel speck of 100. With isovalue 50
and K = 5 the speck is the only small above component and the bubble the only small
below component."""

import math
import sys

import itk
import numpy as np

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED: " + message)


def scene(dtype):
    """The scene as a NumPy array (z, y, x) and the expected output and mask."""
    values = np.zeros((8, 10, 12), dtype=dtype)
    values[1:7, 2:8, 3:9] = 100  # the block: 216 voxels
    values[4, 5, 6] = 0  # the bubble, inside the block
    values[6, 8, 0:2] = 100  # the speck, two voxels apart from the block
    expected = np.zeros_like(values)
    expected[1:7, 2:8, 3:9] = 100
    mask = np.zeros(values.shape, dtype=np.uint8)
    mask[6, 8, 0:2] = 1
    mask[4, 5, 6] = 2
    return values, expected, mask


def with_metadata(image):
    image.SetSpacing([0.5, 0.75, 2.0])
    image.SetOrigin([-10.0, 4.0, 7.5])
    direction = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    image.SetDirection(itk.matrix_from_array(direction))
    return image


def check_metadata(output, reference, what):
    check(np.array_equal(itk.spacing(output), itk.spacing(reference)), what + ": spacing kept")
    check(np.array_equal(itk.origin(output), itk.origin(reference)), what + ": origin kept")
    check(
        np.array_equal(itk.array_from_matrix(output.GetDirection()),
                       itk.array_from_matrix(reference.GetDirection())),
        what + ": direction kept",
    )


Side = itk.SmallIsoComponentEnums


# The wrapped instantiations: each scalar type to itself, integers to float, 2D and 3D.
instantiated = list(itk.SmallIsoComponentImageFilter.keys())
for dimension in (2, 3):
    for pixel in (itk.UC, itk.SS, itk.US, itk.F):
        image_type = itk.Image[pixel, dimension]
        check((image_type, image_type) in instantiated, f"instantiated for {image_type} -> same type")
    for pixel in (itk.UC, itk.SS, itk.US):
        key = (itk.Image[pixel, dimension], itk.Image[itk.F, dimension])
        check(key in instantiated, f"instantiated for {key[0]} -> float")

# The side enum.
check(int(Side.Side_Above) == 0 and int(Side.Side_Below) == 1 and int(Side.Side_Both) == 2,
      "Side values are Above = 0, Below = 1, Both = 2")

# The object API.
values, expected, expected_mask = scene(np.int16)
image = with_metadata(itk.image_from_array(values))
ImageType = itk.Image[itk.SS, 3]
filter = itk.SmallIsoComponentImageFilter[ImageType, ImageType].New(Input=image)
check(filter.GetIsoValue() == 0.0, "default IsoValue is 0")
check(filter.GetMaximumComponentSize() == 20, "default MaximumComponentSize is 20")
check(filter.GetSide() == Side.Side_Both, "default Side is Both")
check(not filter.GetFullyConnected(), "default FullyConnected is off")
check(not filter.GetGenerateRemovedMask(), "default GenerateRemovedMask is off")
check(isinstance(filter, itk.SmallIsoComponentImageFilterBase[ImageType, ImageType]),
      "the filter is a SmallIsoComponentImageFilterBase, wrapped for the same types")

filter.SetIsoValue(50.0)
filter.SetMaximumComponentSize(5)
filter.SetSide(Side.Side_Below)
check(filter.GetSide() == Side.Side_Below, "Side set to Below")
filter.SetSide(Side.Side_Both)
filter.FullyConnectedOn()
check(filter.GetFullyConnected(), "FullyConnectedOn")
filter.FullyConnectedOff()
filter.GenerateRemovedMaskOn()
check(filter.GetIsoValue() == 50.0 and filter.GetMaximumComponentSize() == 5, "parameters set")
filter.Update()

output = filter.GetOutput()
check(np.array_equal(itk.array_view_from_image(output), expected), "speck and bubble removed, nothing else changed")
check_metadata(output, image, "object API")
mask = filter.GetRemovedMask()
check(isinstance(mask, itk.Image[itk.UC, 3]), "the removed mask is an unsigned char image")
check(np.array_equal(itk.array_view_from_image(mask), expected_mask),
      "the mask marks the speck 1 and the bubble 2")
check_metadata(mask, image, "removed mask")

check(filter.GetNumberOfComponents(Side.Side_Above) == 2, "two above components: block and speck")
check(filter.GetNumberOfComponents(Side.Side_Below) == 2, "two below components: outside and bubble")
check(filter.GetNumberOfRemovedComponents(Side.Side_Above) == 1, "one above component removed")
check(filter.GetNumberOfRemovedComponents(Side.Side_Below) == 1, "one below component removed")
check(filter.GetNumberOfRemovedVoxels(Side.Side_Above) == 2, "two above voxels removed")
check(filter.GetNumberOfRemovedVoxels(Side.Side_Below) == 1, "one below voxel removed")
check(filter.GetNumberOfModifiedVoxels() == 3, "three voxels modified")
check(filter.GetNumberOfUnrepairableVoxels() == 0, "no unrepairable voxel")
check(filter.GetEffectiveMaximumComponentSize() == 5, "effective K is 5")

# The component-size histogram (a std::map) comes to Python as a mapping.
above = dict(filter.GetComponentSizeHistogram(Side.Side_Above))
check(above == {2: 1, 215: 1}, f"above histogram {above}")
below = dict(filter.GetComponentSizeHistogram(Side.Side_Below))
check(below == {1: 1, values.size - 215 - 1: 1}, f"below histogram {below}")

try:
    filter.GetNumberOfComponents(Side.Side_Both)
    check(False, "statistics of Both raise")
except RuntimeError:
    pass

# A physical threshold: one voxel is 0.75 mm^3, so 3.0 mm^3 means K = 4.
filter.SetMaximumComponentVolume(3.0)
check(filter.GetUseMaximumComponentVolume(), "the volume threshold is in use")
filter.Update()
check(filter.GetEffectiveMaximumComponentSize() == 4, "K from the volume")

filter.SetIsoValue(math.nan)
try:
    filter.Update()
    check(False, "a NaN isovalue raises")
except RuntimeError:
    pass

# Integer in, float out: the bubble gets the exact mean of its six neighbours.
FloatImageType = itk.Image[itk.F, 3]
to_float = itk.SmallIsoComponentImageFilter[ImageType, FloatImageType].New(
    image, IsoValue=50.0, MaximumComponentSize=5)
to_float.Update()
float_output = to_float.GetOutput()
check(isinstance(float_output, FloatImageType), "the output is a float image")
check(np.array_equal(itk.array_view_from_image(float_output), expected.astype(np.float32)),
      "float output")
check_metadata(float_output, image, "integer to float")

# The functional API. The filter has two indexed outputs, so ITK returns both: the
# filtered image and the removed mask. ITK 5.2's functional call fetches every output as
# the type of output 0, which only works when that is the mask's type, unsigned char; for
# other pixel types use the object API (above) until the mask stops being an indexed
# output.
values, expected, expected_mask = scene(np.uint8)
image = with_metadata(itk.image_from_array(values))
result, removed = itk.small_iso_component_image_filter(image, iso_value=50.0, maximum_component_size=5,
                                                       generate_removed_mask=True)
check(isinstance(result, itk.Image[itk.UC, 3]), "functional API keeps the pixel type")
check(np.array_equal(itk.array_view_from_image(result), expected), "functional API output")
check(np.array_equal(itk.array_view_from_image(removed), expected_mask), "functional API mask")
check_metadata(result, image, "functional API")

# A NumPy array in gives NumPy arrays out.
array_result, array_removed = itk.small_iso_component_image_filter(values, iso_value=50.0,
                                                                   maximum_component_size=5,
                                                                   generate_removed_mask=True)
check(isinstance(array_result, np.ndarray) and array_result.dtype == np.uint8,
      "functional API on a NumPy array returns an array of the same dtype")
check(np.array_equal(array_result, expected) and np.array_equal(array_removed, expected_mask),
      "functional API on a NumPy array")

# The object API with keyword arguments, for the other pixel types.
for dtype in (np.int16, np.uint16, np.float32):
    name = np.dtype(dtype).name
    values, expected, expected_mask = scene(dtype)
    image = with_metadata(itk.image_from_array(values))
    f = itk.SmallIsoComponentImageFilter.New(image, IsoValue=50.0, MaximumComponentSize=5,
                                             GenerateRemovedMask=True)
    f.Update()
    check(itk.template(f.GetOutput())[1] == itk.template(image)[1], f"New() keeps the {name} pixel type")
    check(np.array_equal(itk.array_view_from_image(f.GetOutput()), expected), f"output on {name}")
    check(np.array_equal(itk.array_view_from_image(f.GetRemovedMask()), expected_mask), f"mask on {name}")
    check_metadata(f.GetOutput(), image, f"output on {name}")

# 2D: the middle slice, with K = 1 removes the bubble only (the speck is two pixels).
values, expected, _ = scene(np.uint8)
image2d = itk.image_from_array(np.ascontiguousarray(values[4]))
result2d, _ = itk.small_iso_component_image_filter(image2d, iso_value=50.0, maximum_component_size=1,
                                                   side=Side.Side_Below)
check(np.array_equal(itk.array_view_from_image(result2d), expected[4]), "2D bubble removed")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
