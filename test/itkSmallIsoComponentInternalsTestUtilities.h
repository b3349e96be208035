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
#include "itkSmallIsoComponentReference.h"
#include "itkSmallIsoComponentRunEncoder.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "itkSmallIsoComponentWorkTeam.h"
#include <array>
#include <sstream>
#include <string>
#include <vector>

namespace itk
{
/** What the tests of the filter's internal classes share: a labelling run the way the
 * filter runs it, the component of every voxel, and the comparison of two partitions of
 * the voxels. */
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

/** Labels \a values (extent \a size, axis 0 fastest) at \a isoValue as the filter does:
 * encode, assemble, link, number (keeping the candidates of at most \a candidateSize
 * voxels), the lines cut into slabs for \a slabUnits work units and the loops run by a
 * team of \a teamUnits work units. */
template <typename TPixel>
void
Label(SmallIsoComponentDetail::RunLabeling & labeling,
      const std::vector<TPixel> &            values,
      const std::vector<SizeValueType> &     size,
      double                                 isoValue,
      bool                                   fullyConnected,
      unsigned int                           slabUnits,
      SizeValueType                          candidateSize,
      unsigned int                           teamUnits = 2)
{
  auto threader = MultiThreaderBase::New();
  threader->SetNumberOfWorkUnits(teamUnits);
  SmallIsoComponentDetail::WorkTeam team(threader, teamUnits);
  labeling.Initialize(size, fullyConnected, slabUnits);
  SmallIsoComponentDetail::RunEncoder<TPixel>(isoValue).Encode(values.data(), labeling, team);
  labeling.AssembleRuns(team);
  labeling.LinkRuns();
  labeling.LabelComponents(candidateSize);
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
} // namespace SmallIsoComponentTest
} // end namespace itk

#endif
