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

// The repair of a pass on its own: the new value of every removed voxel (the mean of the
// first other-side values along each axis, NaN never one of them, the closest value on the
// other side when no walk finds one), the mask (and the same values without one), the count of
// unrepairable voxels, against a voxel-by-voxel repair, for removed runs few enough to stay
// on one thread and many enough to be shared; and the flip grouping done in the same loop
// joins every removed run.

#include "itkSmallIsoComponentBelowGrouping.h"
#include "itkSmallIsoComponentInternalsTestUtilities.h"
#include "itkSmallIsoComponentRunRepair.h"
#include "gtest/gtest.h"

#include <array>
#include <sstream>
#include <vector>

namespace
{
using namespace itk::SmallIsoComponentTest;
using itk::SizeValueType;
namespace Internal = itk::SmallIsoComponentDetail;

/** A value above σ = 50.5 with probability \a aboveShare, else one below it (NaN in a
 * tenth of the floating-point ones). */
template <typename T>
T
RandomValue(RandomSource & random, double aboveShare)
{
  if (random.Chance(aboveShare))
  {
    return static_cast<T>(random.Between(51, 100));
  }
  if constexpr (!std::is_integral<T>::value)
  {
    if (random.Chance(0.1))
    {
      return std::numeric_limits<T>::quiet_NaN();
    }
    return static_cast<T>(random.Uniform() * 50.5);
  }
  return static_cast<T>(random.Between(0, 50));
}

template <typename T, unsigned int VDimension>
void
CheckRepairs(uint32_t      seed,
             unsigned int  volumes,
             SizeValueType smallestExtent,
             SizeValueType largestExtent,
             bool          shared = false)
{
  RandomSource random(seed);
  for (unsigned int volume = 0; volume < volumes; ++volume)
  {
    const auto            extent = RandomExtent<VDimension>(random, smallestExtent, largestExtent);
    itk::Size<VDimension> size;
    std::copy(extent.begin(), extent.end(), size.begin());
    const bool                        fullyConnected = random.Chance(0.5);
    const Reference::Grid<VDimension> grid(extent, fullyConnected);
    const bool                        removedAreAbove = random.Chance(0.5);
    // Where the repair is to be shared, the removed side is sparse: many small components.
    const double aboveShare =
      shared ? (removedAreAbove ? 0.15 : 0.85) : random.Pick(std::array<double, 3>{ 0.1, 0.5, 0.9 });
    const double   isoValue = 50.5;
    std::vector<T> values(grid.NumberOfVoxels());
    for (auto & value : values)
    {
      value = RandomValue<T>(random, aboveShare);
    }
    const auto            maximumSize = static_cast<SizeValueType>(random.Between(1, 30));
    Internal::RunLabeling labeling;
    Label(labeling, values, ExtentOf(grid), isoValue, fullyConnected, 2, maximumSize);
    const auto           voxelComponent = VoxelComponents(labeling);
    std::vector<uint8_t> removed(labeling.GetComponents().GetNumberOfComponents(), 0);
    for (SizeValueType c = 0; c < removed.size(); ++c)
    {
      const auto component = static_cast<Internal::RunLabeling::ComponentIndexType>(c);
      removed[c] = labeling.GetComponents().IsComponentAbove(component) == removedAreAbove &&
                   labeling.GetComponents().GetComponentSize(component) <= maximumSize && random.Chance(0.8);
    }
    const auto runs = labeling.GetComponents().CollectCandidateRuns(removed);

    // Some voxels were marked by an earlier pass: the repair marks them again.
    std::vector<T>       output = values;
    std::vector<uint8_t> mask(values.size());
    for (auto & m : mask)
    {
      m = random.Chance(0.2) ? 1 : 0;
    }
    const std::vector<uint8_t> maskBefore = mask;

    auto threader = itk::MultiThreaderBase::New();
    threader->SetNumberOfWorkUnits(2);
    Internal::WorkTeam team(threader, 2);
    if (shared)
    {
      ASSERT_GT(team.GetNumberOfChunks(runs.size()), 1u) << runs.size() << " removed runs are repaired in one chunk";
    }
    Internal::BelowGrouping            grouping(labeling);
    Internal::RunRepair<T, VDimension> repair(team, labeling, runs, size);
    // Removed above runs flip in the below pass of Side Both: the grouping joins them.
    repair.ComputeValues(
      values.data(), Internal::Threshold<T>(isoValue), removedAreAbove, removedAreAbove ? &grouping : nullptr);
    repair.WriteValues(output.data(), mask.data(), 2);
    std::vector<T> withoutMask = values;
    repair.WriteValues(withoutMask.data(), nullptr, 2);

    T                  fallback{};
    const bool         haveFallback = removedAreAbove ? Reference::LargestValueBelow(isoValue, fallback)
                                                      : Reference::SmallestValueNotBelow(isoValue, fallback);
    SizeValueType      expectedUnrepairable = 0;
    SizeValueType      removedVoxels = 0;
    std::ostringstream where;
    where << "seed " << seed << " volume " << volume << " full " << fullyConnected << " above " << removedAreAbove;
    ASSERT_TRUE(haveFallback);
    for (SizeValueType v = 0; v < values.size(); ++v)
    {
      if (!removed[voxelComponent[v]])
      {
        ASSERT_TRUE(SameBits(output[v], values[v]) && mask[v] == maskBefore[v]) << where.str() << " voxel " << v;
        continue;
      }
      ++removedVoxels;
      T expected{};
      if (!Reference::RepairValue(grid, values, isoValue, removedAreAbove, v, expected))
      {
        expected = fallback;
        ++expectedUnrepairable;
      }
      ASSERT_TRUE(SameBits(output[v], expected)) << where.str() << " voxel " << v << ": " << PixelToString(output[v])
                                                 << ", expected " << PixelToString(expected);
      ASSERT_EQ(mask[v], 2) << where.str() << " voxel " << v;
    }
    for (SizeValueType v = 0; v < values.size(); ++v)
    {
      ASSERT_TRUE(SameBits(withoutMask[v], output[v])) << where.str() << " voxel " << v << " written without a mask";
    }
    EXPECT_EQ(repair.GetNumberOfUnrepairableVoxels(), expectedUnrepairable) << where.str();
    EXPECT_GE(repair.GetValueBytes(), removedVoxels * sizeof(T)) << where.str();

    // The joins done in the repair's chunks are the joins of all the runs at once.
    if (!removedAreAbove)
    {
      continue;
    }
    Internal::BelowGrouping alone(labeling);
    alone.JoinNeighbors(runs.data(), runs.data() + runs.size());
    const auto together = grouping.Finish(removed);
    const auto separate = alone.Finish(removed);
    EXPECT_EQ(together.GroupOfComponent, separate.GroupOfComponent) << where.str();
    EXPECT_EQ(together.GroupSize, separate.GroupSize) << where.str();
  }
}
} // namespace

TEST(SmallIsoComponentRunRepair, NewValuesAsAVoxelByVoxelRepairFindsThem)
{
  CheckRepairs<float, 2>(301, 150, 1, 20);
  CheckRepairs<int16_t, 3>(302, 150, 1, 10);
  CheckRepairs<uint8_t, 4>(303, 60, 1, 5);
}

TEST(SmallIsoComponentRunRepair, ManyRemovedRunsAreSharedInChunksAndRepairedAlike)
{
  // Enough removed runs for the team to cut the loops into chunks.
  CheckRepairs<float, 3>(311, 3, 30, 40, true);
  CheckRepairs<uint8_t, 2>(312, 3, 150, 200, true);
}
