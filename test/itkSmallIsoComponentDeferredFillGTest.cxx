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

// The output and mask writing that the encoding leaves for later, and the streaming stores
// it uses: every byte of every block written once and nothing outside, at every alignment,
// for lines shorter and longer than a block, in place or not.

#include "itkSmallIsoComponentDeferredFill.h"
#include "itkSmallIsoComponentStreamingStores.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <numeric>
#include <vector>

namespace
{
using itk::SizeValueType;
namespace Detail = itk::SmallIsoComponentDetail;

constexpr SizeValueType Guard = 80;

std::vector<uint8_t>
RandomBytes(itk::SmallIsoComponentTest::RandomSource & random, SizeValueType count)
{
  std::vector<uint8_t> bytes(count);
  for (auto & b : bytes)
  {
    b = static_cast<uint8_t>(random.Bits());
  }
  return bytes;
}
} // namespace

TEST(SmallIsoComponentStreamingStores, CopyAndZeroEveryByteAtEveryAlignment)
{
  itk::SmallIsoComponentTest::RandomSource random(41);
  for (SizeValueType offset = 0; offset < 64; ++offset)
  {
    for (SizeValueType bytes = 0; bytes < 300; bytes += 1 + bytes / 16)
    {
      const std::vector<uint8_t> source = RandomBytes(random, bytes + 2 * Guard);
      std::vector<uint8_t>       copied(bytes + 2 * Guard, 0xAB);
      Detail::StreamCopy(copied.data() + offset, source.data() + Guard, bytes);
      std::vector<uint8_t> zeroed(bytes + 2 * Guard, 0xCD);
      Detail::StreamZero(zeroed.data() + offset, bytes);
      Detail::StreamFence();
      for (SizeValueType i = 0; i < copied.size(); ++i)
      {
        const bool inside = i >= offset && i < offset + bytes;
        ASSERT_EQ(copied[i], inside ? source[Guard + i - offset] : 0xAB) << "offset " << offset << " bytes " << bytes;
        ASSERT_EQ(zeroed[i], inside ? 0 : 0xCD) << "offset " << offset << " bytes " << bytes;
      }
    }
  }
}

TEST(SmallIsoComponentDeferredFill, EveryBlockOfLinesCopiedAndClearedOnce)
{
  itk::SmallIsoComponentTest::RandomSource random(42);
  const Detail::DeferredFill               nothing;
  EXPECT_TRUE(nothing.IsEmpty());
  EXPECT_EQ(nothing.GetNumberOfBlocks(), 0u);
  for (unsigned int trial = 0; trial < 40; ++trial)
  {
    // Lines from one byte to more than a block, output pixels of 1 to 8 bytes.
    const auto          length = static_cast<SizeValueType>(random.Pick(std::array<int, 5>{ 1, 7, 64, 1000, 70000 }));
    const auto          pixelBytes = static_cast<SizeValueType>(random.Pick(std::array<int, 4>{ 1, 2, 4, 8 }));
    const auto          lines = static_cast<SizeValueType>(random.Between(1, length > 1000 ? 12 : 300));
    const bool          inPlace = random.Chance(0.3);
    const SizeValueType outputBytes = lines * length * pixelBytes;
    const SizeValueType maskBytes = lines * length;
    const auto          offset = static_cast<SizeValueType>(random.Between(0, 63));

    const std::vector<uint8_t> source = RandomBytes(random, outputBytes);
    std::vector<uint8_t>       output(outputBytes + 2 * Guard, 0xAB);
    std::vector<uint8_t>       mask(maskBytes + 2 * Guard, 0xCD);
    if (inPlace)
    {
      std::copy(source.begin(), source.end(), output.begin() + offset);
    }
    uint8_t * const            outputStart = output.data() + offset;
    const Detail::DeferredFill fill(
      inPlace ? outputStart : source.data(), outputStart, length * pixelBytes, mask.data() + Guard, length, lines);
    ASSERT_FALSE(fill.IsEmpty());
    const SizeValueType linesPerBlock =
      std::max<SizeValueType>(1, itk::SmallIsoComponentDetail::Tuning::FillBlockBytes / (length * (pixelBytes + 1)));
    ASSERT_EQ(fill.GetNumberOfBlocks(), (lines + linesPerBlock - 1) / linesPerBlock);

    // The blocks in a random order, as the work units take them.
    std::vector<SizeValueType> blocks(fill.GetNumberOfBlocks());
    std::iota(blocks.begin(), blocks.end(), 0);
    for (SizeValueType i = blocks.size(); i > 1; --i)
    {
      std::swap(blocks[i - 1], blocks[random.Bits() % i]);
    }
    for (const SizeValueType block : blocks)
    {
      fill.FillBlock(block);
    }
    for (SizeValueType i = 0; i < output.size(); ++i)
    {
      const bool inside = i >= offset && i < offset + outputBytes;
      ASSERT_EQ(output[i], inside ? source[i - offset] : 0xAB) << "trial " << trial << " output byte " << i;
    }
    for (SizeValueType i = 0; i < mask.size(); ++i)
    {
      const bool inside = i >= Guard && i < Guard + maskBytes;
      ASSERT_EQ(mask[i], inside ? 0 : 0xCD) << "trial " << trial << " mask byte " << i;
    }
  }
}
