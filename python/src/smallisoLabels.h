/*=========================================================================
 *
 *  Copyright SmallIsoComponent contributors
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#ifndef smallisoLabels_h
#define smallisoLabels_h

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

/** The label-map filter of the smalliso package on NumPy arrays. The label-valued parameters come
 * as NumPy arrays of the label map's own dtype, converted and range-checked by the Python code. */
namespace smalliso
{
namespace py = pybind11;

/** What the label filter is asked to do. */
struct LabelParameters
{
  uint64_t              MaximumSize{ 20 };
  std::optional<double> MaximumVolume;
  /** In NumPy's axis order; empty: 1 per axis. */
  std::vector<double> Spacing;
  /** Labels with their own K (an array of the label dtype) and those K. */
  py::array             SizeLabels;
  std::vector<uint64_t> Sizes;
  /** "all", "islands", "holes" or "listed" (the labels of Selected, an array of the label dtype). */
  std::string  Selection{ "all" };
  py::array    Selected;
  py::array    Background;
  uint64_t     KeepLargest{ 0 };
  bool         FullyConnected{ false };
  unsigned int Threads{ 0 };
};

/** Filters \a labels (2-D, 3-D or 4-D, C- or Fortran-contiguous, aligned) with
 * itk::SmallIsoComponentLabelImageFilter on its own buffer. Returns (output or None in place, mask
 * or None without \a withMask, statistics). A floating-point map with a sample that is not a whole
 * number gives a ValueError naming its NumPy index. */
template <typename TLabel>
py::tuple
FilterLabels(py::array_t<TLabel> labels, const LabelParameters & parameters, bool inPlace, bool withMask);

/** Adds filter_labels and label_types to the core's module. */
void
DefineLabelFunctions(py::module_ & module);
} // namespace smalliso

#endif
