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
LabelBox(const TPixel *                  values,
         const BlockSummary::IndexType & extent,
         const RunEncoder<TPixel> &      encoder,
         bool                            fullyConnected,
         uint64_t                        maximumComponentSize,
         MultiThreaderBase *             threader,
         unsigned int                    workUnits,
         RunLabeling &                   labeling)
{
  WorkTeam team(threader, workUnits);
  labeling.Initialize({ extent[0], extent[1], extent[2] }, fullyConnected, workUnits);
  encoder.Encode(values, labeling, team);
  labeling.AssembleRuns(team);
  labeling.LinkRuns();
  labeling.LabelComponents(maximumComponentSize, maximumComponentSize);
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
  const Threshold<TPixel> threshold(isoValue);
  ComponentRules          boxRules = rules;
  boxRules.AnyAbove = threshold.AnyAbove();
  boxRules.AnyBelow = threshold.AnyBelow();
  RunLabeling labeling;
  LabelBox(values,
           extent,
           RunEncoder<TPixel>(isoValue),
           boxRules.FullyConnected,
           boxRules.MaximumComponentSize,
           threader,
           workUnits,
           labeling);
  BlockSummary summary = SummarizeLabeling(labeling, extent, imageSize, begin, boxRules);
  summary.Settle();
  return summary;
}

template <typename TVisit>
void
ForEachTouchingRunOfOtherSide(const RunLabeling & labeling, SizeValueType run, SizeValueType line, TVisit && visit)
{
  const RunLabeling::RunTable table = labeling.GetRunTable();
  // Sides alternate along a line: the runs beside this one are the other side.
  if (run > table.LineBegin[line])
  {
    visit(run - 1);
  }
  if (run + 1 < table.LineBegin[line + 1])
  {
    visit(run + 1);
  }
  // In the neighbouring lines, every run of the other side that overlaps this one, or with
  // full connectivity ends just before it or starts just after it.
  const bool            above = table.IsAbove(run, line);
  const SizeValueType   allowance = labeling.IsFullyConnected() ? 1 : 0;
  const SizeValueType   start = table.Start[run];
  const SizeValueType   from = start >= allowance ? start - allowance : 0;
  const SizeValueType   to = table.End(run, line) + allowance;
  const LineNeighbors & neighbors = labeling.GetLineNeighbors();
  neighbors.ForEachNeighbor(neighbors.At(line), [&](SizeValueType other) {
    SizeValueType touching = table.RunHolding(other, from);
    touching += table.IsAbove(touching, other) == above ? 1 : 0;
    for (; touching < table.LineBegin[other + 1] && table.Start[touching] < to; touching += 2)
    {
      visit(touching);
    }
  });
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
