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
#ifndef itkSmallIsoComponentSizeCounter_h
#define itkSmallIsoComponentSizeCounter_h

#include "itkIntTypes.h"
#include "SmallIsoComponentExport.h"
#include <map>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class SizeCounter
 * \brief Counts components by size for a histogram: the many small sizes in an array, the
 * few large ones in the histogram itself, so that millions of components cost no tree
 * look-ups. Internal to SmallIsoComponentImageFilter.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT SizeCounter
{
public:
  void
  Add(SizeValueType size)
  {
    if (size < m_Small.size())
    {
      ++m_Small[size];
    }
    else
    {
      ++m_Large[size];
    }
  }

  /** Adds the counts of \a other. */
  void
  Add(const SizeCounter & other);

  /** Size -> number of components of that size, for the sizes added but 0 (which counts
   * nothing: adding it lets a loop count entries that are no component without a branch). */
  std::map<SizeValueType, SizeValueType>
  Histogram() const;

private:
  std::vector<SizeValueType>             m_Small = std::vector<SizeValueType>(4096, 0);
  std::map<SizeValueType, SizeValueType> m_Large;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
