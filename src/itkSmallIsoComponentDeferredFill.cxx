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
#include "itkSmallIsoComponentDeferredFill.h"
#include "itkSmallIsoComponentStreamingStores.h"
#include <algorithm>

namespace itk
{
namespace SmallIsoComponentDetail
{
DeferredFill::DeferredFill(const void *  source,
                           void *        output,
                           SizeValueType outputLineBytes,
                           void *        mask,
                           SizeValueType maskLineBytes,
                           SizeValueType numberOfLines)
  : m_Source(source != output ? static_cast<const char *>(source) : nullptr)
  , m_Output(static_cast<char *>(output))
  , m_Mask(static_cast<char *>(mask))
  , m_OutputLineBytes(outputLineBytes)
  , m_MaskLineBytes(maskLineBytes)
  , m_NumberOfLines(numberOfLines)
  , m_LinesPerBlock(std::max<SizeValueType>(1, Tuning::FillBlockBytes / (outputLineBytes + maskLineBytes)))
  , m_NumberOfBlocks((numberOfLines + m_LinesPerBlock - 1) / m_LinesPerBlock)
{}

void
DeferredFill::FillBlock(SizeValueType block) const
{
  const SizeValueType first = block * m_LinesPerBlock;
  const SizeValueType lines = std::min(m_NumberOfLines, first + m_LinesPerBlock) - first;
  if (m_Source != nullptr)
  {
    StreamCopy(m_Output + first * m_OutputLineBytes, m_Source + first * m_OutputLineBytes, lines * m_OutputLineBytes);
  }
  if (m_Mask != nullptr)
  {
    StreamZero(m_Mask + first * m_MaskLineBytes, lines * m_MaskLineBytes);
  }
  StreamFence();
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
