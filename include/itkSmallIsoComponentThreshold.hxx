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
constexpr bool HasBelowBytes = std::is_same<T, uint8_t>::value || std::is_same<T, int8_t>::value ||
                               std::is_same<T, uint16_t>::value || std::is_same<T, int16_t>::value ||
                               std::is_same<T, float>::value;

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
    return ~_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_subs_epu8(_mm_set1_epi8(static_cast<char>(t)), v),
                                             _mm_setzero_si128())) & 0xFFFFu;
  }
  else if constexpr (std::is_same<T, uint16_t>::value)
  {
    return ~_mm_movemask_epi8(_mm_cmpeq_epi16(_mm_subs_epu16(_mm_set1_epi16(static_cast<short>(t)), v),
                                              _mm_setzero_si128())) & 0xFFFFu;
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
    m_LowestAbove = ceiling <= lowest ? std::numeric_limits<TPixel>::lowest()
                                      : static_cast<TPixel>(m_AnyAbove ? ceiling : highest);
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
      const unsigned int  change =
        (above ? below : ~below & 0xFFFFu) & ~((1u << ((x - last) * sizeof(TPixel))) - 1u);
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
SmallIsoComponentThreshold<TPixel>::EncodeLine(const TPixel *                                      values,
                                               SizeValueType                                       line,
                                               SmallIsoComponentRunLabeling &                      labeling,
                                               std::vector<SmallIsoComponentRunLabeling::CoordinateType> & starts) const
{
  const SizeValueType length = labeling.GetLineLength();
  const bool          firstAbove = this->IsAbove(values[0]);
  bool                above = firstAbove;
  SizeValueType       runs = 1;
  starts.push_back(0);
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
