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

// The bookkeeping of an update: the size histogram (small sizes in an array, large ones in
// the map) against a plain count, and the peak of the memory the phases report.

#include "itkSmallIsoComponentPeakMemory.h"
#include "itkSmallIsoComponentSizeCounter.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"

#include <map>
#include <vector>

namespace
{
using itk::SizeValueType;
namespace Detail = itk::SmallIsoComponentDetail;
} // namespace

TEST(SmallIsoComponentSizeCounter, HistogramOfSmallAndLargeSizes)
{
  itk::SmallIsoComponentTest::RandomSource random(51);
  Detail::SizeCounter                      counter;
  std::map<SizeValueType, SizeValueType>   expected;
  for (unsigned int i = 0; i < 20000; ++i)
  {
    const auto size = static_cast<SizeValueType>(random.Chance(0.9) ? random.Between(1, 5000)
                                                                    : random.Between(4090, 4100) * (1 + i % 3));
    counter.Add(size);
    ++expected[size];
  }
  counter.Add(SizeValueType{ 1 } << 40);
  ++expected[SizeValueType{ 1 } << 40];
  EXPECT_EQ(counter.Histogram(), expected);
  EXPECT_TRUE(Detail::SizeCounter().Histogram().empty());

  // Counters of two parts, added: the counts of both, small and large sizes.
  Detail::SizeCounter                    first;
  Detail::SizeCounter                    second;
  std::map<SizeValueType, SizeValueType> both;
  for (unsigned int i = 0; i < 5000; ++i)
  {
    const auto size =
      static_cast<SizeValueType>(random.Chance(0.8) ? random.Between(1, 4095) : random.Between(4096, 4200));
    (i % 3 == 0 ? first : second).Add(size);
    ++both[size];
  }
  first.Add(second);
  EXPECT_EQ(first.Histogram(), both);
}

TEST(SmallIsoComponentPeakMemory, PeakOfWhatThePhasesHold)
{
  Detail::PeakMemory memory;
  EXPECT_EQ(memory.GetPeakInBytes(), 0u);
  std::vector<uint8_t>  flags(100);
  std::vector<uint32_t> indices(10);
  std::vector<double>   values;
  values.reserve(3);
  memory.Hold(1000, flags, indices, values);
  EXPECT_EQ(memory.GetPeakInBytes(), 1000 + flags.capacity() + 4 * indices.capacity() + 8 * values.capacity());
  const SizeValueType peak = memory.GetPeakInBytes();
  memory.Hold(10);
  EXPECT_EQ(memory.GetPeakInBytes(), peak) << "a smaller report lowered the peak";
  memory.Hold(peak + 1);
  EXPECT_EQ(memory.GetPeakInBytes(), peak + 1);
  memory.Reset();
  EXPECT_EQ(memory.GetPeakInBytes(), 0u);
}
