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
// The label-map part of smalliso._core (see smallisoLabels.h).

#include "smallisoLabels.h"
#include "smallisoPixelTypes.h"

#include "itkIntTypes.h"

#include <pybind11/stl.h>

namespace smalliso
{
namespace
{
/** Calls function(TLabel{}) for the label type of \a labels' dtype (aligned, as the Python layer
 * makes it). */
template <typename TFunction>
py::tuple
ForLabelTypeOf(const py::array & labels, TFunction && function)
{
#define SMALLISO_DISPATCH(T)                  \
  if (py::isinstance<py::array_t<T>>(labels)) \
  {                                           \
    return function(T{});                     \
  }
  SMALLISO_FOR_EACH_LABEL_TYPE(SMALLISO_DISPATCH)
#undef SMALLISO_DISPATCH
  throw py::type_error("dtype " + std::string(py::str(labels.dtype())) + " is not supported for label maps");
}
} // namespace

void
DefineLabelFunctions(py::module_ & module)
{
  py::list names;
#define SMALLISO_NAME(T) names.append(py::str(py::dtype::of<T>()));
  SMALLISO_FOR_EACH_LABEL_TYPE(SMALLISO_NAME)
#undef SMALLISO_NAME
  module.attr("label_types") = py::tuple(names);

  module.def(
    "filter_labels",
    [](const py::array &     labels,
       uint64_t              maxSize,
       std::optional<double> maxVolume,
       std::vector<double>   spacing,
       const py::array &     sizeLabels,
       std::vector<uint64_t> sizes,
       const std::string &   selection,
       const py::array &     selected,
       const py::array &     background,
       uint64_t              keepLargest,
       bool                  fullyConnected,
       bool                  inPlace,
       bool                  withMask,
       unsigned int          threads) {
      const LabelParameters parameters{ maxSize,   maxVolume, std::move(spacing), sizeLabels,  std::move(sizes),
                                        selection, selected,  background,         keepLargest, fullyConnected,
                                        threads };
      return ForLabelTypeOf(labels, [&](auto label) {
        using LabelType = decltype(label);
        return FilterLabels<LabelType>(labels.cast<py::array_t<LabelType>>(), parameters, inPlace, withMask);
      });
    },
    "(output or None in place, mask or None without with_mask, statistics) of the label filter on a C- or "
    "Fortran-contiguous, aligned 2-D, 3-D or 4-D label map; the label-valued arguments are arrays of its dtype.",
    py::arg("labels"),
    py::arg("max_size"),
    py::arg("max_volume"),
    py::arg("spacing"),
    py::arg("size_labels"),
    py::arg("sizes"),
    py::arg("selection"),
    py::arg("selected"),
    py::arg("background"),
    py::arg("keep_largest"),
    py::arg("fully_connected"),
    py::arg("in_place"),
    py::arg("with_mask"),
    py::arg("threads"));
}
} // namespace smalliso
