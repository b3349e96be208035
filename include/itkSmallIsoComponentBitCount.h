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
#ifndef itkSmallIsoComponentBitCount_h
#define itkSmallIsoComponentBitCount_h

#include <cstdint>

#if defined(__GNUC__)
#  define SMALLISO_ALWAYS_INLINE inline __attribute__((always_inline))
/* The same for a lambda, after its parameters. */
#  define SMALLISO_LAMBDA_ALWAYS_INLINE __attribute__((always_inline))
#else
#  define SMALLISO_ALWAYS_INLINE inline
#  define SMALLISO_LAMBDA_ALWAYS_INLINE
#endif
/* Where the compiler may not use the processor's bit-count instruction, the loops that
 * count many bits are compiled twice, once for processors that have it, chosen at run
 * time with HasPopcount(). */
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && !defined(__POPCNT__)
#  define SMALLISO_POPCOUNT_DISPATCH
#endif

namespace itk
{
namespace SmallIsoComponentDetail
{
/** The number of set bits of \a bits. Internal to SmallIsoComponentImageFilter. */
SMALLISO_ALWAYS_INLINE unsigned int
CountBits(uint64_t bits)
{
#if defined(__GNUC__)
  return static_cast<unsigned int>(__builtin_popcountll(bits));
#else
  bits -= (bits >> 1) & 0x5555555555555555ULL;
  bits = (bits & 0x3333333333333333ULL) + ((bits >> 2) & 0x3333333333333333ULL);
  bits = (bits + (bits >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
  return static_cast<unsigned int>((bits * 0x0101010101010101ULL) >> 56);
#endif
}

/** The bits 0 to \a bit (at most 63) of a word. */
constexpr uint64_t
BitsUpTo(unsigned int bit)
{
  return ~uint64_t{ 0 } >> (63 - bit);
}

#if defined(SMALLISO_POPCOUNT_DISPATCH)
/** Whether the processor counts bits in one instruction (nearly every x86-64 processor
 * made since 2008). */
inline bool
HasPopcount()
{
  static const bool has = __builtin_cpu_supports("popcnt") != 0;
  return has;
}
#endif
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
