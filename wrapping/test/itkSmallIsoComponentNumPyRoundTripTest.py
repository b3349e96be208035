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
what the command-line tool writes for the same input, and keeps the image metadata.

Usage: itkSmallIsoComponentNumPyRoundTripTest.py SMALLISOCOMPONENTFILTER OUTPUT_DIRECTORY

The inputs are random noise, which has components of every size on both sides."""

import os
import subprocess
import sys

import itk
import numpy as np

tool, output_directory = sys.argv[1], sys.argv[2]
os.makedirs(output_directory, exist_ok=True)
rng = np.random.default_rng(20240611)
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED: " + message)


def bits(array):
    """The array's bytes, so that floats (NaN included) compare bit for bit."""
    return np.ascontiguousarray(array).view(np.uint8)


def round_trip(name, values, iso_value, max_size):
    image = itk.image_from_array(values)
    image.SetSpacing([0.8, 1.25, 2.5][: values.ndim])
    image.SetOrigin([12.0, -3.5, 100.0][: values.ndim])

    f = itk.SmallIsoComponentImageFilter.New(image, IsoValue=iso_value, MaximumComponentSize=max_size)
    f.Update()
    result = f.GetOutput()
    python_values = itk.array_from_image(result)

    input_file = os.path.join(output_directory, f"roundtrip-{name}-input.nrrd")
    tool_file = os.path.join(output_directory, f"roundtrip-{name}-tool.nrrd")
    itk.imwrite(image, input_file)
    run = subprocess.run(
        [tool, input_file, tool_file, "--isovalue", repr(iso_value), "--max-size", str(max_size)],
        capture_output=True,
        text=True,
    )
    if run.returncode != 0:
        check(False, f"{name}: the tool failed ({run.returncode}): {run.stderr}")
        return
    tool_image = itk.imread(tool_file)
    tool_values = itk.array_from_image(tool_image)

    check(python_values.dtype == values.dtype, f"{name}: pixel type kept ({python_values.dtype})")
    check(tool_values.dtype == python_values.dtype, f"{name}: the tool wrote {tool_values.dtype}")
    check(tool_values.shape == python_values.shape, f"{name}: same shape")
    if tool_values.dtype == python_values.dtype and tool_values.shape == python_values.shape:
        check(np.array_equal(bits(tool_values), bits(python_values)),
              f"{name}: Python and the tool agree bit for bit")
    check(not np.array_equal(bits(python_values), bits(values)), f"{name}: something was removed")
    for what, got in (("filter output", result), ("tool output", tool_image)):
        check(np.allclose(itk.spacing(got), itk.spacing(image)), f"{name}: {what} keeps the spacing")
        check(np.allclose(itk.origin(got), itk.origin(image)), f"{name}: {what} keeps the origin")


round_trip("uchar-3d", rng.integers(0, 101, size=(20, 24, 28), dtype=np.uint8), 50.5, 3)
round_trip("short-3d", rng.integers(-1000, 1001, size=(16, 18, 20), dtype=np.int16), 0.0, 4)
round_trip("ushort-2d", rng.integers(0, 4096, size=(64, 48), dtype=np.uint16), 2048.0, 2)
noisy = rng.normal(0.0, 1.0, size=(20, 22, 24)).astype(np.float32)
noisy[rng.random(noisy.shape) < 0.01] = np.nan
round_trip("float-3d", noisy, 0.25, 5)

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
