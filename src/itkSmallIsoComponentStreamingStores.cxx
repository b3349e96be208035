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
#include "itkSmallIsoComponentStreamingStores.h"
#include <algorithm>
#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
#  include <emmintrin.h>
#endif

namespace itk
{
namespace SmallIsoComponentDetail
{
#if defined(__SSE2__)
namespace
{
/** Bytes from \a address to the next 64-byte boundary, at most \a bytes. */
SizeValueType
HeadBytes(const void * address, SizeValueType bytes)
{
  return std::min<SizeValueType>(bytes, (64 - reinterpret_cast<uintptr_t>(address) % 64) % 64);
}
} // namespace
#endif

void
StreamCopy(void * destination, const void * source, SizeValueType bytes)
{
#if defined(__SSE2__)
  auto *       to = static_cast<char *>(destination);
  const auto * from = static_cast<const char *>(source);
  const auto   head = HeadBytes(to, bytes);
  std::memcpy(to, from, head);
  for (to += head, from += head, bytes -= head; bytes >= 64; to += 64, from += 64, bytes -= 64)
  {
    const __m128i quarter0 = _mm_loadu_si128(reinterpret_cast<const __m128i *>(from));
    const __m128i quarter1 = _mm_loadu_si128(reinterpret_cast<const __m128i *>(from + 16));
    const __m128i quarter2 = _mm_loadu_si128(reinterpret_cast<const __m128i *>(from + 32));
    const __m128i quarter3 = _mm_loadu_si128(reinterpret_cast<const __m128i *>(from + 48));
    _mm_stream_si128(reinterpret_cast<__m128i *>(to), quarter0);
    _mm_stream_si128(reinterpret_cast<__m128i *>(to + 16), quarter1);
    _mm_stream_si128(reinterpret_cast<__m128i *>(to + 32), quarter2);
    _mm_stream_si128(reinterpret_cast<__m128i *>(to + 48), quarter3);
  }
  std::memcpy(to, from, bytes);
#else
  std::memcpy(destination, source, bytes);
#endif
}

void
StreamZero(void * destination, SizeValueType bytes)
{
#if defined(__SSE2__)
  auto *     to = static_cast<char *>(destination);
  const auto head = HeadBytes(to, bytes);
  std::memset(to, 0, head);
  const __m128i zero = _mm_setzero_si128();
  for (to += head, bytes -= head; bytes >= 64; to += 64, bytes -= 64)
  {
    _mm_stream_si128(reinterpret_cast<__m128i *>(to), zero);
    _mm_stream_si128(reinterpret_cast<__m128i *>(to + 16), zero);
    _mm_stream_si128(reinterpret_cast<__m128i *>(to + 32), zero);
    _mm_stream_si128(reinterpret_cast<__m128i *>(to + 48), zero);
  }
  std::memset(to, 0, bytes);
#else
  std::memset(destination, 0, bytes);
#endif
}

void
StreamFence()
{
#if defined(__SSE2__)
  _mm_sfence();
#endif
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
