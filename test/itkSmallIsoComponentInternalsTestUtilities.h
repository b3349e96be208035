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
#ifndef itkSmallIsoComponentInternalsTestUtilities_h
#define itkSmallIsoComponentInternalsTestUtilities_h

#include "itkMultiThreaderBase.h"
#include "itkSmallIsoComponentBlockSummary.h"
#include "itkSmallIsoComponentReference.h"
#include "itkSmallIsoComponentRunEncoder.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "itkSmallIsoComponentWorkTeam.h"
#include "gtest/gtest.h"
#include <array>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace itk
{
/** What the tests of the filter's internal classes share: random grids, a labelling run the
 * way the filter runs it, the component of every voxel, the comparison of two partitions of
 * the voxels, and the comparison of a streamed or chunked run with the reference. */
namespace SmallIsoComponentTest
{
/** The extent of a Reference::Grid as the labeling takes it. */
template <unsigned int VDimension>
std::vector<SizeValueType>
ExtentOf(const Reference::Grid<VDimension> & grid)
{
  return std::vector<SizeValueType>(grid.Size().begin(), grid.Size().end());
}

/** An extent of VDimension axes, each drawn from [smallest, largest]. */
template <unsigned int VDimension>
std::array<SizeValueType, VDimension>
RandomExtent(RandomSource & random, SizeValueType smallest, SizeValueType largest)
{
  std::array<SizeValueType, VDimension> extent;
  for (auto & axisExtent : extent)
  {
    axisExtent =
      static_cast<SizeValueType>(random.Between(static_cast<int64_t>(smallest), static_cast<int64_t>(largest)));
  }
  return extent;
}

/** Calls \a check(random, grid, fullyConnected, where) for \a volumes random grids drawn
 * from \a seed, each of VDimension axes with extents in [1, largestExtent] and either
 * connectivity, \a where naming it for messages ("seed 7 volume 3 full 1"); stops at a
 * fatal failure (an ASSERT in \a check). */
template <unsigned int VDimension, typename TCheck>
void
ForEachRandomGrid(uint32_t seed, unsigned int volumes, SizeValueType largestExtent, TCheck && check)
{
  RandomSource random(seed);
  for (unsigned int volume = 0; volume < volumes && !::testing::Test::HasFatalFailure(); ++volume)
  {
    const auto                        extent = RandomExtent<VDimension>(random, 1, largestExtent);
    const bool                        fullyConnected = random.Chance(0.5);
    const Reference::Grid<VDimension> grid(extent, fullyConnected);
    std::ostringstream                where;
    where << "seed " << seed << " volume " << volume << " full " << fullyConnected;
    check(random, grid, fullyConnected, where.str());
  }
}

/** Labels \a values (extent \a size, axis 0 fastest) at \a isoValue as the filter does:
 * encode, assemble, link, number (keeping the candidates of at most \a candidateSize
 * voxels), the lines cut into slabs for \a slabUnits work units and the loops run by a
 * team of \a teamUnits work units; a shared numbering given the scratch arrays
 * \a partialSizes and \a partialCandidates if not null. */
template <typename TPixel>
void
Label(SmallIsoComponentDetail::RunLabeling &                                  labeling,
      const std::vector<TPixel> &                                             values,
      const std::vector<SizeValueType> &                                      size,
      double                                                                  isoValue,
      bool                                                                    fullyConnected,
      unsigned int                                                            slabUnits,
      SizeValueType                                                           candidateSize,
      unsigned int                                                            teamUnits = 2,
      bool                                                                    aboveCandidates = true,
      bool                                                                    belowCandidates = true,
      std::vector<SmallIsoComponentDetail::RunLabeling::ComponentIndexType> * partialSizes = nullptr,
      std::vector<SmallIsoComponentDetail::RunLabeling::LineRun> *            partialCandidates = nullptr)
{
  auto threader = MultiThreaderBase::New();
  threader->SetNumberOfWorkUnits(teamUnits);
  SmallIsoComponentDetail::WorkTeam team(threader, teamUnits);
  labeling.Initialize(size, fullyConnected, slabUnits);
  SmallIsoComponentDetail::RunEncoder<TPixel>(isoValue).Encode(values.data(), labeling, team);
  labeling.AssembleRuns(team);
  labeling.LinkRuns();
  SmallIsoComponentDetail::RunComponents::Sharing sharing;
  sharing.PartialSizes = partialSizes;
  sharing.PartialCandidates = partialCandidates;
  labeling.LabelComponents(team, aboveCandidates ? candidateSize : 0, belowCandidates ? candidateSize : 0, sharing);
}

/** The component of every voxel, from the runs of a labeling. */
inline std::vector<SizeValueType>
VoxelComponents(const SmallIsoComponentDetail::RunLabeling & labeling)
{
  const SmallIsoComponentDetail::RunLabeling::RunTable runs = labeling.GetRunTable();
  std::vector<SizeValueType>                           component(labeling.GetNumberOfLines() * runs.LineLength);
  for (SizeValueType line = 0; line < labeling.GetNumberOfLines(); ++line)
  {
    for (SizeValueType run = runs.LineBegin[line]; run < runs.LineBegin[line + 1]; ++run)
    {
      for (SizeValueType x = runs.Start[run]; x < runs.End(run, line); ++x)
      {
        component[line * runs.LineLength + x] = runs.Component[run];
      }
    }
  }
  return component;
}

/** Empty when \a actual and \a expected put the same voxels together (one label of
 * each for one label of the other), where \a expected is not \a unlabelled; otherwise
 * the first voxel where they disagree. */
inline std::string
PartitionDifference(const std::vector<SizeValueType> & actual,
                    const std::vector<SizeValueType> & expected,
                    SizeValueType                      unlabelled = Reference::NoComponent)
{
  std::map<SizeValueType, SizeValueType> toExpected;
  std::map<SizeValueType, SizeValueType> toActual;
  for (SizeValueType v = 0; v < expected.size(); ++v)
  {
    if (expected[v] == unlabelled)
    {
      continue;
    }
    const auto forward = toExpected.emplace(actual[v], expected[v]).first;
    const auto backward = toActual.emplace(expected[v], actual[v]).first;
    if (forward->second != expected[v] || backward->second != actual[v])
    {
      std::ostringstream out;
      out << "voxel " << v << ": label " << actual[v] << " where the reference has " << expected[v];
      return out.str();
    }
  }
  return "";
}
/** The extent \a size as the box of planes along its last axis that the streaming sweep and
 * the chunked mode take: a 2-D image's planes are its lines. */
template <unsigned int VDimension>
std::array<uint64_t, 3>
PlaneBox(const std::array<SizeValueType, VDimension> & size)
{
  std::array<uint64_t, 3> box{ size[0], 1, 1 };
  if constexpr (VDimension == 2)
  {
    box[2] = size[1];
  }
  else
  {
    box[1] = size[1];
    box[2] = size[2];
  }
  return box;
}

/** Appends " N voxels and M mask voxels differ" to \a differences when \a output (bit for
 * bit) or the two low bits of \a mask differ from \a expected; returns the number of
 * fallback marks in \a mask (bits 4 and 8, one for each pass that gave a voxel the
 * fallback value). */
template <typename TPixel>
uint64_t
AppendVoxelDifferences(std::ostream &                    differences,
                       const std::vector<TPixel> &       output,
                       const std::vector<uint8_t> &      mask,
                       const Reference::Result<TPixel> & expected)
{
  uint64_t wrongVoxels = 0;
  uint64_t wrongMask = 0;
  uint64_t fallbackMarks = 0;
  for (std::size_t v = 0; v < output.size(); ++v)
  {
    wrongVoxels += SameBits(output[v], expected.Output[v]) ? 0 : 1;
    wrongMask += (mask[v] & 3) == expected.Mask[v] ? 0 : 1;
    fallbackMarks += ((mask[v] & 4) != 0 ? 1 : 0) + ((mask[v] & 8) != 0 ? 1 : 0);
  }
  if (wrongVoxels > 0 || wrongMask > 0)
  {
    differences << " " << wrongVoxels << " voxels and " << wrongMask << " mask voxels differ";
  }
  return fallbackMarks;
}

/** Appends " above statistics differ" or " below statistics differ" to \a differences for
 * each side whose components, removed components, removed voxels or size histogram in
 * \a tally differ from \a expected. */
template <typename TPixel>
void
AppendSideDifferences(std::ostream &                                  differences,
                      const SmallIsoComponentDetail::ComponentTally & tally,
                      const Reference::Result<TPixel> &               expected)
{
  const auto compareSide =
    [&](const char * name, const SmallIsoComponentDetail::SideTally & got, const Reference::SideStatistics & want) {
      const auto histogram = got.GetHistogram();
      if (got.GetComponents() != want.Components || got.GetRemovedComponents() != want.RemovedComponents ||
          got.GetRemovedVoxels() != want.RemovedVoxels ||
          Reference::HistogramType(histogram.begin(), histogram.end()) != want.Histogram)
      {
        differences << " " << name << " statistics differ";
      }
    };
  compareSide("above", tally.Above, expected.Above);
  compareSide("below", tally.Below, expected.Below);
}
} // namespace SmallIsoComponentTest
} // end namespace itk

#endif
