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
#ifndef itkSmallIsoComponentPeakMemory_h
#define itkSmallIsoComponentPeakMemory_h

#include "itkIntTypes.h"
#include <algorithm>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class PeakMemory
 * \brief The most bytes an update of SmallIsoComponentImageFilter held at once beyond its
 * images: each phase reports what it holds at its fullest, and the largest report is the
 * peak. Internal to the filter.
 *
 * \ingroup SmallIsoComponent
 */
class PeakMemory
{
public:
  /** Reports that \a bytes plus the capacity of each of \a vectors are held now. */
  template <typename... TVectors>
  void
  Hold(SizeValueType bytes, const TVectors &... vectors)
  {
    m_PeakInBytes = std::max(m_PeakInBytes, (bytes + ... + BytesOf(vectors)));
  }

  SizeValueType
  GetPeakInBytes() const
  {
    return m_PeakInBytes;
  }

  void
  Reset()
  {
    m_PeakInBytes = 0;
  }

private:
  template <typename T>
  static SizeValueType
  BytesOf(const std::vector<T> & vector)
  {
    return vector.capacity() * sizeof(T);
  }

  SizeValueType m_PeakInBytes{ 0 };
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
