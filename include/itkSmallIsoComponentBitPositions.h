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
#ifndef itkSmallIsoComponentBitPositions_h
#define itkSmallIsoComponentBitPositions_h

#include "itkSmallIsoComponentBitCount.h"
#include <cstdint>

/* Where the compiler takes target attributes and the processor may have AVX-512, loops
 * are compiled a second time for AVX-512, chosen at run time with HasAvx512(). */
#if defined(__GNUC__) && defined(__x86_64__)
#  define SMALLISO_AVX512_DISPATCH
#  include <immintrin.h>
#endif

namespace itk
{
namespace SmallIsoComponentDetail
{
/** Writes base + i for every set bit i of \a bits, in increasing order, from \a out on, and
 * returns the end of what it wrote: one step per bit. Internal to SmallIsoComponentImageFilter. */
SMALLISO_ALWAYS_INLINE uint32_t *
WriteBitPositions(uint32_t * out, uint64_t bits, uint32_t base)
{
  for (; bits != 0; bits &= bits - 1)
  {
    *out++ = base + static_cast<uint32_t>(__builtin_ctzll(bits));
  }
  return out;
}

#if defined(SMALLISO_AVX512_DISPATCH)
/** Whether the processor has AVX-512's foundation and its byte and word instructions,
 * and the system keeps its registers (Intel processors since 2017, AMD since 2022). */
inline bool
HasAvx512()
{
  static const bool has = __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512bw") != 0;
  return has;
}

/** WriteBitPositions() by four compresses of sixteen positions each, without a branch per
 * bit: the loop's exit after a varying number of bits mispredicts about once per word, and
 * dense lines have 30 bits a word. Nothing is written past the returned end (masked
 * stores). Call only where HasAvx512(). */
__attribute__((target("avx512f,popcnt,bmi2"))) inline uint32_t *
WriteBitPositionsCompressed(uint32_t * out, uint64_t bits, uint32_t base)
{
  const __m512i lanes = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
  __m512i       positions = _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(base)), lanes);
  for (unsigned int part = 0; part < 4; ++part)
  {
    const auto         mask = static_cast<__mmask16>(bits >> (16 * part));
    const unsigned int count = static_cast<unsigned int>(__builtin_popcount(mask));
    _mm512_mask_storeu_epi32(
      out, static_cast<__mmask16>(_bzhi_u32(0xFFFFu, count)), _mm512_maskz_compress_epi32(mask, positions));
    out += count;
    positions = _mm512_add_epi32(positions, _mm512_set1_epi32(16));
  }
  return out;
}
#endif
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
