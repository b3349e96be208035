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
#ifndef itkSmallIsoComponentDeferredFill_h
#define itkSmallIsoComponentDeferredFill_h

#include "itkIntTypes.h"
#include "SmallIsoComponentExport.h"
#include "itkSmallIsoComponentTuning.h"

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class DeferredFill
 * \brief The copy of the input into the output and the clearing of the mask, when the run
 * encoding leaves them for later. Internal to SmallIsoComponentImageFilter.
 *
 * Large images of one pixel type are encoded from the input, and the output and the mask
 * are written afterwards with streaming stores, block by block, by the work units that the
 * serial linking of the seams leaves free. An empty fill (the default) has nothing
 * left to write: the encoding wrote the output and the mask itself.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT DeferredFill
{
public:
  /** Nothing left to write. */
  DeferredFill() = default;

  /** \a numberOfLines lines to copy from \a source to \a output (nothing to copy when they
   * are one buffer: the filter runs in place), \a outputLineBytes bytes each, and to
   * clear in \a mask, \a maskLineBytes bytes each (nothing when \a mask is null: no mask is
   * made). */
  DeferredFill(const void *  source,
               void *        output,
               SizeValueType outputLineBytes,
               void *        mask,
               SizeValueType maskLineBytes,
               SizeValueType numberOfLines);

  bool
  IsEmpty() const
  {
    return m_NumberOfBlocks == 0;
  }

  /** Blocks of whole lines, about Tuning::FillBlockBytes of output and mask each. */
  SizeValueType
  GetNumberOfBlocks() const
  {
    return m_NumberOfBlocks;
  }

  /** The bytes the fill writes in all (the output's, unless the filter runs in place, and
   * the mask's). */
  SizeValueType
  GetNumberOfBytes() const
  {
    return m_NumberOfLines *
           ((m_Source != nullptr ? m_OutputLineBytes : 0) + (m_Mask != nullptr ? m_MaskLineBytes : 0));
  }

  /** Writes the output and the mask lines of \a block, with streaming stores. Different
   * blocks may be written concurrently. */
  void
  FillBlock(SizeValueType block) const;

private:
  const char *  m_Source{ nullptr };
  char *        m_Output{ nullptr };
  char *        m_Mask{ nullptr };
  SizeValueType m_OutputLineBytes{ 0 };
  SizeValueType m_MaskLineBytes{ 0 };
  SizeValueType m_NumberOfLines{ 0 };
  SizeValueType m_LinesPerBlock{ 1 };
  SizeValueType m_NumberOfBlocks{ 0 };
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
