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
#ifndef itkSmallIsoComponentThreshold_h
#define itkSmallIsoComponentThreshold_h

#include "itkIntTypes.h"
#include "itkMacro.h"
#include <type_traits>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class Threshold
 * \brief The isovalue σ seen through pixel type TPixel: which side a value is on, and the
 * values closest to σ on each side. Internal to SmallIsoComponentImageFilter.
 *
 * f >= σ holds exactly when f >= LowestAbove() (never for NaN); HighestBelow() is the
 * largest non-NaN value below σ. AnyAbove() / AnyBelow() tell whether the type has such a
 * value at all (for unsigned char, σ <= 0 leaves nothing below). NextSideChange() finds
 * where a line changes side, testing a block of 64 bytes at a time (a reduction the
 * compiler vectorises).
 *
 * \ingroup SmallIsoComponent
 */
template <typename TPixel>
class ITK_TEMPLATE_EXPORT Threshold
{
public:
  static_assert(std::is_arithmetic<TPixel>::value,
                "SmallIsoComponentDetail::Threshold needs a scalar pixel type (an integer or floating-point type).");

  explicit Threshold(double isoValue);

  bool
  IsAbove(TPixel value) const
  {
    return m_AnyAbove && value >= m_LowestAbove;
  }
  bool
  AnyAbove() const
  {
    return m_AnyAbove;
  }
  bool
  AnyBelow() const
  {
    return m_AnyBelow;
  }
  TPixel
  LowestAbove() const
  {
    return m_LowestAbove;
  }
  TPixel
  HighestBelow() const
  {
    return m_HighestBelow;
  }

  /** The first x >= from where the side differs from \a above, or length. */
  SizeValueType
  NextSideChange(const TPixel * line, SizeValueType from, SizeValueType length, bool above) const;

private:
  template <SizeValueType VBlock>
  static bool
  BlockHasChange(const TPixel * block, TPixel lowestAbove, bool above);

  bool   m_AnyAbove{ false };
  TPixel m_LowestAbove{};
  bool   m_AnyBelow{ false };
  TPixel m_HighestBelow{};
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentThreshold.hxx"
#endif

#endif
