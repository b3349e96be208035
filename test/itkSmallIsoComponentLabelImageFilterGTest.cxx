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
// SmallIsoComponentLabelImageFilter held to the brute-force reference of the label-map rule,
// voxel for voxel, over seeded random label maps of every kind the filter takes.

#include "itkSmallIsoComponentLabelImageFilter.h"
#include "itkSmallIsoComponentLabelReference.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkExtractImageFilter.h"
#include "itkStreamingImageFilter.h"
#include "gtest/gtest.h"
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <string>

namespace
{
using namespace itk;
using SmallIsoComponentTest::RandomSource;
namespace LabelReference = SmallIsoComponentLabelReference;
using SelectionEnum = SmallIsoComponentLabelEnums::Selection;

/** The label of each voxel drawn from a blurred field cut into bands, with specks of random
 * labels: components of every size, islands in islands, holes. */
template <typename TLabel, unsigned int VDimension>
std::vector<TLabel>
DrawLabels(RandomSource & random, const std::array<SizeValueType, VDimension> & size, const std::vector<TLabel> & ids)
{
  const SmallIsoComponentReference::Grid<VDimension> grid(size, false);
  std::vector<double>                                field(grid.NumberOfVoxels());
  for (double & value : field)
  {
    value = random.Uniform();
  }
  SmallIsoComponentTest::Detail::Blur(grid, field, static_cast<unsigned int>(random.Between(0, 3)));
  double low = 1.0;
  double high = 0.0;
  for (const double value : field)
  {
    low = std::min(low, value);
    high = std::max(high, value);
  }
  const double        speckles = random.Pick(std::array<double, 4>{ 0.0, 0.01, 0.05, 0.2 });
  std::vector<TLabel> labels(field.size());
  for (SizeValueType v = 0; v < field.size(); ++v)
  {
    const double band = high > low ? (field[v] - low) / (high - low) : 0.0;
    const auto   index = std::min<SizeValueType>(ids.size() - 1, static_cast<SizeValueType>(band * ids.size()));
    labels[v] = random.Chance(speckles) ? ids[random.Bits() % ids.size()] : ids[index];
  }
  return labels;
}

/** Label ids of \a TLabel: small ones, sparse ones near the type's ends, negative ones. */
template <typename TLabel>
std::vector<TLabel>
DrawIds(RandomSource & random)
{
  const auto          count = static_cast<SizeValueType>(random.Between(2, 6));
  std::vector<TLabel> ids;
  const bool          sparse = random.Chance(0.5);
  while (ids.size() < count)
  {
    const auto small = static_cast<TLabel>(random.Between(0, 9));
    TLabel     far = static_cast<TLabel>(1000000 + random.Between(0, 9));
    TLabel     low = static_cast<TLabel>(-1000000 - random.Between(0, 9));
    if constexpr (std::is_integral<TLabel>::value)
    {
      far = static_cast<TLabel>(NumericTraits<TLabel>::max() - static_cast<TLabel>(random.Between(0, 9)));
      low = static_cast<TLabel>(NumericTraits<TLabel>::min() + static_cast<TLabel>(random.Between(0, 9)));
    }
    const TLabel id = !sparse ? small : random.Pick(std::array<TLabel, 3>{ small, far, low });
    if (std::find(ids.begin(), ids.end(), id) == ids.end())
    {
      ids.push_back(id);
    }
  }
  return ids;
}

/** How many of a test's random cases removed components and had unrepairable voxels: a generator
 * that stopped making them would leave the comparison vacuous. */
struct Coverage
{
  unsigned int Cases{ 0 };
  unsigned int WithRemovals{ 0 };
  unsigned int WithUnrepairable{ 0 };

  /** \a unrepairable: whether some cases must have unrepairable voxels (those need a component
   * that spans the image along every axis, which random 4-D maps rarely have). */
  void
  ExpectEnough(bool unrepairable = true) const
  {
    EXPECT_GE(WithRemovals, Cases / 2) << "of " << Cases << " cases";
    EXPECT_GE(WithUnrepairable, unrepairable ? 1u : 0u) << "of " << Cases << " cases";
  }
};

/** The extents ExpectSameAsReference() draws: small ones; lines of 65 to 300 voxels, longer than
 * the blocks the encoding compares at once for every label type, across few lines; or over 2,048
 * lines, which the work units share in parts. */
enum class Extents
{
  Small,
  LongLines,
  ManyLines
};

template <typename TLabel, unsigned int VDimension>
void
ExpectSameAsReference(uint32_t seed, Coverage & coverage, Extents extents = Extents::Small)
{
  RandomSource                          random(seed);
  std::array<SizeValueType, VDimension> size;
  for (SizeValueType & extent : size)
  {
    const bool first = &extent == &size[0];
    switch (extents)
    {
      case Extents::Small:
        extent = SmallIsoComponentTest::Detail::DrawExtent(random, VDimension);
        break;
      case Extents::LongLines:
        extent = static_cast<SizeValueType>(first ? random.Between(65, 300) : random.Between(1, 8));
        break;
      case Extents::ManyLines:
        extent = static_cast<SizeValueType>(first ? random.Between(1, 40) : random.Between(46, 60));
        break;
    }
  }
  const std::vector<TLabel> ids = DrawIds<TLabel>(random);
  const std::vector<TLabel> labels = DrawLabels<TLabel, VDimension>(random, size, ids);

  LabelReference::Parameters<TLabel> parameters;
  parameters.MaximumComponentSize = static_cast<SizeValueType>(random.Pick(std::array<int, 5>{ 0, 1, 2, 5, 20 }));
  if (random.Chance(0.3))
  {
    parameters.MaximumSizePerLabel[ids[random.Bits() % ids.size()]] = static_cast<SizeValueType>(random.Between(0, 30));
  }
  const auto selection = static_cast<SelectionEnum>(random.Between(0, 3));
  parameters.Selected = static_cast<LabelReference::Selection>(selection);
  parameters.Background = ids[random.Bits() % ids.size()];
  for (const TLabel id : ids)
  {
    if (parameters.SelectedLabels.empty() || random.Chance(0.4))
    {
      parameters.SelectedLabels.push_back(id);
    }
  }
  parameters.KeepLargest = random.Chance(0.3) ? static_cast<SizeValueType>(random.Between(1, 3)) : 0;
  parameters.FullyConnected = random.Chance(0.4);
  const auto expected = LabelReference::Run<TLabel, VDimension>(size, labels, parameters);

  using ImageType = Image<TLabel, VDimension>;
  auto filter = SmallIsoComponentLabelImageFilter<ImageType>::New();
  filter->SetInput(SmallIsoComponentTest::MakeImage<TLabel, VDimension>(size, labels));
  filter->SetMaximumComponentSize(parameters.MaximumComponentSize);
  filter->SetMaximumComponentSizes(
    std::map<TLabel, SizeValueType>(parameters.MaximumSizePerLabel.begin(), parameters.MaximumSizePerLabel.end()));
  filter->SetSelection(selection);
  filter->SetSelectedLabels(parameters.SelectedLabels);
  filter->SetBackgroundValue(parameters.Background);
  filter->SetKeepLargestComponents(parameters.KeepLargest);
  filter->SetFullyConnected(parameters.FullyConnected);
  filter->SetGenerateRemovedMask(true);
  filter->SetNumberOfWorkUnits(static_cast<unsigned int>(random.Between(1, 7)));
  filter->Update();
  ++coverage.Cases;
  coverage.WithRemovals += expected.ModifiedVoxels > 0;
  coverage.WithUnrepairable += expected.UnrepairableVoxels > 0;

  const std::string what = "seed " + std::to_string(seed);
  const TLabel *    output = filter->GetOutput()->GetBufferPointer();
  const uint8_t *   mask = filter->GetRemovedMask()->GetBufferPointer();
  SizeValueType     wrong = 0;
  for (SizeValueType v = 0; v < labels.size(); ++v)
  {
    wrong += !(output[v] == expected.Output[v]) || mask[v] != expected.Mask[v];
  }
  EXPECT_EQ(wrong, 0u) << what;
  EXPECT_EQ(filter->GetNumberOfModifiedVoxels(), expected.ModifiedVoxels) << what;
  EXPECT_EQ(filter->GetNumberOfUnrepairableVoxels(), expected.UnrepairableVoxels) << what;
  const auto & statistics = filter->GetLabelStatistics();
  ASSERT_EQ(statistics.size(), expected.Labels.size()) << what;
  for (const auto & entry : expected.Labels)
  {
    const auto found = statistics.find(entry.first);
    ASSERT_NE(found, statistics.end()) << what;
    EXPECT_EQ(found->second.Components, entry.second.Components) << what;
    EXPECT_EQ(found->second.RemovedComponents, entry.second.RemovedComponents) << what;
    EXPECT_EQ(found->second.RemovedVoxels, entry.second.RemovedVoxels) << what;
    EXPECT_EQ(found->second.GainedVoxels, entry.second.GainedVoxels) << what;
    EXPECT_EQ(found->second.Histogram, entry.second.Histogram) << what;
  }
}

TEST(SmallIsoComponentLabelImageFilter, MatchesReferenceIn2D)
{
  Coverage coverage;
  for (uint32_t seed = 1; seed <= 300; ++seed)
  {
    ExpectSameAsReference<uint8_t, 2>(seed, coverage);
  }
  coverage.ExpectEnough();
}

TEST(SmallIsoComponentLabelImageFilter, MatchesReferenceIn3D)
{
  Coverage coverage;
  for (uint32_t seed = 1001; seed <= 1200; ++seed)
  {
    ExpectSameAsReference<uint16_t, 3>(seed, coverage);
    ExpectSameAsReference<int16_t, 3>(seed + 500, coverage);
  }
  coverage.ExpectEnough();
}

TEST(SmallIsoComponentLabelImageFilter, MatchesReferenceIn4D)
{
  Coverage coverage;
  for (uint32_t seed = 2001; seed <= 2100; ++seed)
  {
    ExpectSameAsReference<uint32_t, 4>(seed, coverage);
  }
  coverage.ExpectEnough(false);
}

TEST(SmallIsoComponentLabelImageFilter, MatchesReferenceForWideAndFloatLabels)
{
  Coverage coverage;
  for (uint32_t seed = 3001; seed <= 3100; ++seed)
  {
    ExpectSameAsReference<int64_t, 3>(seed, coverage);
    ExpectSameAsReference<uint64_t, 2>(seed + 100, coverage);
    ExpectSameAsReference<float, 3>(seed + 200, coverage);
  }
  coverage.ExpectEnough();
}

TEST(SmallIsoComponentLabelImageFilter, MatchesReferenceOnLongLines)
{
  Coverage coverage;
  for (uint32_t seed = 4001; seed <= 4060; ++seed)
  {
    ExpectSameAsReference<uint8_t, 2>(seed, coverage, Extents::LongLines);
    ExpectSameAsReference<uint16_t, 3>(seed + 100, coverage, Extents::LongLines);
    ExpectSameAsReference<int64_t, 2>(seed + 200, coverage, Extents::LongLines);
    ExpectSameAsReference<float, 3>(seed + 300, coverage, Extents::LongLines);
  }
  // Unrepairable voxels need a removed component whose every walk leaves the image, which
  // long lines rarely give; the other tests hold them to the reference.
  coverage.ExpectEnough(false);
}

TEST(SmallIsoComponentLabelImageFilter, MatchesReferenceOnManyLines)
{
  Coverage coverage;
  for (uint32_t seed = 5001; seed <= 5012; ++seed)
  {
    ExpectSameAsReference<uint8_t, 3>(seed, coverage, Extents::ManyLines);
    ExpectSameAsReference<uint16_t, 3>(seed + 100, coverage, Extents::ManyLines);
    ExpectSameAsReference<float, 3>(seed + 200, coverage, Extents::ManyLines);
  }
  coverage.ExpectEnough(false);
}

/** Parameters drawn from \a random for a label map of \a ids. */
template <typename TFilter, typename TLabel>
void
DrawSettings(RandomSource & random, const std::vector<TLabel> & ids, TFilter * filter)
{
  // Small K, so that the halo leaves most of the image out of a part.
  filter->SetMaximumComponentSize(static_cast<SizeValueType>(random.Between(1, 4)));
  if (random.Chance(0.3))
  {
    filter->SetMaximumComponentSizes({ { ids[random.Bits() % ids.size()], random.Between(0, 6) } });
  }
  filter->SetSelection(static_cast<SelectionEnum>(random.Between(0, 2)));
  filter->SetBackgroundValue(ids[random.Bits() % ids.size()]);
  filter->SetKeepLargestComponents(random.Chance(0.15) ? 1 : 0);
  filter->SetFullyConnected(random.Chance(0.4));
  filter->SetGenerateRemovedMask(true);
}

/** A random region inside \a whole. */
template <unsigned int VDimension>
ImageRegion<VDimension>
DrawRegion(RandomSource & random, const ImageRegion<VDimension> & whole)
{
  ImageRegion<VDimension> region;
  for (unsigned int a = 0; a < VDimension; ++a)
  {
    const auto first = random.Between(0, static_cast<int64_t>(whole.GetSize(a)) - 1);
    region.SetIndex(a, first);
    region.SetSize(a, static_cast<SizeValueType>(random.Between(1, static_cast<int64_t>(whole.GetSize(a)) - first)));
  }
  return region;
}

/** The counts of \a filter's last run are those of the voxels it wrote, its output's buffered
 * region, voxel for voxel in \a whole's output: a repaired voxel always changes label, so the
 * modified voxels are those that differ from \a input, and the unrepairable ones the rest of the
 * removed. A voxel of the halo counted would make them larger. */
template <typename TFilter, typename TImage>
void
ExpectCountsOfTheVoxelsWritten(TFilter * filter, TFilter * whole, const TImage * input, const std::string & what)
{
  using LabelType = typename TImage::PixelType;
  SizeValueType                      modified = 0;
  SizeValueType                      unrepairable = 0;
  std::map<LabelType, SizeValueType> gained;
  const auto                         region = filter->GetOutput()->GetBufferedRegion();
  for (ImageRegionConstIteratorWithIndex<TImage> it(whole->GetOutput(), region); !it.IsAtEnd(); ++it)
  {
    if (it.Get() != input->GetPixel(it.GetIndex()))
    {
      ++modified;
      ++gained[it.Get()];
    }
    else if (whole->GetRemovedMask()->GetPixel(it.GetIndex()) != 0)
    {
      ++unrepairable;
    }
  }
  EXPECT_EQ(filter->GetNumberOfModifiedVoxels(), modified) << what << ", region " << region;
  EXPECT_EQ(filter->GetNumberOfUnrepairableVoxels(), unrepairable) << what << ", region " << region;
  std::map<LabelType, SizeValueType> counted;
  for (const auto & entry : filter->GetLabelStatistics())
  {
    if (entry.second.GainedVoxels > 0)
    {
      counted[entry.first] = entry.second.GainedVoxels;
    }
  }
  EXPECT_EQ(counted, gained) << what << ", region " << region;
}

/** Any part of the output, alone or as a piece of a streamed output, is that part of the whole
 * image's output: the filter reads the part with a halo of twice the largest K, and keeps what
 * reaches the halo's open border. Its counts are those of the part's voxels. */
template <unsigned int VDimension>
void
ExpectPartsOfTheWhole(uint32_t seed)
{
  using ImageType = Image<uint16_t, VDimension>;
  using FilterType = SmallIsoComponentLabelImageFilter<ImageType>;
  RandomSource                          random(seed);
  std::array<SizeValueType, VDimension> size;
  for (SizeValueType & extent : size)
  {
    extent = static_cast<SizeValueType>(random.Between(VDimension == 2 ? 40 : 16, VDimension == 2 ? 100 : 32));
  }
  const std::vector<uint16_t> ids{ 0, 1, 2, 3, 7 };
  const auto                  input =
    SmallIsoComponentTest::MakeImage<uint16_t, VDimension>(size, DrawLabels<uint16_t, VDimension>(random, size, ids));
  auto whole = FilterType::New();
  whole->SetInput(input);
  DrawSettings(random, ids, whole.GetPointer());
  whole->Update();

  const auto same = [&whole](FilterType * filter) {
    filter->SetMaximumComponentSize(whole->GetMaximumComponentSize());
    filter->SetMaximumComponentSizes(whole->GetMaximumComponentSizes());
    filter->SetSelection(whole->GetSelection());
    filter->SetBackgroundValue(whole->GetBackgroundValue());
    filter->SetKeepLargestComponents(whole->GetKeepLargestComponents());
    filter->SetFullyConnected(whole->GetFullyConnected());
    filter->SetGenerateRemovedMask(true);
  };
  const std::string what = "seed " + std::to_string(seed);
  for (unsigned int trial = 0; trial < 4; ++trial)
  {
    auto part = FilterType::New();
    part->SetInput(input);
    same(part);
    const ImageRegion<VDimension> region = DrawRegion(random, input->GetLargestPossibleRegion());
    part->UpdateOutputInformation();
    part->GetOutput()->SetRequestedRegion(region);
    part->GetOutput()->Update();
    // Keep-largest needs the whole image, and makes it.
    ASSERT_EQ(part->GetOutput()->GetBufferedRegion(),
              part->GetKeepLargestComponents() > 0 ? input->GetLargestPossibleRegion() : region)
      << what;
    SizeValueType wrong = 0;
    for (ImageRegionConstIteratorWithIndex<ImageType> it(part->GetOutput(), region); !it.IsAtEnd(); ++it)
    {
      wrong += it.Get() != whole->GetOutput()->GetPixel(it.GetIndex()) ||
               part->GetRemovedMask()->GetPixel(it.GetIndex()) != whole->GetRemovedMask()->GetPixel(it.GetIndex());
    }
    EXPECT_EQ(wrong, 0u) << what << ", region " << region;
    ExpectCountsOfTheVoxelsWritten(part.GetPointer(), whole.GetPointer(), input.GetPointer(), what);
  }
  // Streamed in pieces from a source that makes only the region asked of it.
  auto source = ExtractImageFilter<ImageType, ImageType>::New();
  source->SetInput(input);
  source->SetExtractionRegion(input->GetLargestPossibleRegion());
  source->SetDirectionCollapseToSubmatrix();
  source->InPlaceOff();
  auto filter = FilterType::New();
  filter->SetInput(source->GetOutput());
  same(filter);
  auto streamer = StreamingImageFilter<ImageType, ImageType>::New();
  streamer->SetInput(filter->GetOutput());
  streamer->SetNumberOfStreamDivisions(static_cast<unsigned int>(random.Between(2, 9)));
  streamer->Update();
  EXPECT_EQ(SmallIsoComponentTest::CountDifferentVoxels(streamer->GetOutput(), whole->GetOutput()), 0u) << what;
  // The filter's output holds the last piece.
  ExpectCountsOfTheVoxelsWritten(filter.GetPointer(), whole.GetPointer(), input.GetPointer(), what);
}

TEST(SmallIsoComponentLabelImageFilter, PartsAndStreamedPiecesAreThoseOfTheWholeImage)
{
  for (uint32_t seed = 5001; seed <= 5060; ++seed)
  {
    ExpectPartsOfTheWhole<2>(seed);
    ExpectPartsOfTheWhole<3>(seed + 100);
  }
}

/** The same result in place as out of place. */
TEST(SmallIsoComponentLabelImageFilter, InPlaceGivesTheSameResult)
{
  for (uint32_t seed = 4001; seed <= 4040; ++seed)
  {
    RandomSource                       random(seed);
    const std::array<SizeValueType, 3> size{ 12, 9, 7 };
    const std::vector<uint8_t>         labels = DrawLabels<uint8_t, 3>(random, size, { 0, 1, 2, 3 });
    using ImageType = Image<uint8_t, 3>;
    auto apart = SmallIsoComponentLabelImageFilter<ImageType>::New();
    apart->SetInput(SmallIsoComponentTest::MakeImage<uint8_t, 3>(size, labels));
    apart->SetMaximumComponentSize(6);
    apart->Update();
    auto inPlace = SmallIsoComponentLabelImageFilter<ImageType>::New();
    inPlace->SetInput(SmallIsoComponentTest::MakeImage<uint8_t, 3>(size, labels));
    inPlace->SetMaximumComponentSize(6);
    inPlace->InPlaceOn();
    inPlace->Update();
    EXPECT_EQ(SmallIsoComponentTest::CountDifferentVoxels(apart->GetOutput(), inPlace->GetOutput()), 0u)
      << "seed " << seed;
  }
}

/** Expects the update of \a filter to be refused with a description that contains \a expected. */
template <typename TFilter>
void
ExpectRefused(TFilter * filter, const std::string & expected)
{
  try
  {
    filter->Update();
    ADD_FAILURE() << "accepted; expected a refusal naming " << expected;
  }
  catch (const ExceptionObject & error)
  {
    EXPECT_NE(std::string(error.GetDescription()).find(expected), std::string::npos) << error.GetDescription();
  }
}

/** A floating-point label map with a fractional, infinite or NaN sample is refused. */
TEST(SmallIsoComponentLabelImageFilter, RefusesSamplesThatAreNotWholeNumbers)
{
  using ImageType = Image<float, 2>;
  for (const float bad : { 2.5f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN() })
  {
    std::vector<float> labels(20, 3.0f);
    labels[13] = bad;
    auto filter = SmallIsoComponentLabelImageFilter<ImageType>::New();
    filter->SetInput(SmallIsoComponentTest::MakeImage<float, 2>({ 5, 4 }, labels));
    SCOPED_TRACE(testing::Message() << "a sample of " << bad);
    ExpectRefused(filter.GetPointer(), "[3, 2]");
  }
}

/** The whole-number check agrees with std::trunc on the edges of each type and on random bit patterns. */
TEST(SmallIsoComponentLabelImageFilter, ChecksWholeNumbersAsTruncDoes)
{
  const auto check = [](auto value) {
    const bool expected = std::isfinite(value) && std::trunc(value) == value;
    EXPECT_EQ(SmallIsoComponentDetail::AreWholeNumbers(&value, 1), expected) << std::hexfloat << value;
  };
  const auto checkType = [&check](auto zero, auto bitsZero) {
    using Real = decltype(zero);
    using Limits = std::numeric_limits<Real>;
    const Real wholeAbove = Real{ 1 } / Limits::epsilon();
    for (const Real edge : { Real{ 0 },
                             -Real{ 0 },
                             Real{ 0.5 },
                             Real{ 1 },
                             std::nextafter(Real{ 1 }, Real{ 0 }),
                             wholeAbove - Real{ 0.5 },
                             wholeAbove - Real{ 1 },
                             wholeAbove,
                             wholeAbove + Real{ 1 },
                             std::nextafter(wholeAbove, Real{ 0 }),
                             Real{ 2 } * wholeAbove + Real{ 2 },
                             Limits::max(),
                             Limits::lowest(),
                             Limits::denorm_min(),
                             Limits::min(),
                             Limits::infinity(),
                             -Limits::infinity(),
                             Limits::quiet_NaN(),
                             Real{ -2.5 },
                             Real{ 98000000 } })
    {
      check(edge);
      check(-edge);
    }
    std::mt19937_64 random(17);
    for (int i = 0; i < 200000; ++i)
    {
      auto bits = static_cast<decltype(bitsZero)>(random());
      Real value;
      std::memcpy(&value, &bits, sizeof(value));
      check(value);
      // Values near the whole numbers too, which random bit patterns seldom give.
      check(std::nearbyint(value / Real{ 1e30 }) + static_cast<Real>(i % 3) / Real{ 4 });
    }
  };
  checkType(0.0f, uint32_t{ 0 });
  checkType(0.0, uint64_t{ 0 });
}

/** A run of equal samples that are not whole numbers is refused, at its first sample, wherever -0 and 0 lie before
 * it (the check reads the runs' labels). */
TEST(SmallIsoComponentLabelImageFilter, RefusesRunsOfSamplesThatAreNotWhole)
{
  using ImageType = Image<float, 2>;
  for (const float bad : { 0.5f,
                           -7.25f,
                           std::numeric_limits<float>::infinity(),
                           -std::numeric_limits<float>::infinity(),
                           std::numeric_limits<float>::quiet_NaN() })
  {
    for (const unsigned int workUnits : { 1u, 2u })
    {
      std::vector<float> labels(40 * 6, 1.0f);
      for (SizeValueType x = 0; x < 10; ++x)
      {
        labels[3 * 40 + x] = x % 2 == 0 ? -0.0f : 0.0f;
      }
      std::fill_n(labels.begin() + 3 * 40 + 10, 20, bad);
      auto filter = SmallIsoComponentLabelImageFilter<ImageType>::New();
      filter->SetInput(SmallIsoComponentTest::MakeImage<float, 2>({ 40, 6 }, labels));
      filter->SetNumberOfWorkUnits(workUnits);
      SCOPED_TRACE(testing::Message() << "a run of " << bad << " at " << workUnits << " work units");
      ExpectRefused(filter.GetPointer(), "[10, 3]");
    }
  }
}

/** The first sample that is not a whole number is named, whatever the number of work units. */
TEST(SmallIsoComponentLabelImageFilter, NamesTheFirstSampleThatIsNotWhole)
{
  using ImageType = Image<float, 3>;
  const std::array<SizeValueType, 3> size{ 64, 32, 16 };
  std::vector<float>                 labels(64 * 32 * 16, 7.0f);
  labels[(12 * 32 + 5) * 64 + 9] = 0.25f;
  labels[(14 * 32 + 1) * 64 + 2] = std::numeric_limits<float>::quiet_NaN();
  for (const unsigned int workUnits : { 1u, 2u, 7u })
  {
    auto filter = SmallIsoComponentLabelImageFilter<ImageType>::New();
    filter->SetInput(SmallIsoComponentTest::MakeImage<float, 3>(size, labels));
    filter->SetNumberOfWorkUnits(workUnits);
    SCOPED_TRACE(testing::Message() << workUnits << " work units");
    ExpectRefused(filter.GetPointer(), "[9, 5, 12] is 0.25");
  }
}

/** -0 is the label 0: a float map gives the same components, output values and mask whichever
 * sign its zeros have (runs are found by comparing bytes first, in which the two differ). */
TEST(SmallIsoComponentLabelImageFilter, TakesNegativeZeroAsZero)
{
  using ImageType = Image<float, 2>;
  const std::array<SizeValueType, 2> size{ 150, 8 };
  for (uint32_t seed = 7001; seed <= 7010; ++seed)
  {
    RandomSource             random(seed);
    const std::vector<float> labels = DrawLabels<float, 2>(random, size, { 0.0f, 1.0f, 2.0f });
    std::vector<float>       signedZeros = labels;
    for (float & label : signedZeros)
    {
      label = label == 0.0f && random.Uniform() < 0.5 ? -0.0f : label;
    }
    const auto run = [&size](const std::vector<float> & map) {
      auto filter = SmallIsoComponentLabelImageFilter<ImageType>::New();
      filter->SetInput(SmallIsoComponentTest::MakeImage<float, 2>(size, map));
      filter->SetMaximumComponentSize(4);
      filter->GenerateRemovedMaskOn();
      filter->Update();
      return filter;
    };
    const auto          positive = run(labels);
    const auto          mixed = run(signedZeros);
    const float * const a = positive->GetOutput()->GetBufferPointer();
    const float * const b = mixed->GetOutput()->GetBufferPointer();
    EXPECT_TRUE(std::equal(a, a + labels.size(), b)) << "seed " << seed;
    EXPECT_EQ(SmallIsoComponentTest::CountDifferentVoxels(positive->GetRemovedMask(), mixed->GetRemovedMask()), 0u)
      << "seed " << seed;
    EXPECT_EQ(positive->GetLabelStatistics().at(0.0f).Components, mixed->GetLabelStatistics().at(0.0f).Components)
      << "seed " << seed;
  }
}

/** K from a physical volume: floor(volume / voxel volume). */
TEST(SmallIsoComponentLabelImageFilter, TakesKFromAVolume)
{
  using ImageType = Image<uint8_t, 3>;
  auto                   image = SmallIsoComponentTest::MakeImage<uint8_t, 3>({ 4, 4, 4 }, std::vector<uint8_t>(64, 1));
  ImageType::SpacingType spacing;
  spacing[0] = 0.5;
  spacing[1] = 2.0;
  spacing[2] = 3.0;
  image->SetSpacing(spacing);
  auto filter = SmallIsoComponentLabelImageFilter<ImageType>::New();
  filter->SetInput(image);
  filter->SetMaximumComponentVolume(7.0 * 3.0);
  filter->Update();
  EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 7u);
  filter->SetMaximumComponentSize(4);
  filter->Update();
  EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 4u);
}

TEST(SmallIsoComponentLabelImageFilter, PerLabelAccessorsAgreeWithTheMaps)
{
  using ImageType = Image<int16_t, 3>;
  for (uint32_t seed = 1; seed <= 20; ++seed)
  {
    RandomSource                       random(seed);
    const std::vector<int16_t>         ids = DrawIds<int16_t>(random);
    const std::array<SizeValueType, 3> size{ 9, 7, 6 };
    const auto image = SmallIsoComponentTest::MakeImage<int16_t, 3>(size, DrawLabels<int16_t, 3>(random, size, ids));
    const SizeValueType k = random.Between(0, 6);
    auto                byMap = SmallIsoComponentLabelImageFilter<ImageType>::New();
    auto                oneByOne = SmallIsoComponentLabelImageFilter<ImageType>::New();
    typename decltype(byMap)::ObjectType::LabelSizeMapType sizes;
    for (auto * filter : { byMap.GetPointer(), oneByOne.GetPointer() })
    {
      filter->SetInput(image);
      filter->SetMaximumComponentSize(3);
    }
    sizes[ids[0]] = k;
    sizes[ids[1]] = k + 4;
    byMap->SetMaximumComponentSizes(sizes);
    oneByOne->SetMaximumComponentSizeOfLabel(ids[1], k + 4);
    oneByOne->SetMaximumComponentSizeOfLabel(ids[0], k);
    EXPECT_EQ(oneByOne->GetMaximumComponentSizes(), sizes);
    byMap->Update();
    oneByOne->Update();
    const auto * expected = byMap->GetOutput()->GetBufferPointer();
    EXPECT_TRUE(std::equal(
      expected, expected + image->GetBufferedRegion().GetNumberOfPixels(), oneByOne->GetOutput()->GetBufferPointer()));
    std::vector<int16_t> labels;
    for (const auto & [label, statistics] : byMap->GetLabelStatistics())
    {
      labels.push_back(label);
      EXPECT_EQ(oneByOne->GetNumberOfComponents(label), statistics.Components);
      EXPECT_EQ(oneByOne->GetNumberOfRemovedComponents(label), statistics.RemovedComponents);
      EXPECT_EQ(oneByOne->GetNumberOfRemovedVoxels(label), statistics.RemovedVoxels);
      EXPECT_EQ(oneByOne->GetNumberOfGainedVoxels(label), statistics.GainedVoxels);
      EXPECT_EQ(oneByOne->GetComponentSizeHistogram(label), statistics.Histogram);
    }
    EXPECT_EQ(oneByOne->GetLabels(), labels);
    int16_t absent = 0;
    while (std::find(labels.begin(), labels.end(), absent) != labels.end())
    {
      ++absent;
    }
    EXPECT_EQ(oneByOne->GetNumberOfComponents(absent), 0u);
    EXPECT_TRUE(oneByOne->GetComponentSizeHistogram(absent).empty());
  }
}

TEST(SmallIsoComponentLabelImageFilter, RefusesAnEmptyList)
{
  using ImageType = Image<uint8_t, 2>;
  auto filter = SmallIsoComponentLabelImageFilter<ImageType>::New();
  filter->SetInput(SmallIsoComponentTest::MakeImage<uint8_t, 2>({ 3, 3 }, std::vector<uint8_t>(9, 1)));
  filter->SetSelection(SelectionEnum::Listed);
  EXPECT_THROW(filter->Update(), ExceptionObject);
  filter->SetSelectedLabels({ 1 });
  EXPECT_NO_THROW(filter->Update());
}
} // namespace
