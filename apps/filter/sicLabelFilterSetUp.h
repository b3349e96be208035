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
#ifndef sicLabelFilterSetUp_h
#define sicLabelFilterSetUp_h

// How the label tools set up SmallIsoComponentLabelImageFilter from their settings and run it: shared by the
// in-memory and the streamed runs.

#include "sicFilterReport.h"
#include "sicImageFiles.h"
#include "sicStrings.h"
#include "sicToolError.h"

#include "itkSmallIsoComponentLabelImageFilter.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace sic
{
/** Whether \a value is a value of TLabel, which is then set to it: exactly, for floating-point labels. */
template <typename TLabel, typename TValue>
bool
Holds(TValue value, TLabel & label)
{
  if constexpr (std::is_floating_point_v<TLabel>)
  {
    label = static_cast<TLabel>(value);
    // A uint64 near 2^64 rounds up to 2^64, which does not convert back.
    if constexpr (std::is_unsigned_v<TValue>)
    {
      if (label >= static_cast<TLabel>(18446744073709551616.0L))
      {
        return false;
      }
    }
    return static_cast<TValue>(label) == value;
  }
  else
  {
    using Limits = std::numeric_limits<TLabel>;
    label = static_cast<TLabel>(value);
    if constexpr (std::is_signed_v<TValue>)
    {
      return Limits::is_signed && value >= static_cast<TValue>(Limits::min());
    }
    else
    {
      return value <= static_cast<std::uint64_t>(Limits::max());
    }
  }
}

/** The label that the canonical id \a id names, which must be a value of TLabel. */
template <typename TLabel>
TLabel
LabelOf(const std::string & flag, const std::string & id, itk::IOComponentEnum type)
{
  TLabel label{};
  errno = 0;
  const bool holds = id[0] == '-' ? Holds(std::strtoll(id.c_str(), nullptr, 10), label)
                                  : Holds(std::strtoull(id.c_str(), nullptr, 10), label);
  if (errno == ERANGE || !holds)
  {
    throw ToolError(flag + " label " + id + " is not a value of the input's pixel type " + PixelTypeName(type) +
                    "; expected a label id the input can hold");
  }
  return label;
}

/** \a label as the statistics key it: a whole number, without a sign for 0. */
template <typename TLabel>
std::string
LabelText(TLabel label)
{
  if constexpr (std::is_floating_point_v<TLabel>)
  {
    char text[400];
    std::snprintf(text, sizeof(text), "%.0f", static_cast<double>(label) + 0.0);
    return text;
  }
  else if constexpr (std::is_signed_v<TLabel>)
  {
    return std::to_string(static_cast<long long>(label));
  }
  else
  {
    return std::to_string(static_cast<unsigned long long>(label));
  }
}

template <typename TFilter>
void
SetUpLabelFilter(TFilter & filter, const FilterSettings & settings, itk::IOComponentEnum type)
{
  using LabelType = typename TFilter::LabelType;
  using Selection = itk::SmallIsoComponentLabelEnums::Selection;
  const auto label = [type](const std::string & flag, const std::string & id) {
    return LabelOf<LabelType>(flag, id, type);
  };
  filter.SetBackgroundValue(label("--background", settings.Background));
  if (settings.Selection == "listed")
  {
    std::vector<LabelType> labels;
    for (const std::string & id : settings.SelectedLabels)
    {
      labels.push_back(label("--select", id));
    }
    filter.SetSelectedLabels(labels);
  }
  filter.SetSelection(settings.Selection == "listed"    ? Selection::Listed
                      : settings.Selection == "islands" ? Selection::Islands
                      : settings.Selection == "holes"   ? Selection::Holes
                                                        : Selection::All);
  typename TFilter::LabelSizeMapType sizes;
  for (const auto & [id, size] : settings.LabelMaximumSizes)
  {
    sizes[label("--max-size-of", id)] = size;
  }
  filter.SetMaximumComponentSizes(sizes);
  if (settings.UsesVolume())
  {
    filter.SetMaximumComponentVolume(*settings.MaximumVolume);
  }
  else
  {
    filter.SetMaximumComponentSize(settings.MaximumSize);
  }
  filter.SetKeepLargestComponents(settings.KeepLargest);
  filter.SetFullyConnected(settings.FullyConnected);
  filter.SetGenerateRemovedMask(!settings.RemovedMask.empty());
  if (settings.Threads > 0)
  {
    filter.SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(settings.Threads));
  }
  // The input is not needed afterwards: filtering in place saves a copy of the volume.
  filter.InPlaceOn();
}

/** Runs \a filter, turning its refusal of a floating-point map with a fractional sample into a ToolError. */
template <typename TFilter>
void
UpdateLabelFilter(TFilter & filter, const FilterSettings & settings)
{
  try
  {
    filter.Update();
  }
  catch (const itk::MemoryAllocationError &)
  {
    throw;
  }
  catch (const itk::ProcessAborted &)
  {
    throw;
  }
  catch (const itk::ExceptionObject & error)
  {
    // Set up as it is, the filter refuses only a floating-point map with a sample that is not a whole number.
    if (!std::is_floating_point_v<typename TFilter::LabelType>)
    {
      throw;
    }
    throw ToolError("cannot filter input " + Quoted(settings.Input) +
                    " as a label map: " + ItkErrorText(error.GetDescription()));
  }
}
} // namespace sic

#endif
