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
#ifndef smallisoStatistics_h
#define smallisoStatistics_h

#include "smallisoCore.h"

#include <map>
#include <string>

namespace smalliso
{
/** The statistics of one side of the isovalue. */
struct SideCounts
{
  uint64_t                     Components{ 0 };
  uint64_t                     RemovedComponents{ 0 };
  uint64_t                     RemovedVoxels{ 0 };
  std::map<uint64_t, uint64_t> Histogram;
};

/** The statistics as a dict with the names of the command-line tool's JSON: "above" and "below"
 * (each with "components", "removed_components", "removed_voxels" and "size_histogram", a dict
 * size -> number of components), "modified_voxels", "unrepairable_voxels". */
py::dict
StatisticsDict(const SideCounts & above,
               const SideCounts & below,
               uint64_t           modifiedVoxels,
               uint64_t           unrepairableVoxels);

/** "above", "below" or "both" as the filter's Side. */
SideEnum
ParseSide(const std::string & side);

/** The summary of the union of two chunks' boxes (serialized), \a upper starting where \a lower
 * ends along one axis. */
py::bytes
MergeSummaries(const py::bytes & lower, const py::bytes & upper);

/** The statistics of the components a summary settled (the whole image's, at the root of the
 * merges, except the voxels that got the fallback value, which the chunks' filters count). */
py::dict
SummaryStatistics(const py::bytes & summary);
} // namespace smalliso

#endif
