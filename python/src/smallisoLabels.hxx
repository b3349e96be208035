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
#ifndef smallisoLabels_hxx
#define smallisoLabels_hxx

#include "smallisoArrays.h"
#include "smallisoLabels.h"

#include "itkImage.h"
#include "itkSmallIsoComponentLabelImageFilter.h"

#include <cmath>
#include <sstream>
#include <type_traits>

namespace smalliso
{
namespace detail
{
using SelectionEnum = itk::SmallIsoComponentLabelEnums::Selection;

template <typename TLabel>
std::vector<TLabel>
LabelsOf(const py::array & labels)
{
  const auto typed = labels.cast<py::array_t<TLabel, py::array::c_style | py::array::forcecast>>();
  return { typed.data(), typed.data() + typed.size() };
}

/** A label as the key of the statistics: a Python int, for floating-point maps too. */
template <typename TLabel>
py::int_
LabelKey(TLabel label)
{
  if constexpr (std::is_floating_point_v<TLabel>)
  {
    return py::int_(py::float_(static_cast<double>(label)));
  }
  else
  {
    return py::int_(label);
  }
}

template <typename TFilter>
py::dict
LabelStatisticsDict(const TFilter & filter)
{
  py::dict labels;
  for (const auto & [label, counts] : filter.GetLabelStatistics())
  {
    py::dict entry;
    entry["components"] = counts.Components;
    entry["removed_components"] = counts.RemovedComponents;
    entry["removed_voxels"] = counts.RemovedVoxels;
    entry["gained_voxels"] = counts.GainedVoxels;
    py::dict histogram;
    for (const auto & [size, number] : counts.Histogram)
    {
      histogram[py::int_(size)] = number;
    }
    entry["size_histogram"] = histogram;
    labels[LabelKey(label)] = entry;
  }
  py::dict statistics;
  statistics["labels"] = labels;
  statistics["modified_voxels"] = filter.GetNumberOfModifiedVoxels();
  statistics["unrepairable_voxels"] = filter.GetNumberOfUnrepairableVoxels();
  statistics["effective_max_size"] = filter.GetEffectiveMaximumComponentSize();
  return statistics;
}

/** The filter's refusal of a sample that is not a whole number, with the sample's NumPy index. */
template <typename TLabel>
[[noreturn]] void
RefuseSample(const py::array_t<TLabel> & labels, bool fortran)
{
  const TLabel * const data = labels.data();
  const auto           whole = [](TLabel value) { return itk::SmallIsoComponentDetail::AreWholeNumbers(&value, 1); };
  py::ssize_t          offset = 0;
  while (offset + 1 < labels.size() && whole(data[offset]))
  {
    ++offset;
  }
  std::vector<py::ssize_t> index(labels.ndim());
  for (py::ssize_t k = 0, rest = offset; k < labels.ndim(); ++k)
  {
    const py::ssize_t axis = fortran ? k : labels.ndim() - 1 - k;
    index[axis] = rest % labels.shape(axis);
    rest /= labels.shape(axis);
  }
  std::ostringstream message;
  message << "the label map's sample at index (";
  for (std::size_t axis = 0; axis < index.size(); ++axis)
  {
    message << (axis > 0 ? ", " : "") << index[axis];
  }
  message << (index.size() == 1 ? ",)" : ")") << " is " << static_cast<double>(data[offset])
          << "; a label map holds whole numbers only (no fraction, infinity or NaN)";
  throw py::value_error(message.str());
}

template <typename TLabel, unsigned int VDimension>
py::tuple
FilterLabelImage(py::array_t<TLabel> & labels, const LabelParameters & parameters, bool inPlace, bool withMask)
{
  using ImageType = itk::Image<TLabel, VDimension>;
  using FilterType = itk::SmallIsoComponentLabelImageFilter<ImageType>;
  // ITK's x is the fastest axis: a C-ordered array's last axis, a Fortran-ordered array's first.
  const bool fortran = (labels.flags() & py::array::c_style) == 0;
  const auto image = ImageOf<ImageType>(labels, parameters.Spacing);

  auto filter = FilterType::New();
  filter->SetInput(image);
  if (parameters.MaximumVolume)
  {
    filter->SetMaximumComponentVolume(*parameters.MaximumVolume);
  }
  else
  {
    filter->SetMaximumComponentSize(parameters.MaximumSize);
  }
  typename FilterType::LabelSizeMapType sizes;
  const std::vector<TLabel>             sizeLabels = LabelsOf<TLabel>(parameters.SizeLabels);
  for (std::size_t k = 0; k < sizeLabels.size(); ++k)
  {
    sizes[sizeLabels[k]] = parameters.Sizes[k];
  }
  filter->SetMaximumComponentSizes(sizes);
  const std::string & selection = parameters.Selection;
  filter->SetSelection(selection == "islands"  ? SelectionEnum::Islands
                       : selection == "holes"  ? SelectionEnum::Holes
                       : selection == "listed" ? SelectionEnum::Listed
                                               : SelectionEnum::All);
  filter->SetSelectedLabels(LabelsOf<TLabel>(parameters.Selected));
  filter->SetBackgroundValue(LabelsOf<TLabel>(parameters.Background).at(0));
  filter->SetKeepLargestComponents(parameters.KeepLargest);
  filter->SetFullyConnected(parameters.FullyConnected);
  if (parameters.Threads > 0)
  {
    filter->SetNumberOfWorkUnits(parameters.Threads);
  }
  filter->SetInPlace(inPlace);
  filter->SetGenerateRemovedMask(withMask);
  bool refused = false;
  {
    py::gil_scoped_release release;
    try
    {
      filter->Update();
    }
    catch (const itk::ExceptionObject &)
    {
      // The only refusal the checked arguments leave: a sample that is not a whole number.
      if (!std::is_floating_point_v<TLabel>)
      {
        throw;
      }
      refused = true;
    }
  }
  if (refused)
  {
    RefuseSample(labels, fortran);
  }
  ImageType * output = filter->GetOutput();
  if (inPlace && output->GetBufferPointer() != labels.data())
  {
    throw std::logic_error("smalliso: the label filter did not run in place");
  }
  const std::vector<py::ssize_t> shape(labels.shape(), labels.shape() + VDimension);
  return py::make_tuple(inPlace ? py::object(py::none()) : py::object(ArrayOf(output, shape, fortran)),
                        withMask ? py::object(ArrayOf(filter->GetRemovedMask(), shape, fortran))
                                 : py::object(py::none()),
                        LabelStatisticsDict(*filter));
}
} // namespace detail

template <typename TLabel>
py::tuple
FilterLabels(py::array_t<TLabel> labels, const LabelParameters & parameters, bool inPlace, bool withMask)
{
  switch (labels.ndim())
  {
    case 2:
      return detail::FilterLabelImage<TLabel, 2>(labels, parameters, inPlace, withMask);
    case 3:
      return detail::FilterLabelImage<TLabel, 3>(labels, parameters, inPlace, withMask);
    default:
      return detail::FilterLabelImage<TLabel, 4>(labels, parameters, inPlace, withMask);
  }
}
} // namespace smalliso

/** Compiles the label filter for label type T. */
#define SMALLISO_INSTANTIATE_LABELS(T)                \
  template pybind11::tuple smalliso::FilterLabels<T>( \
    pybind11::array_t<T>, const smalliso::LabelParameters &, bool, bool);

#endif
