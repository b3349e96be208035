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

// The grouping of below components through flipped above components: hand-made cases (a
// bubble inside a speck, a wall between two below components, corners that only full
// connectivity crosses) and random volumes in 2-D to 4-D against a flood fill of the below
// voxels and the flipped ones, with the flipped runs joined in ranges of any size, in any
// order, and from several threads at once.

#include "itkSmallIsoComponentBelowGrouping.h"
#include "itkSmallIsoComponentInternalsTestUtilities.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <array>
#include <sstream>
#include <vector>

namespace
{
using namespace itk::SmallIsoComponentTest;
using itk::SizeValueType;
using itk::SmallIsoComponentDetail::BelowGrouping;
using RunLabeling = itk::SmallIsoComponentDetail::RunLabeling;

/** A labelling, the above components flipped in it, and their groups. */
struct Grouped
{
  RunLabeling                Labeling;
  std::vector<uint8_t>       Flipped;
  BelowGrouping::Groups      Groups;
  std::vector<SizeValueType> VoxelComponent;
};

/** Groups \a values (200 above, 10 below) with the above components that hold a voxel
 * of \a flippedVoxels flipped; the flipped runs are joined in ranges of at most
 * \a rangeRuns runs, the ranges handed to a team of \a workUnits. */
template <unsigned int VDimension>
void
Group(Grouped &                           grouped,
      const std::vector<uint8_t> &        values,
      const Reference::Grid<VDimension> & grid,
      bool                                fullyConnected,
      const std::vector<uint8_t> &        flippedVoxels,
      SizeValueType                       rangeRuns,
      unsigned int                        workUnits)
{
  Label(grouped.Labeling, values, ExtentOf(grid), 100.0, fullyConnected, 2, grid.NumberOfVoxels());
  grouped.VoxelComponent = VoxelComponents(grouped.Labeling);
  grouped.Flipped.assign(grouped.Labeling.GetComponents().GetNumberOfComponents(), 0);
  for (SizeValueType v = 0; v < values.size(); ++v)
  {
    if (flippedVoxels[v] && values[v] >= 100)
    {
      grouped.Flipped[grouped.VoxelComponent[v]] = 1;
    }
  }
  // Every run is a candidate: the candidate size is the whole image.
  const std::vector<RunLabeling::LineRun> flippedRuns =
    grouped.Labeling.GetComponents().CollectCandidateRuns(grouped.Flipped);
  BelowGrouping       grouping(grouped.Labeling);
  const SizeValueType ranges = (flippedRuns.size() + rangeRuns - 1) / rangeRuns;
  auto                threader = itk::MultiThreaderBase::New();
  threader->SetNumberOfWorkUnits(workUnits);
  itk::SmallIsoComponentDetail::WorkTeam team(threader, workUnits);
  team.ForEach(ranges, [&](SizeValueType range) {
    // The last range first: the order of the joins does not matter.
    const SizeValueType first = (ranges - 1 - range) * rangeRuns;
    const SizeValueType last = std::min<SizeValueType>(flippedRuns.size(), first + rangeRuns);
    grouping.JoinNeighbors(flippedRuns.data() + first, flippedRuns.data() + last);
  });
  grouped.Groups = grouping.Finish(grouped.Flipped);
}

/** Empty when the groups are the components of the below and flipped voxels, with
 * their sizes, numbered in order of their first voxel, and the other above components
 * in no group. */
template <unsigned int VDimension>
std::string
GroupsDifference(const Grouped & grouped, const std::vector<uint8_t> & values, const Reference::Grid<VDimension> & grid)
{
  std::vector<uint8_t>       member(values.size());
  std::vector<SizeValueType> voxelGroup(values.size());
  for (SizeValueType v = 0; v < values.size(); ++v)
  {
    const SizeValueType component = grouped.VoxelComponent[v];
    member[v] = values[v] < 100 || grouped.Flipped[component] ? 1 : 0;
    voxelGroup[v] = grouped.Groups.GroupOfComponent[component];
    if (!member[v] && voxelGroup[v] != BelowGrouping::NoGroup)
    {
      return "an above component that did not flip is in a group";
    }
  }
  std::vector<SizeValueType> sizes;
  const auto                 expected = Reference::LabelComponents(grid, member, sizes);
  std::string                difference = PartitionDifference(voxelGroup, expected);
  if (!difference.empty())
  {
    return difference;
  }
  if (grouped.Groups.GroupSize.size() != sizes.size())
  {
    return "number of groups differs";
  }
  // The flood fill numbers its components in order of their first voxel, as the groups are.
  for (SizeValueType v = 0; v < values.size(); ++v)
  {
    if (member[v] && (voxelGroup[v] != expected[v] || grouped.Groups.GroupSize[voxelGroup[v]] != sizes[expected[v]]))
    {
      std::ostringstream out;
      out << "voxel " << v << " in group " << voxelGroup[v] << " of " << grouped.Groups.GroupSize[voxelGroup[v]]
          << " voxels; the flood fill: " << expected[v] << " of " << sizes[expected[v]];
      return out.str();
    }
  }
  return "";
}

/** Random sides and flips on \a grid (for ForEachRandomGrid), grouped in random ranges by
 * one or three work units, against the flood fill. */
template <unsigned int VDimension>
void
CheckRandomVolume(RandomSource &                      random,
                  const Reference::Grid<VDimension> & grid,
                  bool                                fullyConnected,
                  const std::string &                 where)
{
  const double         density = random.Pick(std::array<double, 3>{ 0.2, 0.5, 0.8 });
  std::vector<uint8_t> values(grid.NumberOfVoxels());
  std::vector<uint8_t> flippedVoxels(values.size());
  for (SizeValueType v = 0; v < values.size(); ++v)
  {
    values[v] = random.Chance(density) ? 200 : 10;
    flippedVoxels[v] = random.Chance(0.1) ? 1 : 0;
  }
  const auto         rangeRuns = static_cast<SizeValueType>(random.Pick(std::array<int, 4>{ 1, 3, 16, 100000 }));
  const unsigned int workUnits = random.Chance(0.5) ? 1 : 3;
  Grouped            grouped;
  Group(grouped, values, grid, fullyConnected, flippedVoxels, rangeRuns, workUnits);
  EXPECT_EQ(GroupsDifference(grouped, values, grid), "") << where << " ranges of " << rangeRuns;
}

/** The groups of a hand-made 2-D image, given as rows (y from 0), '#' above, '.' below,
 * 'F' above and flipped: the size of each group in order. */
std::vector<SizeValueType>
GroupSizes(const std::vector<std::string> & rows, bool fullyConnected)
{
  const std::array<SizeValueType, 2> extent{ rows[0].size(), rows.size() };
  const Reference::Grid<2>           grid(extent, fullyConnected);
  std::vector<uint8_t>               values;
  std::vector<uint8_t>               flippedVoxels;
  for (const std::string & row : rows)
  {
    for (const char c : row)
    {
      values.push_back(c == '.' ? 10 : 200);
      flippedVoxels.push_back(c == 'F' ? 1 : 0);
    }
  }
  Grouped grouped;
  Group(grouped, values, grid, fullyConnected, flippedVoxels, 1, 1);
  EXPECT_EQ(GroupsDifference(grouped, values, grid), "");
  return grouped.Groups.GroupSize;
}
} // namespace

TEST(SmallIsoComponentBelowGrouping, ABubbleInsideAFlippedSpeckJoinsTheOutside)
{
  const std::vector<std::string> rows{ ".......", ".FFF...", ".F.F...", ".FFF...", "......." };
  EXPECT_EQ(GroupSizes(rows, false), std::vector<SizeValueType>{ 35 });
  // Not flipped: the bubble stays a group of its own, the speck in none.
  const std::vector<std::string> kept{ ".......", ".###...", ".#.#...", ".###...", "......." };
  EXPECT_EQ(GroupSizes(kept, false), (std::vector<SizeValueType>{ 26, 1 }));
}

TEST(SmallIsoComponentBelowGrouping, AFlippedWallJoinsTheComponentsOnBothSides)
{
  EXPECT_EQ(GroupSizes({ "..F..", "..F..", "..F.." }, false), std::vector<SizeValueType>{ 15 });
  EXPECT_EQ(GroupSizes({ "..#..", "..#..", "..#.." }, false), (std::vector<SizeValueType>{ 6, 6 }));
}

TEST(SmallIsoComponentBelowGrouping, FullConnectivityGroupsThroughCorners)
{
  // Face: the flipped corner and its two neighbours join three of the four below voxels;
  // the one at the lower right touches the rest only at corners. Full: one group.
  const std::vector<std::string> rows{ "F#.", "#.#", ".#." };
  EXPECT_EQ(GroupSizes(rows, false), (std::vector<SizeValueType>{ 6, 1 }));
  EXPECT_EQ(GroupSizes(rows, true), std::vector<SizeValueType>{ 9 });
}

TEST(SmallIsoComponentBelowGrouping, GroupsAsAFloodFillOfTheBelowAndFlippedVoxels)
{
  ForEachRandomGrid<2>(201, 150, 25, CheckRandomVolume<2>);
  ForEachRandomGrid<3>(202, 150, 10, CheckRandomVolume<3>);
  ForEachRandomGrid<4>(203, 60, 5, CheckRandomVolume<4>);
}
