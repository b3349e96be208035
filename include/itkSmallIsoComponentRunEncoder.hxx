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
#ifndef itkSmallIsoComponentRunEncoder_hxx
#define itkSmallIsoComponentRunEncoder_hxx

#include "itkSmallIsoComponentRunEncoder.h"
#include <cstdint>

namespace itk
{
namespace SmallIsoComponentDetail
{
template <typename TPixel>
SizeValueType
RunEncoder<TPixel>::CountRuns(const TPixel * values, SizeValueType length) const
{
#if defined(__SSE2__)
  if constexpr (UsesSimd)
  {
    SizeValueType runs = 1;
    this->ForEachSideChange(values, length, [&runs](uint64_t change, SizeValueType) {
      runs += static_cast<SizeValueType>(__builtin_popcountll(change));
    });
    return runs;
  }
  else
#endif
  {
    SizeValueType changes = 0;
    for (SizeValueType x = 1; x < length; ++x)
    {
      changes += m_Threshold.IsAbove(values[x]) != m_Threshold.IsAbove(values[x - 1]) ? 1 : 0;
    }
    return changes + 1;
  }
}

template <typename TPixel>
template <typename TAppend>
bool
RunEncoder<TPixel>::EncodeLine(const TPixel * values, SizeValueType length, TAppend && append) const
{
#if defined(__SSE2__)
  if constexpr (UsesSimd)
  {
    append(0);
    return this->ForEachSideChange(values, length, [&](uint64_t change, SizeValueType base) {
      for (; change != 0; change &= change - 1)
      {
        append(static_cast<CoordinateType>(base + static_cast<SizeValueType>(__builtin_ctzll(change))));
      }
    });
  }
  else
#endif
  {
    return this->EncodeLineBySearch(values, length, append);
  }
}

template <typename TPixel>
void
RunEncoder<TPixel>::EncodeLineAndBits(const TPixel *   values,
                                      SizeValueType    length,
                                      CoordinateType * starts,
                                      uint64_t *       bits) const
{
  static_assert(std::is_same<CoordinateType, uint32_t>::value, "WriteBitPositions() writes 32-bit starts.");
  std::fill(bits, bits + (length + 63) / 64, uint64_t{ 0 });
  // Voxel 0 starts the first run.
  bits[0] = 1;
#if defined(__SSE2__)
  if constexpr (UsesSimd)
  {
    *starts++ = 0;
    this->ForEachSideChange(values, length, [&](uint64_t change, SizeValueType base) {
      // Changes come 64 voxels a word from a multiple of 64, or 16 at a time from
      // anywhere near the end: those may reach into the next word.
      const SizeValueType word = base / 64;
      const unsigned int  shift = base % 64;
      bits[word] |= change << shift;
      if (shift != 0 && (change >> (64 - shift)) != 0)
      {
        bits[word + 1] |= change >> (64 - shift);
      }
#  if defined(SMALLISO_AVX512_DISPATCH)
      if (m_Avx512)
      {
        starts = WriteBitPositionsCompressed(starts, change, static_cast<CoordinateType>(base));
        return;
      }
#  endif
      starts = WriteBitPositions(starts, change, static_cast<CoordinateType>(base));
    });
    return;
  }
#endif
  this->EncodeLine(values, length, [&](CoordinateType start) {
    *starts++ = start;
    bits[start / 64] |= uint64_t{ 1 } << (start % 64);
  });
}

#if defined(__SSE2__)
template <typename TPixel>
template <typename TChanges>
bool
RunEncoder<TPixel>::ForEachSideChange(const TPixel * values, SizeValueType length, TChanges && addChanges) const
{
#  if defined(SMALLISO_AVX512_DISPATCH)
  if (m_Avx512)
  {
    return this->ForEachSideChangeAvx512(values, length, addChanges);
  }
#  endif
  return this->ForEachSideChangeSse2(values, length, addChanges);
}

#  if defined(SMALLISO_AVX512_DISPATCH)
template <typename TPixel>
template <typename TChanges>
__attribute__((target("avx512f,avx512bw,popcnt,bmi2"))) bool
RunEncoder<TPixel>::ForEachSideChangeAvx512(const TPixel * values, SizeValueType length, TChanges && addChanges) const
{
  const bool firstAbove = m_Threshold.IsAbove(values[0]);
  if (!m_Threshold.AnyAbove())
  {
    return firstAbove;
  }
  // One bit per voxel, set above the isovalue (v >= the lowest value above it; never for
  // NaN), 64 voxels a word from up to 64 loaded lanes.
  const TPixel lowest = m_Threshold.LowestAbove();
  const auto   above = [lowest](const TPixel * voxels, __mmask64 loaded) __attribute__((target("avx512f,avx512bw")))
                     SMALLISO_LAMBDA_ALWAYS_INLINE->uint64_t
  {
    if constexpr (std::is_same<TPixel, uint8_t>::value || std::is_same<TPixel, int8_t>::value)
    {
      const __m512i v = _mm512_maskz_loadu_epi8(loaded, voxels);
      const __m512i t = _mm512_set1_epi8(static_cast<char>(lowest));
      return std::is_same<TPixel, uint8_t>::value ? _mm512_mask_cmpge_epu8_mask(loaded, v, t)
                                                  : _mm512_mask_cmpge_epi8_mask(loaded, v, t);
    }
    else if constexpr (sizeof(TPixel) == 2)
    {
      const __m512i t = _mm512_set1_epi16(static_cast<short>(lowest));
      uint64_t      bits = 0;
      for (unsigned int half = 0; half < 2; ++half)
      {
        const auto     lanes = static_cast<__mmask32>(loaded >> (32 * half));
        const __m512i  v = _mm512_maskz_loadu_epi16(lanes, voxels + 32 * half);
        const uint64_t marked = std::is_same<TPixel, uint16_t>::value ? _mm512_mask_cmpge_epu16_mask(lanes, v, t)
                                                                      : _mm512_mask_cmpge_epi16_mask(lanes, v, t);
        bits |= marked << (32 * half);
      }
      return bits;
    }
    else
    {
      const __m512 t = _mm512_set1_ps(lowest);
      uint64_t     bits = 0;
      for (unsigned int quarter = 0; quarter < 4; ++quarter)
      {
        const auto   lanes = static_cast<__mmask16>(loaded >> (16 * quarter));
        const __m512 v = _mm512_maskz_loadu_ps(lanes, voxels + 16 * quarter);
        bits |= static_cast<uint64_t>(_mm512_mask_cmp_ps_mask(lanes, v, t, _CMP_GE_OQ)) << (16 * quarter);
      }
      return bits;
    }
  };
  uint64_t      previous = firstAbove ? 1 : 0; // the bit of the voxel before x
  SizeValueType x = 0;
  for (; x + 64 <= length; x += 64)
  {
    const uint64_t bits = above(values + x, ~__mmask64{ 0 });
    const uint64_t change = bits ^ (bits << 1 | previous);
    previous = bits >> 63;
    if (change != 0)
    {
      addChanges(change, x);
    }
  }
  if (x < length)
  {
    const uint64_t loaded = _bzhi_u64(~uint64_t{ 0 }, static_cast<unsigned int>(length - x));
    const uint64_t bits = above(values + x, loaded);
    const uint64_t change = (bits ^ (bits << 1 | previous)) & loaded;
    if (change != 0)
    {
      addChanges(change, x);
    }
  }
  return firstAbove;
}
#  endif

template <typename TPixel>
template <typename TChanges>
bool
RunEncoder<TPixel>::ForEachSideChangeSse2(const TPixel * values, SizeValueType length, TChanges && addChanges) const
{
  {
    const bool firstAbove = m_Threshold.IsAbove(values[0]);
    if (!m_Threshold.AnyAbove())
    {
      return firstAbove;
    }
    // One bit per voxel, set on one side of the isovalue, 64 voxels a word; a run starts
    // where a voxel's bit differs from the previous voxel's.
    const SideBits<TPixel> sideBits(m_Threshold.LowestAbove());
    constexpr bool         marksAbove = SideBitsMarkAbove<TPixel>;
    uint64_t               previous = firstAbove == marksAbove ? 1 : 0; // the bit of the voxel before x
    SizeValueType          x = 0;
    for (; x + 64 <= length; x += 64)
    {
      const uint64_t bits = uint64_t{ sideBits(values + x) } | uint64_t{ sideBits(values + x + 16) } << 16 |
                            uint64_t{ sideBits(values + x + 32) } << 32 | uint64_t{ sideBits(values + x + 48) } << 48;
      const uint64_t change = bits ^ (bits << 1 | previous);
      previous = bits >> 63;
      if (change != 0)
      {
        addChanges(change, x);
      }
    }
    for (; x + 16 <= length; x += 16)
    {
      const uint64_t bits = sideBits(values + x);
      const uint64_t change = (bits ^ (bits << 1 | previous)) & 0xFFFFu;
      previous = bits >> 15;
      if (change != 0)
      {
        addChanges(change, x);
      }
    }
    if (x < length)
    {
      if (length >= 16)
      {
        // The last 16 voxels, of which the ones before x are done.
        const SizeValueType last = length - 16;
        const uint64_t      bits = sideBits(values + last);
        addChanges((bits ^ bits << 1) & 0xFFFFu & ~((uint64_t{ 1 } << (x - last)) - 1), last);
      }
      else
      {
        for (; x < length; ++x)
        {
          const uint64_t bit = m_Threshold.IsAbove(values[x]) == marksAbove ? 1 : 0;
          if (bit != previous)
          {
            addChanges(1, x);
          }
          previous = bit;
        }
      }
    }
    return firstAbove;
  }
}
#endif

template <typename TPixel>
template <typename TAppend>
bool
RunEncoder<TPixel>::EncodeLineBySearch(const TPixel * values, SizeValueType length, TAppend && append) const
{
  const bool firstAbove = m_Threshold.IsAbove(values[0]);
  bool       above = firstAbove;
  append(0);
  for (SizeValueType x = m_Threshold.NextSideChange(values, 1, length, above); x < length;
       x = m_Threshold.NextSideChange(values, x + 1, length, above))
  {
    above = !above;
    append(static_cast<CoordinateType>(x));
  }
  return firstAbove;
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
