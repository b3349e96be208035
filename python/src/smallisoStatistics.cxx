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
#include "smallisoStatistics.h"

#include <stdexcept>
#include <string_view>

namespace smalliso
{
namespace
{
py::dict
SideDict(const SideCounts & counts)
{
  py::dict side;
  side["components"] = counts.Components;
  side["removed_components"] = counts.RemovedComponents;
  side["removed_voxels"] = counts.RemovedVoxels;
  py::dict histogram;
  for (const auto & [size, number] : counts.Histogram)
  {
    histogram[py::int_(size)] = number;
  }
  side["size_histogram"] = histogram;
  return side;
}

SideCounts
CountsOf(const itk::SmallIsoComponentDetail::SideTally & tally)
{
  return { tally.GetComponents(), tally.GetRemovedComponents(), tally.GetRemovedVoxels(), tally.GetHistogram() };
}

/** Needs no GIL: the caller holds the bytes object \a data points into. */
itk::SmallIsoComponentDetail::BlockSummary
Deserialize(std::string_view data)
{
  return itk::SmallIsoComponentDetail::BlockSummary::Deserialize(reinterpret_cast<const uint8_t *>(data.data()),
                                                                 data.size());
}
} // namespace

BoxIndex
ToBox(const std::vector<uint64_t> & numpyOrder, uint64_t fill)
{
  if (numpyOrder.size() == 2)
  {
    return { numpyOrder[1], fill, numpyOrder[0] };
  }
  return { numpyOrder[2], numpyOrder[1], numpyOrder[0] };
}

py::dict
StatisticsDict(const SideCounts & above, const SideCounts & below, uint64_t modifiedVoxels, uint64_t unrepairableVoxels)
{
  py::dict statistics;
  statistics["above"] = SideDict(above);
  statistics["below"] = SideDict(below);
  statistics["modified_voxels"] = modifiedVoxels;
  statistics["unrepairable_voxels"] = unrepairableVoxels;
  return statistics;
}

SideEnum
ParseSide(const std::string & side)
{
  if (side == "above")
  {
    return SideEnum::Above;
  }
  if (side == "below")
  {
    return SideEnum::Below;
  }
  if (side == "both")
  {
    return SideEnum::Both;
  }
  throw py::value_error("side is '" + side + "'; expected 'above', 'below' or 'both'");
}

py::bytes
MergeSummaries(const py::bytes & lower, const py::bytes & upper)
{
  const std::string_view lowerData(lower);
  const std::string_view upperData(upper);
  std::vector<uint8_t>   merged;
  {
    py::gil_scoped_release release;
    merged =
      itk::SmallIsoComponentDetail::BlockSummary::Merge(Deserialize(lowerData), Deserialize(upperData)).Serialize();
  }
  return py::bytes(reinterpret_cast<const char *>(merged.data()), merged.size());
}

py::dict
SummaryStatistics(const py::bytes & summary)
{
  const auto   root = Deserialize(std::string_view(summary));
  const auto & tally = root.GetTally();
  return StatisticsDict(CountsOf(tally.Above), CountsOf(tally.Below), tally.ModifiedVoxels, tally.UnrepairableVoxels);
}
} // namespace smalliso
