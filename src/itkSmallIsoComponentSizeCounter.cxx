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
#include "itkSmallIsoComponentSizeCounter.h"

namespace itk
{
namespace SmallIsoComponentDetail
{
void
SizeCounter::Add(const SizeCounter & other)
{
  for (SizeValueType size = 0; size < m_Small.size(); ++size)
  {
    m_Small[size] += other.m_Small[size];
  }
  for (const auto & entry : other.m_Large)
  {
    m_Large[entry.first] += entry.second;
  }
}

std::map<SizeValueType, SizeValueType>
SizeCounter::Histogram() const
{
  std::map<SizeValueType, SizeValueType> histogram = m_Large;
  for (SizeValueType size = 1; size < m_Small.size(); ++size)
  {
    if (m_Small[size] > 0)
    {
      histogram[size] = m_Small[size];
    }
  }
  return histogram;
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
