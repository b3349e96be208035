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
#ifndef itkSmallIsoComponentDifferential_h
#define itkSmallIsoComponentDifferential_h

#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"
#include <iostream>

namespace itk
{
namespace SmallIsoComponentTest
{
/** Stop a test after this many failing volumes: the first ones tell the story. */
constexpr unsigned int MaximumReportedFailures = 3;

/** Compares the filter with the reference on \a numberOfVolumes random volumes from
 * \a firstSeed on: every output bit, every mask voxel and every statistic, for 1, 2 and 7
 * work units (7 without a mask: the statistics must not depend on it), and swept in slabs
 * of a thickness that varies with the seed (2-D and 3-D). */
template <typename TInputPixel, typename TOutputPixel, unsigned int VDimension>
void
ExpectFilterMatchesReference(uint32_t firstSeed, unsigned int numberOfVolumes, bool large = false)
{
  using InputImageType = Image<TInputPixel, VDimension>;
  using OutputImageType = Image<TOutputPixel, VDimension>;

  // What the volumes exercised, so that a generator that stopped producing removals
  // cannot leave the comparison vacuous.
  unsigned int volumes = 0;
  unsigned int withRemovedAbove = 0;
  unsigned int withRemovedBelow = 0;
  unsigned int withUnrepairable = 0;
  unsigned int failures = 0;
  for (uint32_t seed = firstSeed; seed < firstSeed + numberOfVolumes && failures < MaximumReportedFailures; ++seed)
  {
    const auto c = MakeRandomCase<TInputPixel, TOutputPixel, VDimension>(seed, large);
    const auto expected = Reference::Run<TOutputPixel>(c.Input.GetPointer(), c.Settings);
    ++volumes;
    withRemovedAbove += expected.Above.RemovedComponents > 0 ? 1 : 0;
    withRemovedBelow += expected.Below.RemovedComponents > 0 ? 1 : 0;
    withUnrepairable += expected.UnrepairableVoxels > 0 ? 1 : 0;
    for (const unsigned int workUnits : { 1u, 2u, 7u })
    {
      const auto filter =
        RunFilter<InputImageType, OutputImageType>(c.Input, c.Settings, workUnits, false, workUnits != 7);
      const std::string differences =
        DifferencesFromReference(filter.GetPointer(), expected, c.Settings.MaximumComponentSize);
      if (!differences.empty())
      {
        ADD_FAILURE() << c.Description << " workUnits=" << workUnits << ":" << differences;
        ++failures;
        break;
      }
    }
    // The sweep in slabs (2-D and 3-D images): slabs of 1 plane to the whole depth, one to three
    // work units (with two or more, the labelling thread; with three, it shares its work), in place
    // every third volume when the pixel types allow.
    const SizeValueType depth = c.Input->GetLargestPossibleRegion().GetSize(VDimension - 1);
    const SizeValueType slab = 1 + seed % (depth + 1);
    const unsigned int  slabWorkUnits = 1 + (seed / 3) % 3;
    const bool          inPlace = seed % 3 == 0;
    // In place, the input's buffer becomes the output's: the filter gets a copy.
    auto input = InputImageType::New();
    input->SetRegions(c.Input->GetLargestPossibleRegion());
    input->Allocate();
    std::copy(c.Input->GetBufferPointer(),
              c.Input->GetBufferPointer() + c.Input->GetLargestPossibleRegion().GetNumberOfPixels(),
              input->GetBufferPointer());
    const auto swept = RunFilter<InputImageType, OutputImageType>(
      input.GetPointer(), c.Settings, slabWorkUnits, inPlace, seed % 4 != 1, slab);
    if (swept->GetSweptInSlabs() != (VDimension == 2 || VDimension == 3))
    {
      ADD_FAILURE() << c.Description << ": swept in slabs " << swept->GetSweptInSlabs() << " with slab thickness "
                    << slab;
      ++failures;
      continue;
    }
    const std::string differences =
      DifferencesFromReference(swept.GetPointer(), expected, c.Settings.MaximumComponentSize);
    if (!differences.empty())
    {
      ADD_FAILURE() << c.Description << " in slabs of " << slab << " planes, workUnits=" << slabWorkUnits
                    << (inPlace ? ", in place" : "") << ":" << differences;
      ++failures;
    }
  }
  std::cout << volumes << " volumes, " << withRemovedAbove << " with removed above components, " << withRemovedBelow
            << " with removed below components, " << withUnrepairable << " with unrepairable voxels" << std::endl;
  if (failures == 0)
  {
    EXPECT_GT(withRemovedAbove, numberOfVolumes / 8);
    EXPECT_GT(withRemovedBelow, numberOfVolumes / 8);
    EXPECT_GT(withUnrepairable, 0u);
  }
}
} // namespace SmallIsoComponentTest
} // end namespace itk

#endif
