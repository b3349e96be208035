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
#ifndef itkSmallIsoComponentLineSlabs_h
#define itkSmallIsoComponentLineSlabs_h

#include "itkMultiThreaderBase.h"
#include "itkSmallIsoComponentTuning.h"
#include <algorithm>
#include <atomic>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** The first line of slab \a slab when \a lines lines are cut into \a slabs slabs of
 * consecutive lines (slab \a slabs begins past the last line): lines * slab / slabs, without
 * the product's overflow. */
inline SizeValueType
SlabBeginLine(SizeValueType lines, SizeValueType slabs, SizeValueType slab)
{
  return lines / slabs * slab + lines % slabs * slab / slabs;
}

/** Calls function(slab, begin, end) for each of \a slabs slabs of consecutive lines [begin, end)
 * covering \a lines lines. The work units of \a threader take the slabs one at a time, so that
 * slabs of more work than others do not leave a work unit idle. */
template <typename TFunction>
void
ForEachSlabOfLines(MultiThreaderBase * threader, SizeValueType lines, SizeValueType slabs, const TFunction & function)
{
  std::atomic<SizeValueType> next{ 0 };
  const SizeValueType        workUnits = std::min<SizeValueType>(slabs, threader->GetNumberOfWorkUnits());
  threader->ParallelizeArray(
    0,
    workUnits,
    [&function, &next, lines, slabs](SizeValueType) {
      for (SizeValueType slab = next++; slab < slabs; slab = next++)
      {
        function(slab, SlabBeginLine(lines, slabs, slab), SlabBeginLine(lines, slabs, slab + 1));
      }
    },
    nullptr);
}

/** The slabs of lines to share among \a workUnits work units: more balance the load. */
inline SizeValueType
SlabsFor(SizeValueType lines, unsigned int workUnits)
{
  return std::min<SizeValueType>(lines, SizeValueType{ workUnits } * Tuning::SlabsPerWorkUnit);
}

/** Calls function(line) for every line of \a lines, in slabs of lines shared among the work units
 * of \a threader. */
template <typename TFunction>
void
ForEachLineInSlabs(MultiThreaderBase * threader, SizeValueType lines, const TFunction & function)
{
  ForEachSlabOfLines(threader,
                     lines,
                     SlabsFor(lines, threader->GetNumberOfWorkUnits()),
                     [&function](SizeValueType, SizeValueType begin, SizeValueType end) {
                       for (SizeValueType line = begin; line < end; ++line)
                       {
                         function(line);
                       }
                     });
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
