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

// The classification of pixels by the isovalue: which side a value is on, the values
// closest to σ on each side, and the search for the next change of side, against the
// definition (f >= σ compared as double, NaN below) at the limits of every pixel type.

#include "itkSmallIsoComponentThreshold.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"

#include <cmath>
#include <limits>
#include <vector>

namespace
{
using itk::SizeValueType;
using itk::SmallIsoComponentDetail::Threshold;

template <typename T>
bool
AboveByDefinition(T value, double isoValue)
{
  return static_cast<double>(value) >= isoValue;
}

/** Values at the limits of T and next to the isovalue, and a few in between. */
template <typename T>
std::vector<T>
Probes(double isoValue)
{
  using Limits = std::numeric_limits<T>;
  std::vector<T> probes{ Limits::lowest(), Limits::max(), T(0), T(1) };
  if constexpr (std::is_signed<T>::value)
  {
    probes.push_back(T(-1));
  }
  if constexpr (std::is_integral<T>::value)
  {
    probes.push_back(static_cast<T>(Limits::lowest() + 1));
    probes.push_back(static_cast<T>(Limits::max() - 1));
    if (isoValue > static_cast<double>(Limits::lowest()) + 2 && isoValue < static_cast<double>(Limits::max()) - 2)
    {
      const auto below = static_cast<T>(std::floor(isoValue));
      for (int d = -2; d <= 2; ++d)
      {
        probes.push_back(static_cast<T>(below + d));
      }
    }
  }
  else
  {
    probes.push_back(Limits::infinity());
    probes.push_back(-Limits::infinity());
    probes.push_back(Limits::denorm_min());
    probes.push_back(-Limits::denorm_min());
    probes.push_back(T(-0.0));
    if (std::isfinite(isoValue))
    {
      const auto near = static_cast<T>(isoValue);
      probes.push_back(near);
      probes.push_back(std::nextafter(near, Limits::infinity()));
      probes.push_back(std::nextafter(near, -Limits::infinity()));
    }
  }
  return probes;
}

/** Isovalues at and beyond the limits of T, between two values, and on one. */
template <typename T>
std::vector<double>
IsoValues()
{
  using Limits = std::numeric_limits<T>;
  const double        lowest = static_cast<double>(Limits::lowest());
  const double        highest = static_cast<double>(Limits::max());
  std::vector<double> isoValues{ lowest, highest, 0.0, -0.5, 0.5, 1.0, 1e30, -1e30, 0.1, 1.0 / 3.0 };
  if constexpr (std::is_integral<T>::value)
  {
    for (const double d : { -1.0, -0.5, 0.5, 1.0 })
    {
      isoValues.push_back(lowest + d);
      isoValues.push_back(highest + d);
    }
  }
  else
  {
    isoValues.push_back(std::numeric_limits<double>::infinity());
    isoValues.push_back(-std::numeric_limits<double>::infinity());
    isoValues.push_back(static_cast<double>(Limits::denorm_min()) / 2);
    isoValues.push_back(std::nextafter(highest, std::numeric_limits<double>::infinity()));
    isoValues.push_back(-0.0);
  }
  return isoValues;
}

/** The threshold of every isovalue against the definition. */
template <typename T>
void
CheckThresholds()
{
  using Limits = std::numeric_limits<T>;
  for (const double isoValue : IsoValues<T>())
  {
    const Threshold<T> threshold(isoValue);
    SCOPED_TRACE(isoValue);
    EXPECT_EQ(threshold.AnyAbove(),
              AboveByDefinition(Limits::max(), isoValue) ||
                (!std::is_integral<T>::value && AboveByDefinition(Limits::infinity(), isoValue)));
    const T lowestOfAll = std::is_integral<T>::value ? Limits::lowest() : -Limits::infinity();
    EXPECT_EQ(threshold.AnyBelow(), !AboveByDefinition(lowestOfAll, isoValue));
    for (const T value : Probes<T>(isoValue))
    {
      EXPECT_EQ(threshold.IsAbove(value), AboveByDefinition(value, isoValue)) << "value " << +value;
    }
    if constexpr (!std::is_integral<T>::value)
    {
      EXPECT_FALSE(threshold.IsAbove(Limits::quiet_NaN()));
    }
    if (threshold.AnyAbove())
    {
      // The lowest value above: above, and the value before it is not (or there is none).
      const T lowestAbove = threshold.LowestAbove();
      EXPECT_TRUE(AboveByDefinition(lowestAbove, isoValue));
      if (lowestAbove != lowestOfAll)
      {
        const T before = std::is_integral<T>::value ? static_cast<T>(lowestAbove - 1)
                                                    : std::nextafter(lowestAbove, -Limits::infinity());
        EXPECT_FALSE(AboveByDefinition(before, isoValue)) << "lowest above " << +lowestAbove;
      }
    }
    if (threshold.AnyBelow())
    {
      const T highestBelow = threshold.HighestBelow();
      const T highestOfAll = std::is_integral<T>::value ? Limits::max() : Limits::infinity();
      EXPECT_FALSE(AboveByDefinition(highestBelow, isoValue));
      if (highestBelow != highestOfAll)
      {
        const T after = std::is_integral<T>::value ? static_cast<T>(highestBelow + 1)
                                                   : std::nextafter(highestBelow, Limits::infinity());
        EXPECT_TRUE(AboveByDefinition(after, isoValue)) << "highest below " << +highestBelow;
      }
    }
  }
}

/** NextSideChange() on random lines, from random places, against a voxel-by-voxel search. */
template <typename T>
void
CheckNextSideChange(uint32_t seed)
{
  itk::SmallIsoComponentTest::RandomSource random(seed);
  for (unsigned int trial = 0; trial < 400; ++trial)
  {
    const auto     length = static_cast<SizeValueType>(random.Between(1, 300));
    const double   changeRate = random.Pick(std::array<double, 4>{ 0.0, 0.01, 0.1, 0.5 });
    const T        low = std::is_integral<T>::value ? std::numeric_limits<T>::lowest() : T(-1);
    const T        high = std::is_integral<T>::value ? std::numeric_limits<T>::max() : T(1);
    const double   isoValue = random.Chance(0.9) ? 0.5 * (static_cast<double>(low) + static_cast<double>(high))
                                                 : static_cast<double>(high) + 1.0;
    std::vector<T> line(length);
    bool           above = random.Chance(0.5);
    for (SizeValueType x = 0; x < length; ++x)
    {
      above = random.Chance(changeRate) ? !above : above;
      line[x] = above ? high : low;
      if constexpr (!std::is_integral<T>::value)
      {
        line[x] = !above && random.Chance(0.2) ? std::numeric_limits<T>::quiet_NaN() : line[x];
      }
    }
    const Threshold<T>  threshold(isoValue);
    const SizeValueType from = static_cast<SizeValueType>(random.Between(0, static_cast<int64_t>(length)));
    const bool          side = random.Chance(0.5);
    SizeValueType       expected = from;
    while (expected < length && AboveByDefinition(line[expected], isoValue) == side)
    {
      ++expected;
    }
    EXPECT_EQ(threshold.NextSideChange(line.data(), from, length, side), expected)
      << "length " << length << " from " << from << " side " << side << " iso " << isoValue;
  }
}
} // namespace

TEST(SmallIsoComponentThreshold, SidesAndClosestValuesAtTheLimitsOfEveryType)
{
  CheckThresholds<uint8_t>();
  CheckThresholds<int8_t>();
  CheckThresholds<uint16_t>();
  CheckThresholds<int16_t>();
  CheckThresholds<uint32_t>();
  CheckThresholds<int32_t>();
  CheckThresholds<float>();
  CheckThresholds<double>();
}

TEST(SmallIsoComponentThreshold, NextSideChangeFindsTheFirstVoxelOfTheOtherSide)
{
  CheckNextSideChange<uint8_t>(1);
  CheckNextSideChange<int8_t>(2);
  CheckNextSideChange<uint16_t>(3);
  CheckNextSideChange<int16_t>(4);
  CheckNextSideChange<int32_t>(5);
  CheckNextSideChange<uint32_t>(6);
  CheckNextSideChange<float>(7);
  CheckNextSideChange<double>(8);
}
