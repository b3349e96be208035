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

// The encoding of scanlines as runs: for every pixel type with SIMD compares, the SIMD
// path (with SSE2 and, where the processor has it, with AVX-512) against the search path and against a voxel-by-voxel
// encoding, on lines of every length up to past two 64-voxel words, with a change of side at every position, NaN, and
// thresholds at the limits of the type; the other types against the voxel-by-voxel
// encoding.

#include "itkSmallIsoComponentRunEncoder.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace
{
using itk::SizeValueType;
using itk::SmallIsoComponentDetail::RunEncoder;
using CoordinateType = itk::SmallIsoComponentDetail::RunLabeling::CoordinateType;

/** The encoder with its AVX-512 switch, which only the tests turn. */
template <typename T>
class TestRunEncoder : public RunEncoder<T>
{
public:
  using RunEncoder<T>::RunEncoder;
  using RunEncoder<T>::SetAvx512;
};

/** The runs of a line by definition: a run starts at 0 and wherever a voxel's side
 * (f >= σ as double; NaN below) differs from the voxel before. */
template <typename T>
std::vector<CoordinateType>
NaiveStarts(const std::vector<T> & line, double isoValue, bool & firstAbove)
{
  std::vector<CoordinateType> starts{ 0 };
  firstAbove = static_cast<double>(line[0]) >= isoValue;
  for (SizeValueType x = 1; x < line.size(); ++x)
  {
    if ((static_cast<double>(line[x]) >= isoValue) != (static_cast<double>(line[x - 1]) >= isoValue))
    {
      starts.push_back(static_cast<CoordinateType>(x));
    }
  }
  return starts;
}

template <typename T>
std::string
LineToString(const std::vector<T> & line)
{
  std::ostringstream out;
  for (const T value : line)
  {
    out << " " << +value;
  }
  return out.str();
}

/** Empty when every path of the encoder encodes \a line as the definition does, with
 * AVX-512 and without (where the processor has it), and CountRuns() counts its runs: EncodeLine()
 * and the search, appending after what \a starts holds already (as the encoder appends a slab's
 * lines one after another), and EncodeLineAndBits() (the path of dense lines) into an array
 * sized as the encoder sizes it (its runs counted), between guard words. */
template <typename T>
std::string
EncodingDifference(const std::vector<T> & line, double isoValue)
{
  bool                              expectedFirstAbove = false;
  const std::vector<CoordinateType> expected = NaiveStarts(line, isoValue, expectedFirstAbove);
  std::vector<uint64_t>             expectedBits((line.size() + 63) / 64, 0);
  for (const CoordinateType start : expected)
  {
    expectedBits[start / 64] |= uint64_t{ 1 } << (start % 64);
  }
  std::ostringstream out;
  for (const bool avx512 : { false, true })
  {
    TestRunEncoder<T> encoder(isoValue);
    encoder.SetAvx512(avx512);
    const std::string way = encoder.GetAvx512() ? " (AVX-512)" : "";
    for (const bool bySearch : { false, true })
    {
      std::vector<CoordinateType> starts{ 7, 7 };
      const bool                  firstAbove = bySearch ? encoder.EncodeLineBySearch(line.data(), line.size(), starts)
                                                        : encoder.EncodeLine(line.data(), line.size(), starts);
      starts.erase(starts.begin(), starts.begin() + 2);
      if (starts != expected || firstAbove != expectedFirstAbove)
      {
        out << (bySearch ? "search" : "EncodeLine") << " path" << way << ": " << starts.size() << " runs, first above "
            << firstAbove << "; expected " << expected.size() << " runs, first above " << expectedFirstAbove << "; iso "
            << isoValue << "; line" << LineToString(line) << "\n";
      }
    }
    constexpr CoordinateType    guard = 0xDEADBEEF;
    std::vector<CoordinateType> starts(expected.size() + 2, guard);
    std::vector<uint64_t>       bits(expectedBits.size() + 2, ~uint64_t{ 0 });
    encoder.EncodeLineAndBits(line.data(), line.size(), starts.data() + 1, bits.data() + 1);
    const std::vector<CoordinateType> written(starts.begin() + 1, starts.end() - 1);
    const std::vector<uint64_t>       writtenBits(bits.begin() + 1, bits.end() - 1);
    if (written != expected || writtenBits != expectedBits || starts.front() != guard || starts.back() != guard ||
        bits.front() != ~uint64_t{ 0 } || bits.back() != ~uint64_t{ 0 })
    {
      out << "EncodeLineAndBits" << way
          << ": starts or bits differ from the definition, or were written past their ends; iso " << isoValue
          << "; line" << LineToString(line) << "\n";
    }
    if (encoder.CountRuns(line.data(), line.size()) != expected.size())
    {
      out << "CountRuns" << way << ": " << encoder.CountRuns(line.data(), line.size()) << " runs; expected "
          << expected.size() << "; iso " << isoValue << "; line" << LineToString(line) << "\n";
    }
  }
  return out.str();
}

/** A value of T above and one below the isovalue, varied so that the SIMD compares meet
 * the extremes of the type, and NaN for floating point. */
template <typename T>
struct SideValues
{
  double isoValue;
  T      above[3];
  T      below[3];
};

template <typename T>
std::vector<SideValues<T>>
SideValueSets()
{
  using Limits = std::numeric_limits<T>;
  std::vector<SideValues<T>> sets;
  if constexpr (std::is_integral<T>::value)
  {
    const T lowest = Limits::lowest();
    const T highest = Limits::max();
    const T middle = static_cast<T>(lowest / 2 + highest / 2);
    // σ between two values, σ on a value, σ at the lowest value (nothing below) and at the
    // highest (only it above).
    sets.push_back({ static_cast<double>(middle) + 0.5,
                     { highest, static_cast<T>(middle + 1), static_cast<T>(middle + 2) },
                     { lowest, middle, static_cast<T>(middle - 1) } });
    sets.push_back({ static_cast<double>(middle),
                     { middle, highest, static_cast<T>(middle + 1) },
                     { static_cast<T>(middle - 1), lowest, static_cast<T>(lowest + 1) } });
    sets.push_back(
      { static_cast<double>(highest), { highest, highest, highest }, { static_cast<T>(highest - 1), lowest, middle } });
    sets.push_back({ static_cast<double>(lowest) + 0.5,
                     { static_cast<T>(lowest + 1), highest, middle },
                     { lowest, lowest, lowest } });
  }
  else
  {
    const T nan = Limits::quiet_NaN();
    sets.push_back(
      { 0.1, { T(0.1000001), Limits::max(), Limits::infinity() }, { T(0.0999999), nan, -Limits::infinity() } });
    sets.push_back(
      { 0.0, { T(0.0), Limits::denorm_min(), T(-0.0) }, { -Limits::denorm_min(), nan, Limits::lowest() } });
    sets.push_back({ std::numeric_limits<double>::infinity(),
                     { Limits::infinity(), Limits::infinity(), Limits::infinity() },
                     { Limits::max(), nan, T(0) } });
  }
  return sets;
}

/** Every length 1..130 with a single change of side at every position, random lines, and
 * lines that change at every voxel, for each set of side values. */
template <typename T>
void
CheckEncodings(uint32_t seed)
{
  itk::SmallIsoComponentTest::RandomSource random(seed);
  unsigned int                             failures = 0;
  for (const SideValues<T> & values : SideValueSets<T>())
  {
    const auto pick = [&](bool above) {
      return above ? values.above[random.Bits() % 3] : values.below[random.Bits() % 3];
    };
    for (SizeValueType length = 1; length <= 130; ++length)
    {
      std::vector<std::vector<T>> lines;
      for (SizeValueType change = 0; change <= length; ++change)
      {
        for (const bool firstAbove : { false, true })
        {
          std::vector<T> line(length);
          for (SizeValueType x = 0; x < length; ++x)
          {
            line[x] = pick((x < change) == firstAbove);
          }
          lines.push_back(line);
        }
      }
      for (const double changeRate : { 0.02, 0.2, 0.5, 1.0 })
      {
        std::vector<T> line(length);
        bool           above = random.Chance(0.5);
        for (SizeValueType x = 0; x < length; ++x)
        {
          above = random.Chance(changeRate) ? !above : above;
          line[x] = pick(above);
        }
        lines.push_back(line);
      }
      for (const auto & line : lines)
      {
        const std::string difference = EncodingDifference(line, values.isoValue);
        if (!difference.empty() && failures++ < 5)
        {
          ADD_FAILURE() << difference;
        }
      }
    }
  }
  EXPECT_EQ(failures, 0u);
}
} // namespace

TEST(SmallIsoComponentRunEncoder, SimdTypesEncodeEveryLineAsTheSearchAndTheDefinitionDo)
{
#if defined(__SSE2__)
  // The comparison is between two different paths only where SSE2 is there.
  EXPECT_TRUE(RunEncoder<uint8_t>::UsesSimd);
  EXPECT_TRUE(RunEncoder<int8_t>::UsesSimd);
  EXPECT_TRUE(RunEncoder<uint16_t>::UsesSimd);
  EXPECT_TRUE(RunEncoder<int16_t>::UsesSimd);
  EXPECT_TRUE(RunEncoder<float>::UsesSimd);
#endif
  CheckEncodings<uint8_t>(11);
  CheckEncodings<int8_t>(12);
  CheckEncodings<uint16_t>(13);
  CheckEncodings<int16_t>(14);
  CheckEncodings<float>(15);
}

TEST(SmallIsoComponentRunEncoder, OtherTypesEncodeEveryLineAsTheDefinitionDoes)
{
  EXPECT_FALSE(RunEncoder<int32_t>::UsesSimd);
  EXPECT_FALSE(RunEncoder<double>::UsesSimd);
  CheckEncodings<int32_t>(21);
  CheckEncodings<uint32_t>(22);
  CheckEncodings<double>(23);
}

TEST(SmallIsoComponentRunEncoder, Avx512IsUsedWhereTheProcessorHasIt)
{
  // Where it has not, the comparisons above compared the SSE2 path with itself: say so.
  TestRunEncoder<uint8_t> encoder(127.5);
  if (!encoder.GetAvx512())
  {
    GTEST_SKIP() << "this processor has no AVX-512: only the SSE2 path was compared";
  }
  encoder.SetAvx512(false);
  EXPECT_FALSE(encoder.GetAvx512());
  encoder.SetAvx512(true);
  EXPECT_TRUE(encoder.GetAvx512());
}

TEST(SmallIsoComponentRunEncoder, NothingAboveIsOneBelowRunPerLine)
{
  // σ above every value of the type: no value is above, and every line is one below run.
  const RunEncoder<uint8_t>   encoder(255.5);
  const std::vector<uint8_t>  line{ 255, 0, 255, 255, 1, 200, 255, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 3 };
  std::vector<CoordinateType> starts;
  EXPECT_FALSE(encoder.EncodeLine(line.data(), line.size(), starts));
  EXPECT_EQ(starts, std::vector<CoordinateType>{ 0 });
}
