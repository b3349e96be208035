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
#ifndef itkSmallIsoComponentSideBits_h
#define itkSmallIsoComponentSideBits_h

#include <cstdint>
#include <type_traits>
#if defined(__SSE2__)
#  include <emmintrin.h>
#endif

namespace itk
{
namespace SmallIsoComponentDetail
{
#if defined(__SSE2__)
/** The pixel types SideBits classifies: 8- and 16-bit integers and float. */
template <typename T>
constexpr bool HasSideBits =
  std::is_same<T, uint8_t>::value || std::is_same<T, int8_t>::value || std::is_same<T, uint16_t>::value ||
  std::is_same<T, int16_t>::value || std::is_same<T, float>::value;

/** Whether SideBits marks the voxels above the threshold (unsigned integers) rather than
 * the ones below it (the other types, NaN included). */
template <typename T>
constexpr bool SideBitsMarkAbove = std::is_same<T, uint8_t>::value || std::is_same<T, uint16_t>::value;

/** \class SideBits
 * \brief The SSE2 classification of 16 voxels at once: one bit per voxel, set for the
 * voxels on the side SideBitsMarkAbove<T> names, given the lowest value above the
 * isovalue, t. Internal to SmallIsoComponentImageFilter.
 *
 * v >= t is tested as a saturated difference t - v of zero for unsigned integers, and its
 * negation as t > v for signed ones and as "not v >= t" for float (true for NaN): the one
 * compare each type has in SSE2.
 *
 * \ingroup SmallIsoComponent
 */
template <typename T>
class SideBits
{
public:
  static_assert(HasSideBits<T>, "SideBits classifies 8- and 16-bit integers and float only.");

  explicit SideBits(T lowestAbove)
  {
    if constexpr (std::is_same<T, float>::value)
    {
      m_LowestAbove = _mm_castps_si128(_mm_set1_ps(lowestAbove));
    }
    else if constexpr (sizeof(T) == 1)
    {
      m_LowestAbove = _mm_set1_epi8(static_cast<char>(lowestAbove));
    }
    else
    {
      m_LowestAbove = _mm_set1_epi16(static_cast<short>(lowestAbove));
    }
  }

  /** The bits of the 16 voxels at \a voxels. */
  unsigned int
  operator()(const T * voxels) const
  {
    if constexpr (sizeof(T) == 1)
    {
      return static_cast<unsigned int>(_mm_movemask_epi8(this->Lanes(voxels)));
    }
    else if constexpr (sizeof(T) == 2)
    {
      return static_cast<unsigned int>(
        _mm_movemask_epi8(_mm_packs_epi16(this->Lanes(voxels), this->Lanes(voxels + 8))));
    }
    else
    {
      return static_cast<unsigned int>(
        _mm_movemask_epi8(_mm_packs_epi16(_mm_packs_epi32(this->Lanes(voxels), this->Lanes(voxels + 4)),
                                          _mm_packs_epi32(this->Lanes(voxels + 8), this->Lanes(voxels + 12)))));
    }
  }

private:
  /** All-ones lanes for the marked voxels among the 16 bytes at \a voxels. */
  __m128i
  Lanes(const T * voxels) const
  {
    if constexpr (std::is_same<T, float>::value)
    {
      return _mm_castps_si128(_mm_cmpnge_ps(_mm_loadu_ps(voxels), _mm_castsi128_ps(m_LowestAbove)));
    }
    else
    {
      const __m128i values = _mm_loadu_si128(reinterpret_cast<const __m128i *>(voxels));
      if constexpr (std::is_same<T, uint8_t>::value)
      {
        return _mm_cmpeq_epi8(_mm_subs_epu8(m_LowestAbove, values), _mm_setzero_si128());
      }
      else if constexpr (std::is_same<T, uint16_t>::value)
      {
        return _mm_cmpeq_epi16(_mm_subs_epu16(m_LowestAbove, values), _mm_setzero_si128());
      }
      else if constexpr (std::is_same<T, int8_t>::value)
      {
        return _mm_cmpgt_epi8(m_LowestAbove, values);
      }
      else
      {
        return _mm_cmpgt_epi16(m_LowestAbove, values);
      }
    }
  }

  __m128i m_LowestAbove;
};
#endif
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
