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
#ifndef itkSmallIsoComponentThreshold_hxx
#define itkSmallIsoComponentThreshold_hxx

#include "itkSmallIsoComponentThreshold.h"
#include <cmath>
#include <cstdint>
#include <limits>
#if defined(__SSE2__)
#  include <emmintrin.h>
#endif

namespace itk
{
namespace SmallIsoComponentSse2
{
#if defined(__SSE2__)
/** Pixel types for which BelowBytes() exists. */
template <typename T>
constexpr bool HasBelowBytes =
  std::is_same<T, uint8_t>::value || std::is_same<T, int8_t>::value || std::is_same<T, uint16_t>::value ||
  std::is_same<T, int16_t>::value || std::is_same<T, float>::value;

/** One bit per byte of the 16 bytes at \a p, set for the bytes of voxels below t
 * (v < t, or NaN). */
template <typename T>
unsigned int
BelowBytes(const T * p, T t)
{
  const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i *>(p));
  if constexpr (std::is_same<T, uint8_t>::value)
  {
    // v >= t exactly when the saturated difference t - v is zero.
    return ~_mm_movemask_epi8(
             _mm_cmpeq_epi8(_mm_subs_epu8(_mm_set1_epi8(static_cast<char>(t)), v), _mm_setzero_si128())) &
           0xFFFFu;
  }
  else if constexpr (std::is_same<T, uint16_t>::value)
  {
    return ~_mm_movemask_epi8(
             _mm_cmpeq_epi16(_mm_subs_epu16(_mm_set1_epi16(static_cast<short>(t)), v), _mm_setzero_si128())) &
           0xFFFFu;
  }
  else if constexpr (std::is_same<T, int8_t>::value)
  {
    return static_cast<unsigned int>(_mm_movemask_epi8(_mm_cmpgt_epi8(_mm_set1_epi8(t), v)));
  }
  else if constexpr (std::is_same<T, int16_t>::value)
  {
    return static_cast<unsigned int>(_mm_movemask_epi8(_mm_cmpgt_epi16(_mm_set1_epi16(t), v)));
  }
  else
  {
    // cmpnge is true for v < t and for NaN.
    return static_cast<unsigned int>(
      _mm_movemask_epi8(_mm_castps_si128(_mm_cmpnge_ps(_mm_loadu_ps(p), _mm_set1_ps(t)))));
  }
}

/** For the 16 bytes at \a p, all-ones lanes for the voxels on one side of t: above
 * (v >= t) for unsigned integers, below (v < t, or NaN) for the others;
 * LanesAreAbove<T> tells which. */
template <typename T>
constexpr bool LanesAreAbove = std::is_same<T, uint8_t>::value || std::is_same<T, uint16_t>::value;

template <typename T>
__m128i
SideLanes(const T * p, T t)
{
  if constexpr (std::is_same<T, float>::value)
  {
    return _mm_castps_si128(_mm_cmpnge_ps(_mm_loadu_ps(p), _mm_set1_ps(t)));
  }
  else
  {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i *>(p));
    if constexpr (std::is_same<T, uint8_t>::value)
    {
      return _mm_cmpeq_epi8(_mm_subs_epu8(_mm_set1_epi8(static_cast<char>(t)), v), _mm_setzero_si128());
    }
    else if constexpr (std::is_same<T, uint16_t>::value)
    {
      return _mm_cmpeq_epi16(_mm_subs_epu16(_mm_set1_epi16(static_cast<short>(t)), v), _mm_setzero_si128());
    }
    else if constexpr (std::is_same<T, int8_t>::value)
    {
      return _mm_cmpgt_epi8(_mm_set1_epi8(t), v);
    }
    else
    {
      return _mm_cmpgt_epi16(_mm_set1_epi16(t), v);
    }
  }
}

/** One bit per voxel for 16 voxels, set for the voxels on the side SideLanes() marks
 * (LanesAreAbove<T>: above, otherwise below), the threshold broadcast once. */
template <typename T>
class SideBits
{
public:
  explicit SideBits(T t)
  {
    if constexpr (std::is_same<T, float>::value)
    {
      m_T = _mm_castps_si128(_mm_set1_ps(t));
    }
    else if constexpr (sizeof(T) == 1)
    {
      m_T = _mm_set1_epi8(static_cast<char>(t));
    }
    else
    {
      m_T = _mm_set1_epi16(static_cast<short>(t));
    }
  }

  unsigned int
  operator()(const T * p) const
  {
    if constexpr (sizeof(T) == 1)
    {
      return static_cast<unsigned int>(_mm_movemask_epi8(Lanes(p)));
    }
    else if constexpr (sizeof(T) == 2)
    {
      return static_cast<unsigned int>(_mm_movemask_epi8(_mm_packs_epi16(Lanes(p), Lanes(p + 8))));
    }
    else
    {
      return static_cast<unsigned int>(_mm_movemask_epi8(
        _mm_packs_epi16(_mm_packs_epi32(Lanes(p), Lanes(p + 4)), _mm_packs_epi32(Lanes(p + 8), Lanes(p + 12)))));
    }
  }

private:
  __m128i
  Lanes(const T * p) const
  {
    if constexpr (std::is_same<T, float>::value)
    {
      return _mm_castps_si128(_mm_cmpnge_ps(_mm_loadu_ps(p), _mm_castsi128_ps(m_T)));
    }
    else
    {
      const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i *>(p));
      if constexpr (std::is_same<T, uint8_t>::value)
      {
        return _mm_cmpeq_epi8(_mm_subs_epu8(m_T, v), _mm_setzero_si128());
      }
      else if constexpr (std::is_same<T, uint16_t>::value)
      {
        return _mm_cmpeq_epi16(_mm_subs_epu16(m_T, v), _mm_setzero_si128());
      }
      else if constexpr (std::is_same<T, int8_t>::value)
      {
        return _mm_cmpgt_epi8(m_T, v);
      }
      else
      {
        return _mm_cmpgt_epi16(m_T, v);
      }
    }
  }

  __m128i m_T;
};

/** Whether the 64 bytes at \a p hold a voxel on the other side than \a above: four
 * compares combined into one test. */
template <typename T>
bool
ChangeIn64Bytes(const T * p, T t, bool above)
{
  constexpr SizeValueType step = 16 / sizeof(T);
  const __m128i           l0 = SideLanes(p, t);
  const __m128i           l1 = SideLanes(p + step, t);
  const __m128i           l2 = SideLanes(p + 2 * step, t);
  const __m128i           l3 = SideLanes(p + 3 * step, t);
  // A change is a lane of the marked side when the marked side is the other one, and an
  // unmarked lane otherwise.
  if (above != LanesAreAbove<T>)
  {
    return _mm_movemask_epi8(_mm_or_si128(_mm_or_si128(l0, l1), _mm_or_si128(l2, l3))) != 0;
  }
  return _mm_movemask_epi8(_mm_and_si128(_mm_and_si128(l0, l1), _mm_and_si128(l2, l3))) != 0xFFFF;
}
#endif
} // namespace SmallIsoComponentSse2

template <typename TPixel>
SmallIsoComponentThreshold<TPixel>::SmallIsoComponentThreshold(double isoValue)
{
  if constexpr (std::is_integral<TPixel>::value)
  {
    const double lowest = static_cast<double>(std::numeric_limits<TPixel>::lowest());
    const double highest = static_cast<double>(std::numeric_limits<TPixel>::max());
    const double ceiling = std::ceil(isoValue);
    m_AnyAbove = ceiling <= highest;
    m_LowestAbove =
      ceiling <= lowest ? std::numeric_limits<TPixel>::lowest() : static_cast<TPixel>(m_AnyAbove ? ceiling : highest);
    m_AnyBelow = ceiling - 1.0 >= lowest;
    m_HighestBelow = ceiling - 1.0 >= highest ? std::numeric_limits<TPixel>::max()
                                              : static_cast<TPixel>(m_AnyBelow ? ceiling - 1.0 : lowest);
  }
  else
  {
    m_LowestAbove = static_cast<TPixel>(isoValue);
    if (static_cast<double>(m_LowestAbove) < isoValue)
    {
      m_LowestAbove = std::nextafter(m_LowestAbove, std::numeric_limits<TPixel>::infinity());
    }
    m_AnyAbove = static_cast<double>(m_LowestAbove) >= isoValue;
    m_HighestBelow = static_cast<TPixel>(isoValue);
    if (static_cast<double>(m_HighestBelow) >= isoValue)
    {
      m_HighestBelow = std::nextafter(m_HighestBelow, -std::numeric_limits<TPixel>::infinity());
    }
    m_AnyBelow = static_cast<double>(m_HighestBelow) < isoValue;
  }
}

template <typename TPixel>
template <SizeValueType VBlock>
bool
SmallIsoComponentThreshold<TPixel>::BlockHasChange(const TPixel * block, TPixel lowestAbove, bool above)
{
  // Reductions the compiler vectorises: a minimum or maximum for integers, a count for
  // floating point (where NaN, never above, must count as a change).
  if constexpr (std::is_integral<TPixel>::value)
  {
    TPixel extreme = block[0];
    if (above)
    {
      for (SizeValueType k = 0; k < VBlock; ++k)
      {
        extreme = block[k] < extreme ? block[k] : extreme;
      }
      return extreme < lowestAbove;
    }
    for (SizeValueType k = 0; k < VBlock; ++k)
    {
      extreme = block[k] > extreme ? block[k] : extreme;
    }
    return extreme >= lowestAbove;
  }
  else
  {
    unsigned int aboveCount = 0;
    for (SizeValueType k = 0; k < VBlock; ++k)
    {
      aboveCount += block[k] >= lowestAbove ? 1u : 0u;
    }
    return above ? aboveCount != VBlock : aboveCount != 0;
  }
}

template <typename TPixel>
SizeValueType
SmallIsoComponentThreshold<TPixel>::NextSideChange(const TPixel * line,
                                                   SizeValueType  from,
                                                   SizeValueType  length,
                                                   bool           above) const
{
  if (!m_AnyAbove)
  {
    return above ? from : length;
  }
  const TPixel  t = m_LowestAbove;
  SizeValueType x = from;
#if defined(__SSE2__)
  if constexpr (SmallIsoComponentSse2::HasBelowBytes<TPixel>)
  {
    constexpr SizeValueType step = 16 / sizeof(TPixel);
    while (x + 4 * step <= length && !SmallIsoComponentSse2::ChangeIn64Bytes(line + x, t, above))
    {
      x += 4 * step;
    }
    for (; x + step <= length; x += step)
    {
      const unsigned int below = SmallIsoComponentSse2::BelowBytes(line + x, t);
      const unsigned int change = above ? below : ~below & 0xFFFFu;
      if (change != 0)
      {
        return x + static_cast<SizeValueType>(__builtin_ctz(change)) / sizeof(TPixel);
      }
    }
    if (x < length && length >= step)
    {
      // The last voxels: one compare of the last 16 bytes, ignoring the ones before x.
      const SizeValueType last = length - step;
      const unsigned int  below = SmallIsoComponentSse2::BelowBytes(line + last, t);
      const unsigned int  change = (above ? below : ~below & 0xFFFFu) & ~((1u << ((x - last) * sizeof(TPixel))) - 1u);
      return change != 0 ? last + static_cast<SizeValueType>(__builtin_ctz(change)) / sizeof(TPixel) : length;
    }
  }
  else
#endif
  {
    // Whole blocks, then quarter blocks, before the change is located voxel by voxel.
    constexpr SizeValueType block = 64 / sizeof(TPixel) > 0 ? 64 / sizeof(TPixel) : 1;
    constexpr SizeValueType subBlock = block / 4 > 0 ? block / 4 : 1;
    while (x + block <= length && !BlockHasChange<block>(line + x, t, above))
    {
      x += block;
    }
    while (x + subBlock <= length && !BlockHasChange<subBlock>(line + x, t, above))
    {
      x += subBlock;
    }
  }
  while (x < length && (line[x] >= t) == above)
  {
    ++x;
  }
  return x;
}

template <typename TPixel>
void
SmallIsoComponentThreshold<TPixel>::EncodeLine(const TPixel *                                              values,
                                               SizeValueType                                               line,
                                               SmallIsoComponentRunLabeling &                              labeling,
                                               std::vector<SmallIsoComponentRunLabeling::CoordinateType> & starts) const
{
  const SizeValueType length = labeling.GetLineLength();
  const bool          firstAbove = this->IsAbove(values[0]);
  bool                above = firstAbove;
  SizeValueType       runs = 1;
  starts.push_back(0);
#if defined(__SSE2__)
  if constexpr (SmallIsoComponentSse2::HasBelowBytes<TPixel>)
  {
    if (!m_AnyAbove)
    {
      labeling.SetLineRuns(line, 1, false);
      return;
    }
    // One bit per voxel, set on one side of the isovalue, 64 voxels a word; a run starts
    // where a voxel's bit differs from the previous voxel's.
    const SmallIsoComponentSse2::SideBits<TPixel> sideBits(m_LowestAbove);
    constexpr bool                                marksAbove = SmallIsoComponentSse2::LanesAreAbove<TPixel>;
    uint64_t      previous = firstAbove == marksAbove ? 1 : 0; // the bit of the voxel before x
    SizeValueType x = 0;
    const auto    addStarts = [&](uint64_t change, SizeValueType base) {
      for (; change != 0; change &= change - 1)
      {
        starts.push_back(static_cast<SmallIsoComponentRunLabeling::CoordinateType>(
          base + static_cast<SizeValueType>(__builtin_ctzll(change))));
        ++runs;
      }
    };
    for (; x + 64 <= length; x += 64)
    {
      const uint64_t bits = uint64_t{ sideBits(values + x) } | uint64_t{ sideBits(values + x + 16) } << 16 |
                            uint64_t{ sideBits(values + x + 32) } << 32 | uint64_t{ sideBits(values + x + 48) } << 48;
      const uint64_t change = bits ^ (bits << 1 | previous);
      previous = bits >> 63;
      if (change != 0)
      {
        addStarts(change, x);
      }
    }
    for (; x + 16 <= length; x += 16)
    {
      const uint64_t bits = sideBits(values + x);
      const uint64_t change = (bits ^ (bits << 1 | previous)) & 0xFFFFu;
      previous = bits >> 15;
      if (change != 0)
      {
        addStarts(change, x);
      }
    }
    if (x < length)
    {
      if (length >= 16)
      {
        // The last 16 voxels, of which the ones before x are done.
        const SizeValueType last = length - 16;
        const uint64_t      bits = sideBits(values + last);
        addStarts((bits ^ bits << 1) & 0xFFFFu & ~((uint64_t{ 1 } << (x - last)) - 1), last);
      }
      else
      {
        for (; x < length; ++x)
        {
          const uint64_t bit = this->IsAbove(values[x]) == marksAbove ? 1 : 0;
          if (bit != previous)
          {
            addStarts(1, x);
          }
          previous = bit;
        }
      }
    }
    labeling.SetLineRuns(line, runs, firstAbove);
    return;
  }
#endif
  for (SizeValueType x = this->NextSideChange(values, 1, length, above); x < length;
       x = this->NextSideChange(values, x + 1, length, above))
  {
    above = !above;
    starts.push_back(static_cast<SmallIsoComponentRunLabeling::CoordinateType>(x));
    ++runs;
  }
  labeling.SetLineRuns(line, runs, firstAbove);
}
} // end namespace itk

#endif
