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
#include "itkSmallIsoComponentLargeArray.h"
#include <cstdlib>
#include <new>
#if defined(__linux__)
#  include <sys/mman.h>
#endif

namespace itk
{
namespace SmallIsoComponentDetail
{
namespace
{
constexpr SizeValueType HugePageBytes = SizeValueType{ 2 } << 20;
}

void *
AllocateLarge(SizeValueType bytes)
{
  if (bytes < Tuning::LargeBlockBytes)
  {
    void * block = std::malloc(bytes == 0 ? 1 : bytes);
    if (block == nullptr)
    {
      throw std::bad_alloc();
    }
    return block;
  }
  // aligned_alloc wants a multiple of the alignment.
  const SizeValueType rounded = (bytes + HugePageBytes - 1) / HugePageBytes * HugePageBytes;
  void *              block = std::aligned_alloc(HugePageBytes, rounded);
  if (block == nullptr)
  {
    throw std::bad_alloc();
  }
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Advice only: without transparent huge pages the block is ordinary memory.
  madvise(block, rounded, MADV_HUGEPAGE);
#endif
  return block;
}

void
FreeLarge(void * block) noexcept
{
  // Both ways of AllocateLarge() are released by free().
  std::free(block);
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
