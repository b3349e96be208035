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

// Small hand-made images whose expected outputs were worked out by hand, one behaviour
// of the filter each.

#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"
#include <cmath>

namespace
{
using namespace itk::SmallIsoComponentTest;
using SizeValueType = itk::SizeValueType;
using Histogram = std::map<SizeValueType, SizeValueType>;

template <typename TPixel>
using Image2D = itk::Image<TPixel, 2>;
template <typename TPixel>
using Image3D = itk::Image<TPixel, 3>;

/** A 2D image from rows listed top (y = 0) to bottom. */
template <typename TPixel>
typename Image2D<TPixel>::Pointer
MakeImage2D(SizeValueType width, SizeValueType height, const std::vector<TPixel> & rows)
{
  return MakeImage<TPixel, 2>({ width, height }, rows);
}

template <typename TImage>
std::vector<typename TImage::PixelType>
Values(const TImage * image)
{
  return Reference::BufferOf(image);
}

Parameters
Settings(double isoValue, SizeValueType K, SideEnum side, bool fullyConnected = false)
{
  Parameters p;
  p.IsoValue = isoValue;
  p.MaximumComponentSize = K;
  p.Side = side;
  p.FullyConnected = fullyConnected;
  return p;
}

/** Floor of a / b for b > 0, negative a included. */
int64_t
FloorDivide(int64_t a, int64_t b)
{
  return a / b - (a % b != 0 && a < 0 ? 1 : 0);
}

/** Lays out one single-voxel component per combination of neighbour values: component
 * i sits at the centre of its own 3^N cell, its 2·N face neighbours get the values of
 * combination i, and every other voxel of the image is \a filler. Each walk from a centre
 * stops at once on its neighbour, so the repair value is the mean of the combination. */
template <typename TPixel, unsigned int VDimension>
typename itk::Image<TPixel, VDimension>::Pointer
MakeLattice(const std::vector<TPixel> & neighborValues, TPixel centre, TPixel filler, std::vector<int64_t> & sums)
{
  constexpr unsigned int neighbors = 2 * VDimension;
  SizeValueType          combinations = 1;
  for (unsigned int k = 0; k < neighbors; ++k)
  {
    combinations *= neighborValues.size();
  }
  // Cells per axis: the smallest count whose power holds every combination.
  SizeValueType cells = 1;
  while (itk::Math::UnsignedPower(cells, VDimension) < combinations)
  {
    ++cells;
  }
  std::array<SizeValueType, VDimension> size;
  size.fill(3 * cells);
  const Reference::Grid<VDimension> grid(size, false);
  std::vector<TPixel>               values(grid.NumberOfVoxels(), filler);
  sums.assign(combinations, 0);
  for (SizeValueType i = 0; i < combinations; ++i)
  {
    typename Reference::Grid<VDimension>::CoordinatesType c;
    SizeValueType                                         cell = i;
    for (unsigned int a = 0; a < VDimension; ++a)
    {
      c[a] = static_cast<itk::OffsetValueType>(3 * (cell % cells) + 1);
      cell /= cells;
    }
    values[grid.Linear(c)] = centre;
    SizeValueType digits = i;
    for (unsigned int k = 0; k < neighbors; ++k)
    {
      const TPixel value = neighborValues[digits % neighborValues.size()];
      digits /= neighborValues.size();
      auto n = c;
      n[k / 2] += k % 2 == 0 ? -1 : 1;
      values[grid.Linear(n)] = value;
      sums[i] += value;
    }
  }
  return MakeImage<TPixel, VDimension>(size, values);
}

/** Removes single-voxel components whose neighbours are integers on the other side of an
 * integer σ, for every combination of neighbour values, and checks that each new value is
 * the mean rounded half up and still on the other side. */
template <typename TPixel, unsigned int VDimension>
void
ExpectRoundingKeepsTheSide(int isoValue, bool removeAbove)
{
  const int           step = removeAbove ? -1 : 1;
  const int           first = removeAbove ? isoValue - 1 : isoValue; // the value closest to σ
  std::vector<TPixel> neighborValues;
  for (int k = 0; k < (VDimension == 2 ? 4 : 2); ++k)
  {
    neighborValues.push_back(static_cast<TPixel>(first + step * k));
  }
  const auto           centre = static_cast<TPixel>(removeAbove ? isoValue : isoValue - 1);
  std::vector<int64_t> sums;
  const auto input = MakeLattice<TPixel, VDimension>(neighborValues, centre, static_cast<TPixel>(first), sums);
  using ImageType = itk::Image<TPixel, VDimension>;
  const auto filter =
    RunFilter<ImageType>(input.GetPointer(), Settings(isoValue, 1, removeAbove ? SideEnum::Above : SideEnum::Below));
  ASSERT_EQ(filter->GetNumberOfRemovedComponents(removeAbove ? SideEnum::Above : SideEnum::Below), sums.size());

  const int64_t  n = 2 * VDimension;
  unsigned int   halves = 0;
  const TPixel * output = filter->GetOutput()->GetBufferPointer();
  const TPixel * in = input->GetBufferPointer();
  SizeValueType  checked = 0;
  for (SizeValueType v = 0; v < input->GetBufferedRegion().GetNumberOfPixels(); ++v)
  {
    if (in[v] != centre)
    {
      continue;
    }
    const int64_t sum = sums[checked++];
    // The mean rounded half up, in integers: floor((2 * sum + n) / (2 * n)).
    const int64_t expected = FloorDivide(2 * sum + n, 2 * n);
    halves += (2 * sum) % (2 * n) == n || (2 * sum) % (2 * n) == -n ? 1 : 0;
    EXPECT_EQ(int64_t{ output[v] }, expected) << "neighbour sum " << sum << " of " << n;
    if (removeAbove)
    {
      EXPECT_LT(output[v], isoValue) << "neighbour sum " << sum;
    }
    else
    {
      EXPECT_GE(output[v], isoValue) << "neighbour sum " << sum;
    }
  }
  EXPECT_EQ(checked, sums.size());
  EXPECT_GT(halves, 0u) << "no combination had a mean ending in .5";
}
} // namespace

TEST(SmallIsoComponentBehaviour, BubbleInsideSpeckGoesWithTheSpeck)
{
  // A ring of eight above voxels (90) around a one-voxel bubble (40), on a background
  // 1 + 2x + 3y, σ = 50, K = 8. Both removes the speck first; its bubble then belongs to
  // the background and keeps its value. Removing the bubble on the original
  // classification would have left a solid speck.
  std::vector<uint8_t> rows(49);
  for (unsigned int y = 0; y < 7; ++y)
  {
    for (unsigned int x = 0; x < 7; ++x)
    {
      const bool ring = x >= 2 && x <= 4 && y >= 2 && y <= 4;
      rows[7 * y + x] = static_cast<uint8_t>(ring ? 90 : 1 + 2 * x + 3 * y);
    }
  }
  rows[7 * 3 + 3] = 40;
  const auto input = MakeImage2D<uint8_t>(7, 7, rows);

  const auto           both = RunFilter<Image2D<uint8_t>>(input.GetPointer(), Settings(50, 8, SideEnum::Both));
  std::vector<uint8_t> expected = rows;
  // Ring voxel -> mean of the first below values along -x, +x, -y, +y (worked by hand).
  expected[7 * 2 + 2] = 14; // (9 + 17 + 8 + 20) / 4 = 13.5
  expected[7 * 2 + 3] = 19; // (9 + 17 + 10 + 40) / 4
  expected[7 * 2 + 4] = 16; // (9 + 17 + 12 + 24) / 4 = 15.5
  expected[7 * 3 + 2] = 20; // (12 + 40 + 8 + 20) / 4
  expected[7 * 3 + 4] = 24; // (40 + 20 + 12 + 24) / 4
  expected[7 * 4 + 2] = 17; // (15 + 23 + 8 + 20) / 4 = 16.5
  expected[7 * 4 + 3] = 25; // (15 + 23 + 40 + 22) / 4
  expected[7 * 4 + 4] = 19; // (15 + 23 + 12 + 24) / 4 = 18.5
  EXPECT_EQ(Values(both->GetOutput()), expected);
  std::vector<uint8_t> expectedMask(49, 0);
  for (const unsigned int v : { 16, 17, 18, 23, 25, 30, 31, 32 })
  {
    expectedMask[v] = 1;
  }
  EXPECT_EQ(Values(both->GetRemovedMask()), expectedMask);
  EXPECT_EQ(both->GetNumberOfComponents(SideEnum::Above), 1u);
  EXPECT_EQ(both->GetComponentSizeHistogram(SideEnum::Above), (Histogram{ { 8, 1 } }));
  EXPECT_EQ(both->GetNumberOfRemovedComponents(SideEnum::Above), 1u);
  EXPECT_EQ(both->GetNumberOfRemovedVoxels(SideEnum::Above), 8u);
  // The below pass sees one background that has swallowed the bubble and the ring.
  EXPECT_EQ(both->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 49, 1 } }));
  EXPECT_EQ(both->GetNumberOfRemovedComponents(SideEnum::Below), 0u);
  EXPECT_EQ(both->GetNumberOfModifiedVoxels(), 8u);
  EXPECT_EQ(both->GetNumberOfUnrepairableVoxels(), 0u);

  // Below alone fills the bubble with the mean of the ring around it.
  const auto           below = RunFilter<Image2D<uint8_t>>(input.GetPointer(), Settings(50, 8, SideEnum::Below));
  std::vector<uint8_t> filled = rows;
  filled[7 * 3 + 3] = 90;
  EXPECT_EQ(Values(below->GetOutput()), filled);
  EXPECT_EQ(below->GetRemovedMask()->GetBufferPointer()[7 * 3 + 3], 2);
  EXPECT_EQ(below->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 1, 1 }, { 40, 1 } }));
  EXPECT_EQ(below->GetNumberOfRemovedVoxels(SideEnum::Below), 1u);
  EXPECT_EQ(below->GetNumberOfRemovedComponents(SideEnum::Above), 0u);
}

TEST(SmallIsoComponentBehaviour, SpeckWithBubbleInsideObjectWithBubbleIn3D)
{
  // 3D, Both, K = 1: a one-voxel bubble inside a big object is filled, and a one-voxel
  // speck outside it is removed; components of two or more voxels stay.
  const SizeValueType  n = 6;
  std::vector<int16_t> values(n * n * n, -100);
  const auto           at = [n](SizeValueType x, SizeValueType y, SizeValueType z) { return x + n * (y + n * z); };
  for (SizeValueType z = 0; z < n; ++z)
  {
    for (SizeValueType y = 0; y < n; ++y)
    {
      for (SizeValueType x = 3; x < n; ++x)
      {
        values[at(x, y, z)] = 100;
      }
    }
  }
  values[at(4, 2, 2)] = -50; // bubble
  values[at(1, 3, 3)] = 60;  // speck
  values[at(1, 0, 0)] = 70;  // a two-voxel speck, kept
  values[at(1, 1, 0)] = 70;
  const auto           input = MakeImage<int16_t, 3>({ n, n, n }, values);
  const auto           filter = RunFilter<Image3D<int16_t>>(input.GetPointer(), Settings(0, 1, SideEnum::Both));
  std::vector<int16_t> expected = values;
  expected[at(4, 2, 2)] = 100;
  expected[at(1, 3, 3)] = -100;
  EXPECT_EQ(Values(filter->GetOutput()), expected);
  EXPECT_EQ(filter->GetComponentSizeHistogram(SideEnum::Above), (Histogram{ { 1, 1 }, { 2, 1 }, { 107, 1 } }));
  EXPECT_EQ(filter->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 1, 1 }, { 106, 1 } }));
  EXPECT_EQ(filter->GetNumberOfModifiedVoxels(), 2u);
}

TEST(SmallIsoComponentBehaviour, ComponentsTouchingTheBorder)
{
  // Walks that leave the image find nothing and are left out of the mean.
  // clang-format off
  const auto input = MakeImage2D<uint8_t>(5, 4, {
    200, 30, 40, 50,  60,
     20, 70, 80, 200, 200,
     25, 35, 45, 55,  65,
      5,  6,  7,  8,  210 });
  // clang-format on
  const auto filter = RunFilter<Image2D<uint8_t>>(input.GetPointer(), Settings(100, 2, SideEnum::Above));
  // clang-format off
  EXPECT_EQ(Values(filter->GetOutput()), (std::vector<uint8_t>{
     25, 30, 40, 50, 60,  // (30 + 20) / 2
     20, 70, 80, 62, 68,  // (80 + 50 + 55) / 3 = 61.7; (80 + 60 + 65) / 3 = 68.3
     25, 35, 45, 55, 65,
      5,  6,  7,  8, 37 })); // (8 + 65) / 2 = 36.5
  // clang-format on
  EXPECT_EQ(filter->GetComponentSizeHistogram(SideEnum::Above), (Histogram{ { 1, 2 }, { 2, 1 } }));
  EXPECT_EQ(filter->GetNumberOfRemovedVoxels(SideEnum::Above), 4u);
  EXPECT_EQ(filter->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 16, 1 } }));
  EXPECT_EQ(filter->GetNumberOfUnrepairableVoxels(), 0u);

  // A component spanning the image along x: only the y walks find values.
  // clang-format off
  const auto band = MakeImage2D<uint8_t>(3, 3, {
     10,  20,  30,
    200, 200, 200,
     40,  50,  61 });
  // clang-format on
  const auto bandFilter = RunFilter<Image2D<uint8_t>>(band.GetPointer(), Settings(100, 3, SideEnum::Above));
  EXPECT_EQ(Values(bandFilter->GetOutput()), (std::vector<uint8_t>{ 10, 20, 30, 25, 35, 46, 40, 50, 61 }));
}

TEST(SmallIsoComponentBehaviour, IntegerRoundingNeverCrossesAnIntegerIsoValue)
{
  // Every combination of neighbour values next to σ, so means end in .25, .5, .75 and
  // .5 exactly (rounded half up, towards σ when removing above components).
  ExpectRoundingKeepsTheSide<uint8_t, 2>(100, true);
  ExpectRoundingKeepsTheSide<uint8_t, 2>(100, false);
  ExpectRoundingKeepsTheSide<int16_t, 2>(-10, true);
  ExpectRoundingKeepsTheSide<int16_t, 2>(-10, false);
  ExpectRoundingKeepsTheSide<int16_t, 2>(0, true);
  ExpectRoundingKeepsTheSide<int16_t, 3>(0, false);
  ExpectRoundingKeepsTheSide<int16_t, 3>(7, true);
  ExpectRoundingKeepsTheSide<uint8_t, 3>(2, true);
  ExpectRoundingKeepsTheSide<uint8_t, 3>(254, false);
}

TEST(SmallIsoComponentBehaviour, NaNIsBelowAndNeverARepairValue)
{
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();

  // A NaN bubble in an above object is a below component and is filled.
  // clang-format off
  const auto bubble = MakeImage2D<float>(5, 5, {
    0, 0, 0,   0, 0,
    0, 1, 2,   3, 0,
    0, 4, nan, 5, 0,
    0, 6, 7,   8, 0,
    0, 0, 0,   0, 0 });
  // clang-format on
  const auto filled = RunFilter<Image2D<float>>(bubble.GetPointer(), Settings(0.5, 1, SideEnum::Both));
  EXPECT_EQ(filled->GetOutput()->GetBufferPointer()[12], 4.5f); // (4 + 5 + 2 + 7) / 4
  EXPECT_EQ(filled->GetRemovedMask()->GetBufferPointer()[12], 2);
  EXPECT_EQ(filled->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 1, 1 }, { 16, 1 } }));
  EXPECT_EQ(filled->GetNumberOfModifiedVoxels(), 1u);

  // A speck whose walks meet NaN in two directions: only the other two count.
  // clang-format off
  const auto speck = MakeImage2D<float>(5, 5, {
    0, 0,    0,     0,   0,
    0, 0,    nan,   0,   0,
    0, 0.25, 1,     nan, 0,
    0, 0,    0.125, 0,   0,
    0, 0,    0,     0,   0 });
  // clang-format on
  const auto repaired = RunFilter<Image2D<float>>(speck.GetPointer(), Settings(0.5, 1, SideEnum::Above));
  const auto out = Values(repaired->GetOutput());
  EXPECT_EQ(out[12], 0.1875f); // (0.25 + 0.125) / 2
  EXPECT_TRUE(std::isnan(out[7]));
  EXPECT_TRUE(std::isnan(out[13]));
  EXPECT_EQ(repaired->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 24, 1 } }));
  EXPECT_EQ(repaired->GetNumberOfUnrepairableVoxels(), 0u);

  // Only NaN and the border around a speck: the fallback, the largest float below σ.
  const auto cornered = MakeImage2D<float>(3, 1, { nan, 1, nan });
  const auto fallback = RunFilter<Image2D<float>>(cornered.GetPointer(), Settings(0.5, 1, SideEnum::Both));
  EXPECT_EQ(fallback->GetOutput()->GetBufferPointer()[1], std::nextafter(0.5f, 0.0f));
  EXPECT_EQ(fallback->GetNumberOfUnrepairableVoxels(), 1u);
  EXPECT_EQ(fallback->GetNumberOfRemovedComponents(SideEnum::Above), 1u);
  EXPECT_EQ(fallback->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 3, 1 } }));

  // A below component made of NaN only, inside an object, is filled too.
  // clang-format off
  const auto nanPair = MakeImage2D<float>(4, 3, {
    2, 2,   2,   2,
    2, nan, nan, 2,
    2, 2,   3,   2 });
  // clang-format on
  const auto pair = RunFilter<Image2D<float>>(nanPair.GetPointer(), Settings(0.5, 2, SideEnum::Below));
  EXPECT_EQ(Values(pair->GetOutput()), (std::vector<float>{ 2, 2, 2, 2, 2, 2, 2.25f, 2, 2, 2, 3, 2 }));
}

TEST(SmallIsoComponentBehaviour, DoubleRepairValuesNeverOverflow)
{
  // A bubble inside samples near the largest double, and a speck inside samples near the
  // lowest: the sums of their six walks' values overflow, their means do not.
  constexpr double    huge = 1.7e308;
  constexpr unsigned  n = 3;
  std::vector<double> values(n * n * n, huge);
  values[13] = 0.0;
  const auto   bubble = MakeImage<double, 3>({ n, n, n }, values);
  const auto   settings = Settings(1.0, 1, SideEnum::Both);
  const auto   filled = RunFilter<Image3D<double>>(bubble.GetPointer(), settings);
  const double repaired = filled->GetOutput()->GetBufferPointer()[13];
  EXPECT_TRUE(std::isfinite(repaired));
  EXPECT_NEAR(repaired / huge, 1.0, 1e-15);
  EXPECT_EQ(Values(filled->GetOutput()), Reference::Run<double>(bubble.GetPointer(), settings).Output);

  std::vector<double> negative(n * n * n, -huge);
  negative[13] = 0.0;
  const auto speck = MakeImage<double, 3>({ n, n, n }, negative);
  const auto lowered = RunFilter<Image3D<double>>(speck.GetPointer(), Settings(-1.0, 1, SideEnum::Above));
  EXPECT_TRUE(std::isfinite(lowered->GetOutput()->GetBufferPointer()[13]));
  EXPECT_NEAR(lowered->GetOutput()->GetBufferPointer()[13] / -huge, 1.0, 1e-15);

  // Three huge values and three small ones: the mean is half the huge one.
  values.assign(n * n * n, 0.0);
  for (const unsigned v : { 4u, 10u, 12u })
  {
    values[v] = huge;
  }
  for (const unsigned v : { 14u, 16u, 22u })
  {
    values[v] = 1.0;
  }
  const auto mixed = MakeImage<double, 3>({ n, n, n }, values);
  const auto halved = RunFilter<Image3D<double>>(mixed.GetPointer(), Settings(0.5, 1, SideEnum::Below));
  EXPECT_NEAR(halved->GetOutput()->GetBufferPointer()[13] / (huge / 2), 1.0, 1e-15);
  EXPECT_EQ(Values(halved->GetOutput()),
            Reference::Run<double>(mixed.GetPointer(), Settings(0.5, 1, SideEnum::Below)).Output);
}

TEST(SmallIsoComponentBehaviour, ZeroMaximumSizeChangesNothingButCounts)
{
  const auto c = MakeRandomCase<uint8_t, uint8_t, 3>(424242);
  auto       settings = c.Settings;
  settings.MaximumComponentSize = 0;
  settings.Side = SideEnum::Both;
  const auto filter = RunFilter<Image3D<uint8_t>>(c.Input.GetPointer(), settings);
  EXPECT_EQ(Values(filter->GetOutput()), c.Values) << c.Description;
  EXPECT_EQ(Values(filter->GetRemovedMask()), std::vector<uint8_t>(c.Values.size(), 0));
  const auto counts = Reference::CountComponents(c.Input.GetPointer(), settings.IsoValue, settings.FullyConnected);
  EXPECT_GT(counts.Above.Components + counts.Below.Components, 1u) << c.Description;
  EXPECT_EQ(filter->GetNumberOfComponents(SideEnum::Above), counts.Above.Components);
  EXPECT_EQ(filter->GetNumberOfComponents(SideEnum::Below), counts.Below.Components);
  EXPECT_EQ(filter->GetComponentSizeHistogram(SideEnum::Above), counts.Above.Histogram);
  EXPECT_EQ(filter->GetComponentSizeHistogram(SideEnum::Below), counts.Below.Histogram);
  for (const SideEnum side : { SideEnum::Above, SideEnum::Below })
  {
    EXPECT_EQ(filter->GetNumberOfRemovedComponents(side), 0u);
    EXPECT_EQ(filter->GetNumberOfRemovedVoxels(side), 0u);
  }
  EXPECT_EQ(filter->GetNumberOfModifiedVoxels(), 0u);
  EXPECT_EQ(filter->GetNumberOfUnrepairableVoxels(), 0u);
  EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 0u);
}

TEST(SmallIsoComponentBehaviour, OneVoxelImage)
{
  // Nothing to walk to: the above pass gives the fallback below σ (99), the below pass
  // then sees a one-voxel below component and gives the fallback above σ (100). Each
  // fallback counts as an unrepairable voxel.
  const auto image2D = MakeImage2D<uint8_t>(1, 1, { 200 });
  const auto both = RunFilter<Image2D<uint8_t>>(image2D.GetPointer(), Settings(100, 20, SideEnum::Both));
  EXPECT_EQ(both->GetOutput()->GetBufferPointer()[0], 100);
  EXPECT_EQ(both->GetRemovedMask()->GetBufferPointer()[0], 2);
  EXPECT_EQ(both->GetNumberOfRemovedComponents(SideEnum::Above), 1u);
  EXPECT_EQ(both->GetNumberOfRemovedComponents(SideEnum::Below), 1u);
  EXPECT_EQ(both->GetNumberOfModifiedVoxels(), 1u);
  EXPECT_EQ(both->GetNumberOfUnrepairableVoxels(), 2u);

  const auto image3D = MakeImage<float, 3>({ 1, 1, 1 }, { 200.0f });
  const auto above = RunFilter<Image3D<float>>(image3D.GetPointer(), Settings(100, 1, SideEnum::Above));
  EXPECT_EQ(above->GetOutput()->GetBufferPointer()[0], std::nextafter(100.0f, 0.0f));
  EXPECT_EQ(above->GetRemovedMask()->GetBufferPointer()[0], 1);
  EXPECT_EQ(above->GetNumberOfUnrepairableVoxels(), 1u);
  EXPECT_EQ(above->GetComponentSizeHistogram(SideEnum::Below), Histogram{});

  const auto kept = RunFilter<Image3D<float>>(image3D.GetPointer(), Settings(100, 0, SideEnum::Both));
  EXPECT_EQ(kept->GetOutput()->GetBufferPointer()[0], 200.0f);
  EXPECT_EQ(kept->GetNumberOfComponents(SideEnum::Above), 1u);
  EXPECT_EQ(kept->GetNumberOfComponents(SideEnum::Below), 0u);
}

TEST(SmallIsoComponentBehaviour, ImageAllAboveIsoValue)
{
  std::vector<uint8_t> values(4 * 4 * 4);
  for (SizeValueType v = 0; v < values.size(); ++v)
  {
    values[v] = static_cast<uint8_t>(150 + v);
  }
  const auto input = MakeImage<uint8_t, 3>({ 4, 4, 4 }, values);

  // The only component is bigger than K: nothing happens.
  const auto big = RunFilter<Image3D<uint8_t>>(input.GetPointer(), Settings(100, 63, SideEnum::Both));
  EXPECT_EQ(Values(big->GetOutput()), values);
  EXPECT_EQ(big->GetComponentSizeHistogram(SideEnum::Above), (Histogram{ { 64, 1 } }));
  EXPECT_EQ(big->GetNumberOfComponents(SideEnum::Below), 0u);
  EXPECT_EQ(big->GetNumberOfModifiedVoxels(), 0u);

  // K covers the image: no walk finds a below voxel, all get the fallback 99.
  const auto small = RunFilter<Image3D<uint8_t>>(input.GetPointer(), Settings(100, 64, SideEnum::Above));
  EXPECT_EQ(Values(small->GetOutput()), std::vector<uint8_t>(64, 99));
  EXPECT_EQ(small->GetNumberOfUnrepairableVoxels(), 64u);
  EXPECT_EQ(small->GetNumberOfRemovedVoxels(SideEnum::Above), 64u);

  // With σ <= 0 no uint8 value is below σ: the component cannot be removed.
  for (const double iso : { 0.0, -3.5 })
  {
    const auto stuck = RunFilter<Image3D<uint8_t>>(input.GetPointer(), Settings(iso, 64, SideEnum::Both));
    EXPECT_EQ(Values(stuck->GetOutput()), values);
    EXPECT_EQ(Values(stuck->GetRemovedMask()), std::vector<uint8_t>(64, 0));
    EXPECT_EQ(stuck->GetNumberOfRemovedComponents(SideEnum::Above), 0u);
    EXPECT_EQ(stuck->GetNumberOfUnrepairableVoxels(), 64u);
    EXPECT_EQ(stuck->GetNumberOfModifiedVoxels(), 0u);
  }

  // The mirror case: σ above 255 puts every voxel below and nothing can go above.
  const auto allBelow = RunFilter<Image3D<uint8_t>>(input.GetPointer(), Settings(255.5, 64, SideEnum::Below));
  EXPECT_EQ(Values(allBelow->GetOutput()), values);
  EXPECT_EQ(allBelow->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 64, 1 } }));
  EXPECT_EQ(allBelow->GetNumberOfRemovedComponents(SideEnum::Below), 0u);
  EXPECT_EQ(allBelow->GetNumberOfUnrepairableVoxels(), 64u);
}

TEST(SmallIsoComponentBehaviour, SamplesEqualToIsoValueAreAbove)
{
  // clang-format off
  const auto input = MakeImage2D<uint8_t>(3, 3, {
    10, 10, 10,
    10, 50, 10,
    10, 10, 12 });
  // clang-format on
  const auto equal = RunFilter<Image2D<uint8_t>>(input.GetPointer(), Settings(50, 1, SideEnum::Above));
  EXPECT_EQ(equal->GetOutput()->GetBufferPointer()[4], 10);
  const auto justAbove = RunFilter<Image2D<uint8_t>>(input.GetPointer(), Settings(50.001, 1, SideEnum::Above));
  EXPECT_EQ(justAbove->GetOutput()->GetBufferPointer()[4], 50);
  EXPECT_EQ(justAbove->GetNumberOfComponents(SideEnum::Above), 0u);
}

TEST(SmallIsoComponentBehaviour, DiagonalNeighboursConnectOnlyWhenFullyConnected)
{
  // Two voxels touching at a corner in 3D: two components of one voxel with face
  // connectivity, one of two voxels with full connectivity.
  std::vector<uint8_t> values(27, 0);
  values[0] = 100;  // (0, 0, 0)
  values[13] = 100; // (1, 1, 1)
  const auto input = MakeImage<uint8_t, 3>({ 3, 3, 3 }, values);
  const auto face = RunFilter<Image3D<uint8_t>>(input.GetPointer(), Settings(50, 1, SideEnum::Above, false));
  EXPECT_EQ(face->GetComponentSizeHistogram(SideEnum::Above), (Histogram{ { 1, 2 } }));
  EXPECT_EQ(face->GetNumberOfRemovedVoxels(SideEnum::Above), 2u);
  const auto full = RunFilter<Image3D<uint8_t>>(input.GetPointer(), Settings(50, 1, SideEnum::Above, true));
  EXPECT_EQ(full->GetComponentSizeHistogram(SideEnum::Above), (Histogram{ { 2, 1 } }));
  EXPECT_EQ(full->GetNumberOfRemovedVoxels(SideEnum::Above), 0u);
  EXPECT_EQ(Values(full->GetOutput()), values);
}

TEST(SmallIsoComponentBehaviour, MaximumComponentVolumeWithAnisotropicSpacing)
{
  // Two specks of 20 and 21 voxels; with spacing (1, 1, 1.4) a volume of 28 is 20 voxels.
  const SizeValueType  n = 12;
  std::vector<uint8_t> values(n * n * n, 0);
  const auto           at = [n](SizeValueType x, SizeValueType y, SizeValueType z) { return x + n * (y + n * z); };
  for (SizeValueType k = 0; k < 20; ++k)
  {
    values[at(1 + k % 5, 1 + k / 5, 1)] = 100;
  }
  for (SizeValueType k = 0; k < 21; ++k)
  {
    values[at(1 + k % 7, 1 + k / 7, 8)] = 100;
  }
  auto         input = MakeImage<uint8_t, 3>({ n, n, n }, values);
  const double spacing[3] = { 1.0, 1.0, 1.4 };
  input->SetSpacing(spacing);

  using FilterType = itk::SmallIsoComponentImageFilter<Image3D<uint8_t>>;
  auto filter = FilterType::New();
  filter->SetInput(input);
  filter->SetIsoValue(50);
  filter->SetSide(SideEnum::Above);
  filter->SetMaximumComponentSize(5);
  filter->SetMaximumComponentVolume(28.0);
  filter->Update();
  EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 20u);
  EXPECT_EQ(filter->GetNumberOfRemovedComponents(SideEnum::Above), 1u);
  EXPECT_EQ(filter->GetNumberOfRemovedVoxels(SideEnum::Above), 20u);

  // Set last wins: the size again.
  filter->SetMaximumComponentSize(5);
  filter->Update();
  EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 5u);
  EXPECT_EQ(filter->GetNumberOfRemovedComponents(SideEnum::Above), 0u);

  // Just under 20 voxels' volume: K = 19.
  filter->SetMaximumComponentVolume(27.9);
  filter->Update();
  EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 19u);
  EXPECT_EQ(filter->GetNumberOfRemovedComponents(SideEnum::Above), 0u);

  // 21 voxels' volume and a little more removes both.
  filter->SetMaximumComponentVolume(29.5);
  filter->Update();
  EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 21u);
  EXPECT_EQ(filter->GetNumberOfRemovedVoxels(SideEnum::Above), 41u);
}

TEST(SmallIsoComponentBehaviour, VolumeOfWholeVoxelsIsNotRoundedDown)
{
  // k voxels of volume 0.001 have volume 0.001 k, but 0.1^3 and 0.001 k in floating point
  // give a quotient just below k for some k. A user asking for that volume means k voxels.
  auto         input = MakeImage<uint8_t, 3>({ 2, 2, 2 }, std::vector<uint8_t>(8, 0));
  const double spacing[3] = { 0.1, 0.1, 0.1 };
  input->SetSpacing(spacing);
  auto filter = itk::SmallIsoComponentImageFilter<Image3D<uint8_t>>::New();
  filter->SetInput(input);
  for (SizeValueType k = 1; k <= 100; ++k)
  {
    filter->SetMaximumComponentVolume(static_cast<double>(k) * 0.001);
    filter->Update();
    EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), k);
  }
}

TEST(SmallIsoComponentBehaviour, MetadataPassesThrough)
{
  auto         c = MakeRandomCase<float, float, 3>(777);
  auto         input = c.Input;
  const double spacing[3] = { 0.5, 0.75, 1.4 };
  const double origin[3] = { -3.0, 4.25, 10.5 };
  input->SetSpacing(spacing);
  input->SetOrigin(origin);
  Image3D<float>::DirectionType direction;
  direction.Fill(0.0);
  direction[0][1] = 1.0;
  direction[1][2] = -1.0;
  direction[2][0] = 1.0;
  input->SetDirection(direction);
  // A region that does not start at 0.
  auto region = input->GetBufferedRegion();
  region.SetIndex({ { 5, -2, 3 } });
  input->SetRegions(region);

  const auto filter = RunFilter<Image3D<float>>(input.GetPointer(), c.Settings, 2);
  for (const itk::ImageBase<3> * output : { static_cast<const itk::ImageBase<3> *>(filter->GetOutput()),
                                            static_cast<const itk::ImageBase<3> *>(filter->GetRemovedMask()) })
  {
    EXPECT_EQ(output->GetSpacing(), input->GetSpacing());
    EXPECT_EQ(output->GetOrigin(), input->GetOrigin());
    EXPECT_EQ(output->GetDirection(), input->GetDirection());
    EXPECT_EQ(output->GetLargestPossibleRegion(), region);
    EXPECT_EQ(output->GetBufferedRegion(), region);
  }
  const auto expected = Reference::Run<float>(input.GetPointer(), c.Settings);
  EXPECT_EQ(DifferencesFromReference(filter.GetPointer(), expected, c.Settings.MaximumComponentSize), "")
    << c.Description;
}

TEST(SmallIsoComponentBehaviour, Int16InFloatOut)
{
  // The mean is not rounded for a float output: 8.5 stays 8.5, where int16 gives 9.
  // clang-format off
  const auto input = MakeImage2D<int16_t>(3, 3, {
    -3, 8,   -1,
     7, 300, 10,
    -4, 9,   -7 });
  // clang-format on
  const auto toFloat =
    RunFilter<Image2D<int16_t>, Image2D<float>>(input.GetPointer(), Settings(10.5, 1, SideEnum::Above));
  EXPECT_EQ(toFloat->GetOutput()->GetBufferPointer()[4], 8.5f); // (7 + 10 + 8 + 9) / 4
  EXPECT_EQ(toFloat->GetOutput()->GetBufferPointer()[0], -3.0f);
  const auto toInt16 = RunFilter<Image2D<int16_t>>(input.GetPointer(), Settings(10.5, 1, SideEnum::Above));
  EXPECT_EQ(toInt16->GetOutput()->GetBufferPointer()[4], 9);

  // Values beyond int8 or uint8 survive the conversion exactly.
  const auto wide = MakeImage2D<int16_t>(3, 1, { 32767, -30000, 30001 });
  const auto wideFilter =
    RunFilter<Image2D<int16_t>, Image2D<float>>(wide.GetPointer(), Settings(25000, 1, SideEnum::Below));
  EXPECT_EQ(Values(wideFilter->GetOutput()), (std::vector<float>{ 32767.0f, 31384.0f, 30001.0f }));
  EXPECT_EQ(wideFilter->GetComponentSizeHistogram(SideEnum::Below), (Histogram{ { 1, 1 } }));
}

TEST(SmallIsoComponentBehaviour, InPlaceGivesTheSameResult)
{
  for (const uint32_t seed : { 31u, 32u, 33u, 34u, 35u, 36u })
  {
    const auto c = MakeRandomCase<int16_t, int16_t, 3>(seed);
    const auto notInPlace = RunFilter<Image3D<int16_t>>(c.Input.GetPointer(), c.Settings, 2, false);

    const auto      copy = MakeImage<int16_t, 3>(c.Size, c.Values);
    const int16_t * buffer = copy->GetBufferPointer();
    const auto      inPlace = RunFilter<Image3D<int16_t>>(copy.GetPointer(), c.Settings, 2, true);
    EXPECT_EQ(inPlace->GetOutput()->GetBufferPointer(), buffer) << "the filter did not run in place";
    EXPECT_EQ(Values(inPlace->GetOutput()), Values(notInPlace->GetOutput())) << c.Description;
    EXPECT_EQ(Values(inPlace->GetRemovedMask()), Values(notInPlace->GetRemovedMask())) << c.Description;
    const auto expected = Reference::Run<int16_t>(c.Input.GetPointer(), c.Settings);
    EXPECT_EQ(DifferencesFromReference(inPlace.GetPointer(), expected, c.Settings.MaximumComponentSize), "")
      << c.Description;
  }
}
