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
"""NumPy -> itk.image_from_array -> the filter -> itk.array_from_image gives, bit for bit,
what the NumPy reference (small_iso_component_reference.py) computes on small random
volumes, with the same statistics, the pixel type and the image metadata kept.

The volumes take a few values each, so that they have components of many sizes on both
sides and samples equal to the isovalue; the float volume has NaN samples."""

import sys

import itk
import numpy as np

import small_iso_component_reference as reference

failures = ["reference: " + failure for failure in reference.hand_made_failures()]
for failure in failures:
    print("FAILED: " + failure)
rng = np.random.default_rng(20240611)
Side = itk.SmallIsoComponentEnums
SIDES = {"above": Side.Side_Above, "below": Side.Side_Below, "both": Side.Side_Both}


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED: " + message)


def bits(array):
    """The array's bytes, so that floats (NaN included) compare bit for bit."""
    return np.ascontiguousarray(array).view(np.uint8)


def with_metadata(image):
    dimension = image.GetImageDimension()
    image.SetSpacing([0.8, 1.25, 2.5][:dimension])
    image.SetOrigin([12.0, -3.5, 100.0][:dimension])
    direction = np.eye(dimension)[::-1].copy()  # the axes reversed: a mirroring direction
    image.SetDirection(itk.matrix_from_array(direction))
    return image


def check_metadata(got, image, what):
    check(np.array_equal(itk.spacing(got), itk.spacing(image)), what + " keeps the spacing")
    check(np.array_equal(itk.origin(got), itk.origin(image)), what + " keeps the origin")
    check(np.array_equal(itk.array_from_matrix(got.GetDirection()), itk.array_from_matrix(image.GetDirection())),
          what + " keeps the direction")


def round_trip(name, values, iso_value, max_size, side="both", fully_connected=False, to_float=False):
    expected = reference.run(values, iso_value, max_size, side, fully_connected, np.float32 if to_float else None)
    image = with_metadata(itk.image_from_array(values))
    if to_float:
        f = itk.SmallIsoComponentImageFilter[type(image), itk.Image[itk.F, values.ndim]].New(image)
    else:
        f = itk.SmallIsoComponentImageFilter.New(image)
    f.SetIsoValue(iso_value)
    f.SetMaximumComponentSize(max_size)
    f.SetSide(SIDES[side])
    f.SetFullyConnected(fully_connected)
    f.GenerateRemovedMaskOn()
    f.Update()
    output = itk.array_from_image(f.GetOutput())
    mask = itk.array_from_image(f.GetRemovedMask())

    check(output.dtype == expected["output"].dtype, f"{name}: output dtype {output.dtype}")
    check(output.shape == values.shape, f"{name}: output shape {output.shape}")
    if output.dtype == expected["output"].dtype and output.shape == values.shape:
        check(np.array_equal(bits(output), bits(expected["output"])), f"{name}: output equals the reference bit for bit")
    check(mask.dtype == np.uint8 and np.array_equal(mask, expected["mask"]), f"{name}: mask equals the reference")
    check(expected["modified_voxels"] > 0, f"{name}: the case removes something")
    check(f.GetNumberOfModifiedVoxels() == expected["modified_voxels"], f"{name}: modified voxels")
    check(f.GetNumberOfUnrepairableVoxels() == 0, f"{name}: no unrepairable voxel")
    for side_name in ("above", "below"):
        statistics = expected[side_name]
        got = {
            "components": f.GetNumberOfComponents(SIDES[side_name]),
            "removed_components": f.GetNumberOfRemovedComponents(SIDES[side_name]),
            "removed_voxels": f.GetNumberOfRemovedVoxels(SIDES[side_name]),
            "histogram": dict(f.GetComponentSizeHistogram(SIDES[side_name])),
        }
        check(got == statistics, f"{name}: {side_name} statistics {got}, expected {statistics}")
    check_metadata(f.GetOutput(), image, f"{name}: the output")
    check_metadata(f.GetRemovedMask(), image, f"{name}: the mask")


def levels(shape, count, dtype, low=0, step=1):
    """Random samples taking count values low, low + step, ..."""
    return (low + step * rng.integers(0, count, size=shape)).astype(dtype)


round_trip("uchar-3d", levels((6, 7, 8), 3, np.uint8, step=50), 50.0, 3)
round_trip("uchar-3d-full", levels((7, 6, 8), 3, np.uint8, step=50), 50.5, 4, fully_connected=True)
round_trip("short-3d-above", levels((8, 6, 7), 4, np.int16, low=-1000, step=500), 0.0, 2, side="above")
round_trip("short-3d-below", levels((8, 6, 7), 4, np.int16, low=-1000, step=500), 0.0, 2, side="below")
round_trip("ushort-2d", levels((24, 30), 3, np.uint16, step=2048), 2048.0, 3)
round_trip("short-to-float-3d", levels((6, 8, 7), 5, np.int16, low=-7, step=3), 0.5, 3, to_float=True)
noisy = rng.normal(0.0, 1.0, size=(7, 8, 9)).astype(np.float32)
noisy[rng.random(noisy.shape) < 0.05] = np.nan
round_trip("float-3d", noisy, 0.25, 5)
round_trip("float-2d-full", noisy[3].copy(), -0.5, 2, fully_connected=True)

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
