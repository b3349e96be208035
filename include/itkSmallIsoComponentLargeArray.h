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
#ifndef itkSmallIsoComponentLargeArray_h
#define itkSmallIsoComponentLargeArray_h

#include "itkIntTypes.h"
#include "SmallIsoComponentExport.h"
#include "itkSmallIsoComponentTuning.h"
#include <type_traits>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** Uninitialised memory of at least \a bytes bytes. Blocks of Tuning::LargeBlockBytes or more are
 * aligned to 2 MiB and, on Linux, offered to the kernel for transparent huge pages, so
 * that touching them first costs one fault per 2 MiB instead of one per 4 KiB. */
SmallIsoComponent_EXPORT void *
AllocateLarge(SizeValueType bytes);

/** Frees what AllocateLarge() returned (nullptr is allowed). */
SmallIsoComponent_EXPORT void
FreeLarge(void * block) noexcept;

/** \class LargeArray
 * \brief An array of trivially copyable values whose memory is kept when it is asked for
 * fewer values again, so that a filter updated again on an image of the same size takes no
 * fresh memory. Reserve() leaves the values uninitialised: the parallel loops that fill
 * them touch their pages first. Internal to SmallIsoComponentImageFilter.
 *
 * \ingroup SmallIsoComponent
 */
template <typename T>
class LargeArray
{
  static_assert(std::is_trivially_copyable<T>::value, "LargeArray holds plain values");

public:
  LargeArray() = default;
  LargeArray(const LargeArray &) = delete;
  LargeArray &
  operator=(const LargeArray &) = delete;
  LargeArray(LargeArray && other) noexcept
    : m_Data(other.m_Data)
    , m_Capacity(other.m_Capacity)
  {
    other.m_Data = nullptr;
    other.m_Capacity = 0;
  }
  LargeArray &
  operator=(LargeArray && other) noexcept
  {
    if (this != &other)
    {
      FreeLarge(m_Data);
      m_Data = other.m_Data;
      m_Capacity = other.m_Capacity;
      other.m_Data = nullptr;
      other.m_Capacity = 0;
    }
    return *this;
  }
  ~LargeArray() { FreeLarge(m_Data); }

  /** Room for \a count values, their contents undefined (earlier values are not kept). */
  void
  Reserve(SizeValueType count)
  {
    if (count > m_Capacity)
    {
      FreeLarge(m_Data);
      m_Data = nullptr;
      m_Capacity = 0;
      m_Data = static_cast<T *>(AllocateLarge(count * sizeof(T)));
      m_Capacity = count;
    }
  }

  /** Gives the memory back. */
  void
  Release() noexcept
  {
    FreeLarge(m_Data);
    m_Data = nullptr;
    m_Capacity = 0;
  }

  T *
  data()
  {
    return m_Data;
  }
  const T *
  data() const
  {
    return m_Data;
  }
  SizeValueType
  capacity() const
  {
    return m_Capacity;
  }

private:
  T *           m_Data{ nullptr };
  SizeValueType m_Capacity{ 0 };
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
