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

#include "itkSmallIsoComponentWorkTeam.h"
#include <algorithm>

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
 * covering \a lines lines, each slab taken by the next free member of \a team. */
template <typename TFunction>
void
ForEachSlabOfLines(WorkTeam & team, SizeValueType lines, SizeValueType slabs, const TFunction & function)
{
  team.ForEach(slabs, [&function, lines, slabs](SizeValueType slab) {
    function(slab, SlabBeginLine(lines, slabs, slab), SlabBeginLine(lines, slabs, slab + 1));
  });
}

/** The slabs of lines to share among the members of \a team: more balance the load. */
inline SizeValueType
SlabsFor(SizeValueType lines, const WorkTeam & team)
{
  return std::min<SizeValueType>(lines, SizeValueType{ team.GetNumberOfWorkUnits() } * Tuning::SlabsPerWorkUnit);
}

/** Calls function(line) for every line of \a lines, in slabs of lines shared among the members
 * of \a team. */
template <typename TFunction>
void
ForEachLineInSlabs(WorkTeam & team, SizeValueType lines, const TFunction & function)
{
  ForEachSlabOfLines(
    team, lines, SlabsFor(lines, team), [&function](SizeValueType, SizeValueType begin, SizeValueType end) {
      for (SizeValueType line = begin; line < end; ++line)
      {
        function(line);
      }
    });
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
