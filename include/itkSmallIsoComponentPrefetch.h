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
#ifndef itkSmallIsoComponentPrefetch_h
#define itkSmallIsoComponentPrefetch_h

#include "itkIntTypes.h"

namespace itk
{
namespace SmallIsoComponentDetail
{
/** Asks for the cache line at \a address ahead of its use; a hint only. Internal to
 * SmallIsoComponentImageFilter, like the distances below.
 *
 * The loops over removed and flipped runs visit runs that are few and far apart: what
 * each run reads is usually not in cache, and requesting it a few runs ahead overlaps
 * the waits. */
inline void
Prefetch(const void * address)
{
#if defined(__GNUC__)
  __builtin_prefetch(address);
  // GCC takes the prefetch for an operation without effects: a function (such as a lambda)
  // that only prefetches would count as one without effects too, and the calls to it not
  // yet inlined would be dropped. An empty statement that counts as an effect keeps them.
  __asm__ __volatile__("" : : "r"(address));
#else
  (void)address;
#endif
}

} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
