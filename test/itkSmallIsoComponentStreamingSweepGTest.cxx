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
// The streaming sweep against the brute-force reference: every output voxel, every mask voxel and
// every statistic, for random volumes, slab thicknesses from one plane to the whole volume, and
// input handed over in random pieces.

#include "itkSmallIsoComponentInternalsTestUtilities.h"
#include "itkSmallIsoComponentStreamingSweep.h"

#include "gtest/gtest.h"

namespace
{
using namespace itk;
using namespace itk::SmallIsoComponentTest;

/** Runs the sweep on \a c with slabs of \a slabPlanes planes, the input handed over in pieces of 1
 * to 4 planes drawn from \a random, and returns how it differs from the reference (empty if not). */
template <typename TPixel, unsigned int VDimension>
std::string
SweepDifferences(const RandomCase<TPixel, VDimension> & c,
                 uint64_t                               slabPlanes,
                 unsigned int                           workUnits,
                 RandomSource &                         random)
{
  const auto expected = Reference::Run<TPixel>(c.Input.GetPointer(), c.Settings);
  // The image as a box whose planes are along its last axis.
  const std::array<uint64_t, 3> size = PlaneBox<VDimension>(c.Size);
  const uint64_t                planeVoxels = size[0] * size[1];
  std::vector<TPixel>           output(c.Values.size());
  std::vector<uint8_t>          mask(c.Values.size());
  uint64_t                      nextPlane = 0;
  bool                          outOfOrder = false;
  auto                          threader = MultiThreaderBase::New();
  threader->SetNumberOfWorkUnits(workUnits);
  SmallIsoComponentDetail::StreamingSweep<TPixel> sweep(
    size,
    c.Settings.IsoValue,
    c.Settings.MaximumComponentSize,
    c.Settings.Side,
    c.Settings.FullyConnected,
    slabPlanes,
    true,
    threader,
    workUnits,
    [&](uint64_t plane, const TPixel * values, const uint8_t * planeMask) {
      outOfOrder = outOfOrder || plane != nextPlane;
      ++nextPlane;
      std::copy(values, values + planeVoxels, output.begin() + plane * planeVoxels);
      std::copy(planeMask, planeMask + planeVoxels, mask.begin() + plane * planeVoxels);
    });
  for (uint64_t given = 0; given < size[2];)
  {
    const auto piece = std::min<uint64_t>(size[2] - given, static_cast<uint64_t>(random.Between(1, 4)));
    sweep.Push(c.Values.data() + given * planeVoxels, piece);
    given += piece;
  }
  sweep.Finish();

  std::ostringstream differences;
  if (outOfOrder || nextPlane != size[2])
  {
    differences << " planes out of order or missing";
  }
  const uint64_t fallbackMarks = AppendVoxelDifferences(differences, output, mask, expected);
  if (fallbackMarks != expected.FallbackVoxels)
  {
    differences << " " << fallbackMarks << " voxels marked as given the fallback value, not "
                << expected.FallbackVoxels;
  }
  const auto & tally = sweep.GetTally();
  AppendSideDifferences(differences, tally, expected);
  if (tally.ModifiedVoxels != expected.ModifiedVoxels ||
      tally.UnrepairableVoxels + sweep.GetNumberOfFallbackVoxels() != expected.UnrepairableVoxels)
  {
    differences << " modified " << tally.ModifiedVoxels << "/" << expected.ModifiedVoxels << ", unrepairable "
                << tally.UnrepairableVoxels << "+" << sweep.GetNumberOfFallbackVoxels() << "/"
                << expected.UnrepairableVoxels;
  }
  const uint64_t bound = SmallIsoComponentDetail::StreamingSweep<TPixel>::WindowPlanes(
    c.Settings.MaximumComponentSize, slabPlanes, workUnits);
  if (sweep.GetPeakWindowPlanes() > bound)
  {
    differences << " held " << sweep.GetPeakWindowPlanes() << " planes at once, more than the bound " << bound;
  }
  if (!differences.str().empty())
  {
    differences << " (slabPlanes=" << slabPlanes << " workUnits=" << workUnits << ")";
  }
  return differences.str();
}

template <typename TPixel, unsigned int VDimension>
void
CheckSweepOfRandomVolumes(uint32_t firstSeed, unsigned int numberOfVolumes, bool large = false)
{
  unsigned int failures = 0;
  unsigned int thinSlabs = 0;
  for (uint32_t seed = firstSeed; seed < firstSeed + numberOfVolumes && failures < 5; ++seed)
  {
    const auto     c = MakeRandomCase<TPixel, TPixel, VDimension>(seed, large);
    RandomSource   random(seed * 31u + 7u);
    const uint64_t depth = VDimension == 2 ? c.Size[1] : c.Size[2];
    const uint64_t slabPlanes =
      random.Chance(0.3) ? 1 : static_cast<uint64_t>(random.Between(1, static_cast<int>(depth)));
    const unsigned int workUnits = random.Chance(0.5) ? 1 : 2;
    thinSlabs += slabPlanes == 1 ? 1 : 0;
    const std::string differences = SweepDifferences(c, slabPlanes, workUnits, random);
    if (!differences.empty())
    {
      ADD_FAILURE() << c.Description << ":" << differences;
      ++failures;
    }
  }
  EXPECT_GT(thinSlabs, numberOfVolumes / 5);
}

/** Tall volumes of random binary noise with a small K: the window must stay within its bound
 * while the sweep runs far past it. */
void
CheckSweepOfTallNoise(uint32_t firstSeed, unsigned int numberOfVolumes)
{
  unsigned int failures = 0;
  for (uint32_t seed = firstSeed; seed < firstSeed + numberOfVolumes && failures < 5; ++seed)
  {
    RandomSource           random(seed);
    RandomCase<uint8_t, 3> c;
    c.Size = { static_cast<SizeValueType>(random.Between(1, 9)),
               static_cast<SizeValueType>(random.Between(1, 9)),
               static_cast<SizeValueType>(random.Between(60, 140)) };
    const double density = 0.2 + 0.6 * random.Uniform();
    for (SizeValueType v = 0; v < c.Size[0] * c.Size[1] * c.Size[2]; ++v)
    {
      c.Values.push_back(random.Chance(density) ? 255 : 0);
    }
    c.Input = MakeImage<uint8_t, 3>(c.Size, c.Values);
    c.Settings.IsoValue = 127.5;
    c.Settings.MaximumComponentSize = static_cast<SizeValueType>(random.Between(1, 6));
    c.Settings.Side = random.Pick(std::array<SideEnum, 3>{ SideEnum::Above, SideEnum::Below, SideEnum::Both });
    c.Settings.FullyConnected = random.Chance(0.5);
    const auto        slabPlanes = static_cast<uint64_t>(random.Between(1, 5));
    const std::string differences = SweepDifferences(c, slabPlanes, 1, random);
    if (!differences.empty())
    {
      ADD_FAILURE() << "seed=" << seed << " size=[" << c.Size[0] << "," << c.Size[1] << "," << c.Size[2]
                    << "] density=" << density << " K=" << c.Settings.MaximumComponentSize
                    << " side=" << c.Settings.Side << " fullyConnected=" << c.Settings.FullyConnected << ":"
                    << differences;
      ++failures;
    }
  }
}
/** A hand-made 3-D case: \a size voxels, all \a background except those \a draw sets. */
template <typename TDraw>
RandomCase<int16_t, 3>
NamedCase(const std::array<SizeValueType, 3> & size, SizeValueType maximumSize, SideEnum side, TDraw && draw)
{
  RandomCase<int16_t, 3> c;
  c.Size = size;
  c.Values.assign(size[0] * size[1] * size[2], 0);
  // Varied values on each side, so that the repair values tell the walks apart.
  for (SizeValueType v = 0; v < c.Values.size(); ++v)
  {
    c.Values[v] = static_cast<int16_t>(-1 - static_cast<int>(v % 7));
  }
  const auto at = [&](SizeValueType x, SizeValueType y, SizeValueType z) -> int16_t & {
    return c.Values[x + size[0] * (y + size[1] * z)];
  };
  draw(at);
  c.Input = MakeImage<int16_t, 3>(c.Size, c.Values);
  c.Settings.IsoValue = 0.5;
  c.Settings.MaximumComponentSize = maximumSize;
  c.Settings.Side = side;
  return c;
}

/** The sweep of \a c with every slab thickness from one plane to the whole depth, at one and two
 * work units, against the reference. */
void
ExpectEverySlabThicknessMatches(const RandomCase<int16_t, 3> & c)
{
  RandomSource random(1);
  for (uint64_t slabPlanes = 1; slabPlanes <= c.Size[2]; ++slabPlanes)
  {
    for (const unsigned int workUnits : { 1u, 2u })
    {
      EXPECT_EQ(SweepDifferences(c, slabPlanes, workUnits, random), "");
    }
  }
}
} // namespace

TEST(SmallIsoComponentStreamingSweep, MatchesTheReferenceOn3DVolumes)
{
  CheckSweepOfRandomVolumes<uint8_t, 3>(1, 600);
}

TEST(SmallIsoComponentStreamingSweep, MatchesTheReferenceOn2DVolumes)
{
  CheckSweepOfRandomVolumes<float, 2>(5001, 600);
}

TEST(SmallIsoComponentStreamingSweep, MatchesTheReferenceOnLargerInt16Volumes)
{
  CheckSweepOfRandomVolumes<int16_t, 3>(7001, 60, true);
}

TEST(SmallIsoComponentStreamingSweep, HoldsABoundedWindowOnTallNoise)
{
  CheckSweepOfTallNoise(1, 300);
}

TEST(SmallIsoComponentStreamingSweep, MatchesTheReferenceOnDoubleVolumesWithNaN)
{
  CheckSweepOfRandomVolumes<double, 3>(9001, 400);
}

TEST(SmallIsoComponentStreamingSweep, ComponentsSpanningExactlyKAndKPlusOnePlanes)
{
  constexpr SizeValueType k = 4;
  const auto              c = NamedCase({ 4, 4, 2 * k + 4 }, k, SideEnum::Above, [&](auto at) {
    for (SizeValueType z = 1; z <= k; ++z)
    {
      at(0, 0, z) = static_cast<int16_t>(10 + z); // K voxels over K planes: removed
    }
    for (SizeValueType z = 2; z <= k + 2; ++z)
    {
      at(3, 3, z) = 20; // K + 1 voxels over K + 1 planes: kept
    }
  });
  const auto              expected = Reference::Run<int16_t>(c.Input.GetPointer(), c.Settings);
  EXPECT_EQ(expected.Above.RemovedComponents, 1u);
  EXPECT_EQ(expected.Above.Components, 2u);
  ExpectEverySlabThicknessMatches(c);
}

TEST(SmallIsoComponentStreamingSweep, BubbleInASpeckAcrossSlabBoundaries)
{
  // A 3 x 3 x 3 speck around a one-voxel bubble, planes 2 to 4: with Side Both the speck goes and
  // takes its bubble with it, across whichever slab boundaries fall inside it.
  const auto c = NamedCase({ 5, 5, 8 }, 30, SideEnum::Both, [](auto at) {
    for (SizeValueType z = 2; z <= 4; ++z)
      for (SizeValueType y = 1; y <= 3; ++y)
        for (SizeValueType x = 1; x <= 3; ++x)
        {
          at(x, y, z) = static_cast<int16_t>(x + y + z);
        }
    at(2, 2, 3) = -50;
  });
  const auto expected = Reference::Run<int16_t>(c.Input.GetPointer(), c.Settings);
  EXPECT_EQ(expected.Above.RemovedComponents, 1u);
  // The below pass sees the bubble joined to the background through the flipped speck.
  EXPECT_EQ(expected.Below.Components, 1u);
  EXPECT_EQ(expected.ModifiedVoxels, 26u);
  ExpectEverySlabThicknessMatches(c);
}

TEST(SmallIsoComponentStreamingSweep, WalksThatCrossAWholeComponentOfKPlanes)
{
  // A column of K voxels along the planes: the walk from its first voxel meets the other side K
  // planes away, the farthest a walk of a removed component can go.
  constexpr SizeValueType k = 5;
  const auto              c = NamedCase({ 3, 3, k + 3 }, k, SideEnum::Above, [&](auto at) {
    for (SizeValueType z = 1; z <= k; ++z)
    {
      at(1, 1, z) = 7;
    }
    at(1, 1, 0) = -300;
    at(1, 1, k + 1) = -100;
  });
  const auto              expected = Reference::Run<int16_t>(c.Input.GetPointer(), c.Settings);
  EXPECT_EQ(expected.Above.RemovedComponents, 1u);
  ExpectEverySlabThicknessMatches(c);
}

TEST(SmallIsoComponentStreamingSweep, ComponentsThatCloseOnlyAtTheLastPlane)
{
  // A small component that ends in the last plane, beside an object that spans every plane: neither
  // is complete before the sweep reaches the end.
  constexpr SizeValueType k = 6;
  const auto              c = NamedCase({ 4, 4, 9 }, k, SideEnum::Both, [&](auto at) {
    for (SizeValueType z = 0; z < 9; ++z)
    {
      at(3, 0, z) = 40;
      at(3, 1, z) = 40;
      at(2, 1, z) = 41;
    }
    for (SizeValueType z = 4; z < 9; ++z)
    {
      at(0, 3, z) = 9;
    }
  });
  const auto              expected = Reference::Run<int16_t>(c.Input.GetPointer(), c.Settings);
  EXPECT_EQ(expected.Above.RemovedComponents, 1u);
  EXPECT_EQ(expected.Above.Components, 2u);
  EXPECT_EQ(expected.ModifiedVoxels, 5u);
  ExpectEverySlabThicknessMatches(c);
}
