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

// Properties the filter's result must have whatever its exact values, checked on the
// same kind of seeded random volumes as the differential test (other seeds).

#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"

namespace
{
using namespace itk::SmallIsoComponentTest;
using SizeValueType = itk::SizeValueType;

constexpr unsigned int MaximumReportedFailures = 3;

/** Calls check(randomCase, filter) for each volume; check returns an empty string when
 * the property holds, else what is wrong. The filter runs with one work unit. */
template <typename TInputPixel, typename TOutputPixel, unsigned int VDimension, typename TCheck>
void
ForEachRandomCase(uint32_t firstSeed, unsigned int numberOfVolumes, TCheck check, bool forceSideBoth = false)
{
  using InputImageType = itk::Image<TInputPixel, VDimension>;
  using OutputImageType = itk::Image<TOutputPixel, VDimension>;
  unsigned int failures = 0;
  for (uint32_t seed = firstSeed; seed < firstSeed + numberOfVolumes && failures < MaximumReportedFailures; ++seed)
  {
    auto c = MakeRandomCase<TInputPixel, TOutputPixel, VDimension>(seed);
    if (forceSideBoth)
    {
      c.Settings.Side = SideEnum::Both;
      c.Description += " (side forced to Both)";
    }
    const auto        filter = RunFilter<InputImageType, OutputImageType>(c.Input, c.Settings);
    const std::string problem = check(c, filter.GetPointer());
    if (!problem.empty())
    {
      ADD_FAILURE() << c.Description << ": " << problem;
      ++failures;
    }
  }
}

/** Runs a check on 2D and 3D volumes of uint8, float with NaN, and int16 converted to float. */
template <typename TCheck>
void
ForAllKindsOfVolume(uint32_t firstSeed, TCheck check, bool forceSideBoth = false)
{
  ForEachRandomCase<uint8_t, uint8_t, 2>(firstSeed, 120, check, forceSideBoth);
  ForEachRandomCase<uint8_t, uint8_t, 3>(firstSeed + 1000, 80, check, forceSideBoth);
  ForEachRandomCase<float, float, 2>(firstSeed + 2000, 120, check, forceSideBoth);
  ForEachRandomCase<float, float, 3>(firstSeed + 3000, 80, check, forceSideBoth);
  ForEachRandomCase<int16_t, float, 3>(firstSeed + 4000, 80, check, forceSideBoth);
}

template <typename TPixel>
bool
IsAbove(TPixel value, double isoValue)
{
  return Reference::IsAbove(value, isoValue);
}

/** The input as the filter sees it: converted to the output pixel type. */
template <typename TCase, typename TFilter>
std::vector<typename TFilter::OutputPixelType>
ConvertedInput(const TCase & c, const TFilter *)
{
  return std::vector<typename TFilter::OutputPixelType>(c.Values.begin(), c.Values.end());
}
} // namespace

TEST(SmallIsoComponentInvariants, UnmaskedVoxelsKeepTheirBits)
{
  ForAllKindsOfVolume(100000, [](const auto & c, auto * filter) -> std::string {
    const auto   converted = ConvertedInput(c, filter);
    const auto * output = filter->GetOutput()->GetBufferPointer();
    const auto * mask = filter->GetRemovedMask()->GetBufferPointer();
    for (SizeValueType v = 0; v < converted.size(); ++v)
    {
      if (mask[v] == 0 && !SameBits(output[v], converted[v]))
      {
        return "voxel " + std::to_string(v) + " has mask 0 but changed from " + PixelToString(converted[v]) + " to " +
               PixelToString(output[v]);
      }
    }
    return {};
  });
}

TEST(SmallIsoComponentInvariants, RemovedVoxelsEndOnTheOtherSide)
{
  // Mask 1: above in the input, below (and a number) in the output, only when Side is not
  // Below. Mask 2: above in the output, only when Side is not Above; a mask-2 voxel that
  // was above in the input was moved twice, which only Side Both does.
  ForAllKindsOfVolume(110000, [](const auto & c, auto * filter) -> std::string {
    const auto   converted = ConvertedInput(c, filter);
    const auto * output = filter->GetOutput()->GetBufferPointer();
    const auto * mask = filter->GetRemovedMask()->GetBufferPointer();
    const double iso = c.Settings.IsoValue;
    for (SizeValueType v = 0; v < converted.size(); ++v)
    {
      const auto where = [&]() {
        return "voxel " + std::to_string(v) + " (input " + PixelToString(converted[v]) + ", output " +
               PixelToString(output[v]) + ", mask " + std::to_string(mask[v]) + ")";
      };
      switch (mask[v])
      {
        case 0:
          break;
        case 1:
          if (c.Settings.Side == SideEnum::Below || !IsAbove(converted[v], iso) || IsAbove(output[v], iso) ||
              Reference::IsNaN(output[v]))
          {
            return where() + " was not moved from above to below by the above pass";
          }
          break;
        case 2:
          if (c.Settings.Side == SideEnum::Above || !IsAbove(output[v], iso) ||
              (IsAbove(converted[v], iso) && c.Settings.Side != SideEnum::Both))
          {
            return where() + " was not moved to above by the below pass";
          }
          break;
        default:
          return where() + " has a mask value other than 0, 1, 2";
      }
    }
    return {};
  });
}

TEST(SmallIsoComponentInvariants, CountsAgreeWithMaskAndHistograms)
{
  ForAllKindsOfVolume(120000, [](const auto & c, auto * filter) -> std::string {
    const auto          converted = ConvertedInput(c, filter);
    const auto *        mask = filter->GetRemovedMask()->GetBufferPointer();
    const double        iso = c.Settings.IsoValue;
    const SizeValueType K = c.Settings.MaximumComponentSize;
    SizeValueType       inputAbove = 0;
    SizeValueType       masked = 0;
    SizeValueType       removedByAbovePass = 0;
    SizeValueType       removedByBelowPass = 0;
    for (SizeValueType v = 0; v < converted.size(); ++v)
    {
      const bool above = IsAbove(converted[v], iso);
      inputAbove += above ? 1 : 0;
      masked += mask[v] != 0 ? 1 : 0;
      removedByAbovePass += mask[v] == 1 || (mask[v] == 2 && above) ? 1 : 0;
      removedByBelowPass += mask[v] == 2 ? 1 : 0;
    }
    std::ostringstream problems;
    const auto         expectEqual = [&problems](const char * what, SizeValueType expected, SizeValueType got) {
      if (expected != got)
      {
        problems << what << ": expected " << expected << ", got " << got << "; ";
      }
    };
    expectEqual("modified voxels = nonzero mask voxels", masked, filter->GetNumberOfModifiedVoxels());
    expectEqual("removed above voxels", removedByAbovePass, filter->GetNumberOfRemovedVoxels(SideEnum::Above));
    expectEqual("removed below voxels", removedByBelowPass, filter->GetNumberOfRemovedVoxels(SideEnum::Below));

    // The histograms cover each side's voxels; removals follow from them and K.
    const SizeValueType belowSeen =
      converted.size() - inputAbove +
      (c.Settings.Side == SideEnum::Both ? filter->GetNumberOfRemovedVoxels(SideEnum::Above) : 0);
    const std::array<std::pair<SideEnum, SizeValueType>, 2> sides{ { { SideEnum::Above, inputAbove },
                                                                     { SideEnum::Below, belowSeen } } };
    for (const auto & side : sides)
    {
      typename std::remove_pointer<decltype(filter)>::type::OutputPixelType otherSide{};
      const bool    processed = c.Settings.Side == SideEnum::Both || c.Settings.Side == side.first;
      const bool    removable = side.first == SideEnum::Above ? Reference::LargestValueBelow(iso, otherSide)
                                                              : Reference::SmallestValueNotBelow(iso, otherSide);
      SizeValueType voxels = 0;
      SizeValueType components = 0;
      SizeValueType small = 0;
      SizeValueType smallVoxels = 0;
      for (const auto & entry : filter->GetComponentSizeHistogram(side.first))
      {
        voxels += entry.first * entry.second;
        components += entry.second;
        small += entry.first <= K ? entry.second : 0;
        smallVoxels += entry.first <= K ? entry.first * entry.second : 0;
      }
      const bool removes = processed && removable;
      expectEqual("voxels in the histogram", side.second, voxels);
      expectEqual("components in the histogram", filter->GetNumberOfComponents(side.first), components);
      expectEqual(
        "removed components from the histogram", removes ? small : 0, filter->GetNumberOfRemovedComponents(side.first));
      expectEqual(
        "removed voxels from the histogram", removes ? smallVoxels : 0, filter->GetNumberOfRemovedVoxels(side.first));
    }
    return problems.str();
  });
}

TEST(SmallIsoComponentInvariants, BothLeavesNoSmallComponentUnlessUnrepairable)
{
  unsigned int checked = 0;
  ForAllKindsOfVolume(
    130000,
    [&checked](const auto & c, auto * filter) -> std::string {
      if (filter->GetNumberOfUnrepairableVoxels() > 0)
      {
        return {};
      }
      ++checked;
      const auto counts =
        Reference::CountComponents(filter->GetOutput(), c.Settings.IsoValue, c.Settings.FullyConnected);
      const SizeValueType K = c.Settings.MaximumComponentSize;
      if (!counts.Above.Histogram.empty() && counts.Above.Histogram.begin()->first <= K)
      {
        return "the output has an above component of " + std::to_string(counts.Above.Histogram.begin()->first) +
               " voxels; histogram " + HistogramToString(counts.Above.Histogram);
      }
      if (!counts.Below.Histogram.empty() && counts.Below.Histogram.begin()->first <= K)
      {
        return "the output has a below component of " + std::to_string(counts.Below.Histogram.begin()->first) +
               " voxels; histogram " + HistogramToString(counts.Below.Histogram);
      }
      return {};
    },
    true);
  EXPECT_GT(checked, 300u);
}

TEST(SmallIsoComponentInvariants, IdempotentWhenEverythingWasRepaired)
{
  unsigned int checked = 0;
  ForAllKindsOfVolume(140000, [&checked](const auto & c, auto * filter) -> std::string {
    if (filter->GetNumberOfUnrepairableVoxels() > 0)
    {
      return {};
    }
    ++checked;
    using FilterType = typename std::remove_pointer<decltype(filter)>::type;
    using OutputImageType = typename FilterType::OutputImageType;
    const auto          again = RunFilter<OutputImageType, OutputImageType>(filter->GetOutput(), c.Settings);
    const SizeValueType changed = CountDifferentVoxels(filter->GetOutput(), again->GetOutput());
    if (changed > 0 || again->GetNumberOfModifiedVoxels() > 0 ||
        again->GetNumberOfRemovedComponents(SideEnum::Above) > 0 ||
        again->GetNumberOfRemovedComponents(SideEnum::Below) > 0)
    {
      return "a second run changed " + std::to_string(changed) + " voxels and reported " +
             std::to_string(again->GetNumberOfModifiedVoxels()) + " modified";
    }
    return {};
  });
  EXPECT_GT(checked, 300u);
}

TEST(SmallIsoComponentInvariants, OutputIndependentOfWorkUnits)
{
  ForAllKindsOfVolume(150000, [](const auto & c, auto * filter) -> std::string {
    using FilterType = typename std::remove_pointer<decltype(filter)>::type;
    using InputImageType = typename FilterType::InputImageType;
    using OutputImageType = typename FilterType::OutputImageType;
    for (const unsigned int workUnits : { 2u, 3u, 7u, 16u })
    {
      const auto other = RunFilter<InputImageType, OutputImageType>(c.Input, c.Settings, workUnits);
      const auto n = other->GetOutput()->GetBufferedRegion().GetNumberOfPixels();
      const bool sameMask = std::equal(filter->GetRemovedMask()->GetBufferPointer(),
                                       filter->GetRemovedMask()->GetBufferPointer() + n,
                                       other->GetRemovedMask()->GetBufferPointer());
      bool       sameStatistics = other->GetNumberOfModifiedVoxels() == filter->GetNumberOfModifiedVoxels() &&
                            other->GetNumberOfUnrepairableVoxels() == filter->GetNumberOfUnrepairableVoxels();
      for (const SideEnum side : { SideEnum::Above, SideEnum::Below })
      {
        sameStatistics = sameStatistics && other->GetNumberOfComponents(side) == filter->GetNumberOfComponents(side) &&
                         other->GetNumberOfRemovedComponents(side) == filter->GetNumberOfRemovedComponents(side) &&
                         other->GetNumberOfRemovedVoxels(side) == filter->GetNumberOfRemovedVoxels(side) &&
                         other->GetComponentSizeHistogram(side) == filter->GetComponentSizeHistogram(side);
      }
      const SizeValueType changed = CountDifferentVoxels(filter->GetOutput(), other->GetOutput());
      if (changed > 0 || !sameMask || !sameStatistics)
      {
        return std::to_string(workUnits) + " work units differ from 1: " + std::to_string(changed) +
               " output voxels, mask " + (sameMask ? "same" : "different") + ", statistics " +
               (sameStatistics ? "same" : "different");
      }
    }
    return {};
  });
}
