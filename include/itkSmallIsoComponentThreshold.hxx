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
#include <limits>

namespace itk
{
namespace SmallIsoComponentDetail
{
template <typename TPixel>
Threshold<TPixel>::Threshold(double isoValue)
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
Threshold<TPixel>::BlockHasChange(const TPixel * block, TPixel lowestAbove, bool above)
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
Threshold<TPixel>::NextSideChange(const TPixel * line, SizeValueType from, SizeValueType length, bool above) const
{
  if (!m_AnyAbove)
  {
    return above ? from : length;
  }
  SizeValueType x = from;
  // Whole blocks, then quarter blocks, before the change is located voxel by voxel.
  constexpr SizeValueType block = 64 / sizeof(TPixel) > 0 ? 64 / sizeof(TPixel) : 1;
  constexpr SizeValueType subBlock = block / 4 > 0 ? block / 4 : 1;
  while (x + block <= length && !BlockHasChange<block>(line + x, m_LowestAbove, above))
  {
    x += block;
  }
  while (x + subBlock <= length && !BlockHasChange<subBlock>(line + x, m_LowestAbove, above))
  {
    x += subBlock;
  }
  while (x < length && (line[x] >= m_LowestAbove) == above)
  {
    ++x;
  }
  return x;
}

} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
