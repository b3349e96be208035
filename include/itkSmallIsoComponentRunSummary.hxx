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
#ifndef itkSmallIsoComponentRunSummary_hxx
#define itkSmallIsoComponentRunSummary_hxx

#include "itkSmallIsoComponentWorkTeam.h"

namespace itk
{
namespace SmallIsoComponentDetail
{
template <typename TPixel>
void
LabelBox(const TPixel *                             values,
         const BlockSummary::IndexType &            extent,
         const SmallIsoComponentThreshold<TPixel> & threshold,
         bool                                       fullyConnected,
         uint64_t                                   maximumComponentSize,
         MultiThreaderBase *                        threader,
         unsigned int                               workUnits,
         SmallIsoComponentRunLabeling &             labeling)
{
  SmallIsoComponentWorkTeam team(threader, workUnits);
  labeling.SetWorkTeam(&team);
  labeling.Initialize({ extent[0], extent[1], extent[2] }, fullyConnected, workUnits);
  threshold.Encode(values, labeling, threader, [](SizeValueType, SizeValueType) {});
  labeling.AssembleRuns(threader);
  labeling.LinkRuns(threader);
  labeling.LabelComponents(maximumComponentSize);
  labeling.SetWorkTeam(nullptr);
}

template <typename TPixel>
BlockSummary
SummarizeBox(const TPixel *                  values,
             const BlockSummary::IndexType & extent,
             const BlockSummary::IndexType & imageSize,
             const BlockSummary::IndexType & begin,
             double                          isoValue,
             const ComponentRules &          rules,
             MultiThreaderBase *             threader,
             unsigned int                    workUnits)
{
  const SmallIsoComponentThreshold<TPixel> threshold(isoValue);
  ComponentRules                           boxRules = rules;
  boxRules.AnyAbove = threshold.AnyAbove();
  boxRules.AnyBelow = threshold.AnyBelow();
  SmallIsoComponentRunLabeling labeling;
  LabelBox(
    values, extent, threshold, boxRules.FullyConnected, boxRules.MaximumComponentSize, threader, workUnits, labeling);
  BlockSummary summary = SummarizeLabeling(labeling, extent, imageSize, begin, boxRules);
  summary.Settle();
  return summary;
}

template <typename TVisit>
void
ForEachTouchingRunOfOtherSide(const SmallIsoComponentRunLabeling & labeling,
                              const BlockSummary::IndexType &      extent,
                              bool                                 fullyConnected,
                              SizeValueType                        run,
                              SizeValueType                        line,
                              TVisit &&                            visit)
{
  // Sides alternate along a line: the runs beside this one are the other side.
  const SizeValueType lineBegin = labeling.GetLineRunsBegin(line);
  const SizeValueType lineEnd = labeling.GetLineRunsEnd(line);
  if (run > lineBegin)
  {
    visit(run - 1);
  }
  if (run + 1 < lineEnd)
  {
    visit(run + 1);
  }
  const bool          above = labeling.IsRunAbove(run, line);
  const SizeValueType allowance = fullyConnected ? 1 : 0;
  const SizeValueType start = labeling.GetRunStart(run);
  const SizeValueType from = start >= allowance ? start - allowance : 0;
  const SizeValueType to = labeling.GetRunEnd(run, line) + allowance;
  const auto          y = static_cast<int64_t>(line % extent[1]);
  const auto          z = static_cast<int64_t>(line / extent[1]);
  const int           reach = 1;
  for (int dz = -reach; dz <= reach; ++dz)
  {
    for (int dy = -reach; dy <= reach; ++dy)
    {
      const int moved = (dy != 0 ? 1 : 0) + (dz != 0 ? 1 : 0);
      if (moved == 0 || (!fullyConnected && moved > 1) || y + dy < 0 || z + dz < 0 ||
          y + dy >= static_cast<int64_t>(extent[1]) || z + dz >= static_cast<int64_t>(extent[2]))
      {
        continue;
      }
      const auto          other = static_cast<SizeValueType>((y + dy) + static_cast<int64_t>(extent[1]) * (z + dz));
      const SizeValueType otherBegin = labeling.GetLineRunsBegin(other);
      const SizeValueType otherEnd = labeling.GetLineRunsEnd(other);
      // The last run starting at or before from, then every run that starts before to.
      SizeValueType low = otherBegin;
      SizeValueType high = otherEnd;
      while (high - low > 1)
      {
        const SizeValueType middle = low + (high - low) / 2;
        if (labeling.GetRunStart(middle) <= from)
        {
          low = middle;
        }
        else
        {
          high = middle;
        }
      }
      for (SizeValueType k = low; k < otherEnd && labeling.GetRunStart(k) < to; ++k)
      {
        if (labeling.IsRunAbove(k, other) != above)
        {
          visit(k);
        }
      }
    }
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
