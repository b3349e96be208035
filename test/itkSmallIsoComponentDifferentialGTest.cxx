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

// The filter against the brute-force reference on seeded random volumes: every output
// bit, every mask voxel and every statistic must agree, for 1, 2 and 7 work units.

#include "itkSmallIsoComponentDifferential.h"
#include <algorithm>
#include <limits>

using itk::SmallIsoComponentTest::ExpectFilterMatchesReference;

TEST(SmallIsoComponentDifferential, UInt8Image2D)
{
  ExpectFilterMatchesReference<uint8_t, uint8_t, 2>(1000, 260);
}

TEST(SmallIsoComponentDifferential, UInt8Image3D)
{
  ExpectFilterMatchesReference<uint8_t, uint8_t, 3>(2000, 160);
}

TEST(SmallIsoComponentDifferential, Int16Image2D)
{
  ExpectFilterMatchesReference<int16_t, int16_t, 2>(3000, 260);
}

TEST(SmallIsoComponentDifferential, Int16Image3D)
{
  ExpectFilterMatchesReference<int16_t, int16_t, 3>(4000, 160);
}

TEST(SmallIsoComponentDifferential, FloatImageWithNaN2D)
{
  ExpectFilterMatchesReference<float, float, 2>(5000, 260);
}

TEST(SmallIsoComponentDifferential, FloatImageWithNaN3D)
{
  ExpectFilterMatchesReference<float, float, 3>(6000, 160);
}

TEST(SmallIsoComponentDifferential, UInt8ToFloat2D)
{
  ExpectFilterMatchesReference<uint8_t, float, 2>(7000, 260);
}

TEST(SmallIsoComponentDifferential, UInt8ToFloat3D)
{
  ExpectFilterMatchesReference<uint8_t, float, 3>(8000, 160);
}

TEST(SmallIsoComponentDifferential, Int16ToFloat2D)
{
  ExpectFilterMatchesReference<int16_t, float, 2>(9000, 260);
}

TEST(SmallIsoComponentDifferential, Int16ToFloat3D)
{
  ExpectFilterMatchesReference<int16_t, float, 3>(10000, 160);
}

TEST(SmallIsoComponentDifferential, LargeUInt8Image3D)
{
  // Every extent 20 to 40: many slabs per work unit count, long walks, big components.
  ExpectFilterMatchesReference<uint8_t, uint8_t, 3>(11000, 40, true);
}

TEST(SmallIsoComponentDifferential, LargeFloatImageWithNaN3D)
{
  ExpectFilterMatchesReference<float, float, 3>(12000, 40, true);
}

TEST(SmallIsoComponentDifferential, ManyRemovedRunsAndStreamedOutput3D)
{
  // White noise around the isovalue in a 128x128x128 uint8 volume: thousands of removed
  // runs on each side, so the repair is shared among the work units, and 4 MiB of output
  // and mask, so the filter writes them with streaming stores. Both sides, both
  // connectivities, every bit against the reference at 1, 2 and 7 work units.
  using namespace itk::SmallIsoComponentTest;
  using ImageType = itk::Image<uint8_t, 3>;
  const std::array<itk::SizeValueType, 3> extent{ 128, 128, 128 };
  for (const bool fullyConnected : { false, true })
  {
    RandomSource         random(fullyConnected ? 13001u : 13002u);
    std::vector<uint8_t> values(extent[0] * extent[1] * extent[2]);
    for (itk::SizeValueType i = 0; i < values.size(); ++i)
    {
      // The lower half mostly above with a sprinkle below (bubbles), the upper half the
      // other way round (specks).
      const double aboveShare = i < values.size() / 2 ? 0.88 : 0.12;
      values[i] = static_cast<uint8_t>(random.Chance(aboveShare) ? random.Between(150, 255) : random.Between(0, 120));
    }
    const auto input = MakeImage<uint8_t, 3>(extent, values);
    Parameters settings;
    settings.IsoValue = 128;
    settings.MaximumComponentSize = 20;
    settings.Side = SideEnum::Both;
    settings.FullyConnected = fullyConnected;
    const auto expected = Reference::Run<uint8_t>(input.GetPointer(), settings);
    ASSERT_GT(expected.Above.RemovedComponents, 4 * itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShare)
      << "the volume no longer exercises a shared repair";
    ASSERT_GT(expected.Below.RemovedComponents, 4 * itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShare);
    for (const unsigned int workUnits : { 1u, 2u, 7u })
    {
      const auto filter = RunFilter<ImageType>(input, settings, workUnits);
      EXPECT_EQ(DifferencesFromReference(filter.GetPointer(), expected, settings.MaximumComponentSize), "")
        << "fullyConnected=" << fullyConnected << " workUnits=" << workUnits;
    }

    // In place: the output and the input are one buffer, which the above pass reads.
    const auto      copy = MakeImage<uint8_t, 3>(extent, values);
    const uint8_t * buffer = copy->GetBufferPointer();
    const auto      inPlace = RunFilter<ImageType>(copy, settings, 2, true);
    ASSERT_EQ(inPlace->GetOutput()->GetBufferPointer(), buffer) << "the filter did not run in place";
    EXPECT_EQ(DifferencesFromReference(inPlace.GetPointer(), expected, settings.MaximumComponentSize), "")
      << "fullyConnected=" << fullyConnected << " in place";
    // In place without a mask: the filter writes nothing but the removed voxels.
    const auto      noMaskCopy = MakeImage<uint8_t, 3>(extent, values);
    const uint8_t * noMaskBuffer = noMaskCopy->GetBufferPointer();
    const auto      inPlaceNoMask = RunFilter<ImageType>(noMaskCopy, settings, 2, true, false);
    ASSERT_EQ(inPlaceNoMask->GetOutput()->GetBufferPointer(), noMaskBuffer) << "the filter did not run in place";
    EXPECT_EQ(DifferencesFromReference(inPlaceNoMask.GetPointer(), expected, settings.MaximumComponentSize), "")
      << "fullyConnected=" << fullyConnected << " in place without a mask";

    // A second update of the same filter writes over the first one's output and mask; a
    // third without the mask gives its buffer back.
    const auto again = RunFilter<ImageType>(input, settings, 2);
    Parameters other = settings;
    other.IsoValue = 100;
    again->SetIsoValue(other.IsoValue);
    again->Update();
    const auto expectedOther = Reference::Run<uint8_t>(input.GetPointer(), other);
    EXPECT_EQ(DifferencesFromReference(again.GetPointer(), expectedOther, other.MaximumComponentSize), "")
      << "fullyConnected=" << fullyConnected << " second update";
    again->GenerateRemovedMaskOff();
    again->Update();
    EXPECT_EQ(DifferencesFromReference(again.GetPointer(), expectedOther, other.MaximumComponentSize), "")
      << "fullyConnected=" << fullyConnected << " third update, without the mask";
    EXPECT_EQ(again->GetRemovedMask()->GetPixelContainer()->Capacity(), 0u) << "the mask's buffer was kept";

    // The run arrays are kept for the next update, and given back when asked.
    const itk::SizeValueType kept = again->GetWorkingMemoryInBytes();
    EXPECT_GE(kept, 8 * (values.size() / 10)) << "the run arrays were not kept after the update";
    again->ReleaseWorkingMemory();
    EXPECT_EQ(again->GetWorkingMemoryInBytes(), 0u);
    again->SetIsoValue(settings.IsoValue);
    again->Update();
    EXPECT_EQ(DifferencesFromReference(again.GetPointer(), expected, settings.MaximumComponentSize), "")
      << "fullyConnected=" << fullyConnected << " after the working memory was given back";
    const itk::SizeValueType keptAgain = again->GetWorkingMemoryInBytes();
    EXPECT_GT(keptAgain, 0u);
    again->Modified();
    again->Update();
    EXPECT_EQ(again->GetWorkingMemoryInBytes(), keptAgain) << "a second update of the same image took more memory";
  }
}

TEST(SmallIsoComponentDifferential, DenseNoiseWithSharedNumbering3D)
{
  // Each voxel of a 192x128x128 uint8 volume above or below the isovalue with probability
  // 1/2: about 1.6 million runs, enough for the numbering to be shared between two work
  // units, with the output and the mask written in the moments it leaves free. Both sides
  // and Side Above, every bit against the reference at 1, 2 and 3 work units, in a first
  // update and a second.
  using namespace itk::SmallIsoComponentTest;
  using ImageType = itk::Image<uint8_t, 3>;
  const std::array<itk::SizeValueType, 3> extent{ 192, 128, 128 };
  RandomSource                            random(14001u);
  std::vector<uint8_t>                    values(extent[0] * extent[1] * extent[2]);
  for (auto & value : values)
  {
    value = static_cast<uint8_t>(random.Chance(0.5) ? random.Between(129, 255) : random.Between(0, 127));
  }
  itk::SizeValueType runs = 0;
  for (itk::SizeValueType i = 0; i < values.size(); ++i)
  {
    runs += (i % extent[0] == 0 || (values[i] > 128) != (values[i - 1] > 128)) ? 1 : 0;
  }
  ASSERT_GE(runs, itk::SmallIsoComponentDetail::Tuning::MinimumRunsToShareNumbering)
    << "the volume no longer has the runs to share the numbering";
  ASSERT_LE(2 * values.size(), itk::SmallIsoComponentDetail::Tuning::FillBytesPerRunToShareNumbering * runs)
    << "the output and the mask would be written beside a serial numbering";
  const auto input = MakeImage<uint8_t, 3>(extent, values);
  for (const auto side : { SideEnum::Both, SideEnum::Above })
  {
    Parameters settings;
    settings.IsoValue = 128;
    settings.MaximumComponentSize = 20;
    settings.Side = side;
    const auto expected = Reference::Run<uint8_t>(input.GetPointer(), settings);
    for (const unsigned int workUnits : { 1u, 2u, 3u })
    {
      const auto filter = RunFilter<ImageType>(input, settings, workUnits);
      EXPECT_EQ(DifferencesFromReference(filter.GetPointer(), expected, settings.MaximumComponentSize), "")
        << "side " << side << " workUnits=" << workUnits;
      // Updated again, the filter has scratch memory from the first update, in which the
      // first stage of a shared numbering helps the second with Side Both.
      filter->Modified();
      filter->Update();
      EXPECT_EQ(DifferencesFromReference(filter.GetPointer(), expected, settings.MaximumComponentSize), "")
        << "side " << side << " workUnits=" << workUnits << ", second update";
    }
  }
}

#if defined(__linux__)
#  include <sys/resource.h>

TEST(SmallIsoComponentDifferential, RepeatedUpdateTakesNoFreshMemory)
{
  // A dense random volume: a removed component in every few voxels, so that each pass's
  // arrays (flags per component, removed runs, new values, the grouping) are megabytes, the
  // size the allocator maps afresh and gives back. Updated again on the same image, the
  // filter reuses what it kept: the process takes no page fault while it runs, at 1 and 2
  // work units, and the output stays the reference's. The process's count also takes in
  // what the system does to it now and then (a page of code mapped again, one fault in some
  // full runs of the tests on a busy machine), so of three such updates one must take none:
  // memory taken afresh by the filter would fault in every one.
  using namespace itk::SmallIsoComponentTest;
  using ImageType = itk::Image<uint8_t, 3>;
  const std::array<itk::SizeValueType, 3> extent{ 160, 160, 160 };
  RandomSource                            random(13101u);
  std::vector<uint8_t>                    values(extent[0] * extent[1] * extent[2]);
  for (auto & value : values)
  {
    value = random.Chance(0.5) ? 255 : 0;
  }
  const auto input = MakeImage<uint8_t, 3>(extent, values);
  Parameters settings;
  settings.IsoValue = 127.5;
  settings.MaximumComponentSize = 20;
  settings.Side = SideEnum::Both;
  const auto expected = Reference::Run<uint8_t>(input.GetPointer(), settings);
  const auto minorFaults = [] {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_minflt;
  };
  for (const unsigned int workUnits : { 1u, 2u })
  {
    const auto filter = RunFilter<ImageType>(input, settings, workUnits);
    filter->Modified();
    filter->Update();
    long fewest = std::numeric_limits<long>::max();
    for (int update = 0; update < 3; ++update)
    {
      filter->Modified();
      const long before = minorFaults();
      filter->Update();
      fewest = std::min(fewest, minorFaults() - before);
    }
    EXPECT_EQ(fewest, 0) << "work units " << workUnits << ": every update like the last one took fresh memory";
    EXPECT_EQ(DifferencesFromReference(filter.GetPointer(), expected, settings.MaximumComponentSize), "")
      << "work units " << workUnits;
  }
}
#endif
