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
#ifndef itkSmallIsoComponentRunSummary_h
#define itkSmallIsoComponentRunSummary_h

#include "itkSmallIsoComponentBlockSummary.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentRunEncoder.h"

namespace itk
{
namespace SmallIsoComponentDetail
{
/** The summary of a box of a 3-D image whose components \a labeling found: the labelling's
 * image is the box (\a extent voxels from \a begin, lines along x), numbered with
 * LabelComponents(rules.MaximumComponentSize) so that the runs of its small components are
 * candidates. The summary is not settled yet. Internal to the module. */
SmallIsoComponent_EXPORT BlockSummary
SummarizeLabeling(const RunLabeling &             labeling,
                  const BlockSummary::IndexType & extent,
                  const BlockSummary::IndexType & imageSize,
                  const BlockSummary::IndexType & begin,
                  const ComponentRules &          rules);

/** Labels the box of \a extent voxels at \a values (x fastest) with \a labeling: encodes its runs
 * with \a encoder, links them under \a fullyConnected and numbers the components, keeping the runs of those of at
 * most \a maximumComponentSize voxels as candidates; \a workUnits share the work. */
template <typename TPixel>
void
LabelBox(const TPixel *                  values,
         const BlockSummary::IndexType & extent,
         const RunEncoder<TPixel> &      encoder,
         bool                            fullyConnected,
         uint64_t                        maximumComponentSize,
         MultiThreaderBase *             threader,
         unsigned int                    workUnits,
         RunLabeling &                   labeling);

/** The settled summary of the box [begin, begin + extent) of an image of \a imageSize voxels, whose
 * voxels are at \a values: what a chunk of the chunked mode reports. */
template <typename TPixel>
BlockSummary
SummarizeBox(const TPixel *                  values,
             const BlockSummary::IndexType & extent,
             const BlockSummary::IndexType & imageSize,
             const BlockSummary::IndexType & begin,
             double                          isoValue,
             const ComponentRules &          rules,
             MultiThreaderBase *             threader,
             unsigned int                    workUnits);

/** How far beyond a part of the image the filter's result in that part can depend on the voxels:
 * K for one side, 2K for Side Both (docs/algorithm.md derives it). */
SmallIsoComponent_EXPORT uint64_t
BoxHalo(uint64_t maximumComponentSize, SmallIsoComponentEnums::Side side);

/** Calls visit(otherRun) for every run of the other side that touches run \a run of line \a line
 * of \a labeling: the runs beside it in its line and
 * the other side's runs of the neighbouring lines that overlap it (diagonally too with full
 * connectivity). A run may be visited more than once. */
template <typename TVisit>
void
ForEachTouchingRunOfOtherSide(const RunLabeling & labeling, SizeValueType run, SizeValueType line, TVisit && visit);
} // namespace SmallIsoComponentDetail
} // end namespace itk

#include "itkSmallIsoComponentRunSummary.hxx"

#endif
