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
#ifndef itkSmallIsoComponentWorkingMemory_h
#define itkSmallIsoComponentWorkingMemory_h

#include "itkSmallIsoComponentBelowGrouping.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentRunRepair.h"
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class WorkingMemory
 * \brief What SmallIsoComponentImageFilter's update works in besides the input and the
 * output, kept for the next update: the labelling, the grouping of the below pass, and the
 * arrays of the passes, which keep their memory when they are cleared.
 * \ingroup SmallIsoComponent
 */
template <typename TOutputPixel, unsigned int VDimension>
struct WorkingMemory
{
  using LineRun = RunLabeling::LineRun;

  RunLabeling           Labeling;
  BelowGrouping         Grouping;
  BelowGrouping::Groups Groups;
  /** One flag per component: removed by the above pass, by the below pass. */
  std::vector<uint8_t> RemovedAbove;
  std::vector<uint8_t> RemovedBelow;
  /** One flag per group of the below pass: removed. */
  std::vector<uint8_t> RemovedGroups;
  /** The runs a pass removes, in run order (each pass's in turn). */
  std::vector<LineRun> Runs;
  /** The marks of the parallel collection of Runs. */
  std::vector<uint8_t> Marks;
  /** The repair's new values, one array per chunk. */
  std::vector<std::vector<TOutputPixel>> Values;

  /** Bytes held besides the labelling. */
  SizeValueType
  GetPassBytes() const
  {
    return Grouping.GetScratchBytes() + Groups.GroupOfComponent.capacity() * sizeof(RunLabeling::ComponentIndexType) +
           Groups.GroupSize.capacity() * sizeof(SizeValueType) + RemovedAbove.capacity() + RemovedBelow.capacity() +
           RemovedGroups.capacity() + Runs.capacity() * sizeof(LineRun) + Marks.capacity() +
           Values.capacity() * sizeof(std::vector<TOutputPixel>) +
           RunRepair<TOutputPixel, VDimension>::GetValueBytes(Values);
  }

  /** Gives back all the memory; the labelling keeps its settings. */
  void
  ReleaseMemory()
  {
    Labeling.ReleaseMemory();
    Grouping.ReleaseMemory();
    Groups = BelowGrouping::Groups();
    std::vector<uint8_t>().swap(RemovedAbove);
    std::vector<uint8_t>().swap(RemovedBelow);
    std::vector<uint8_t>().swap(RemovedGroups);
    std::vector<LineRun>().swap(Runs);
    std::vector<uint8_t>().swap(Marks);
    std::vector<std::vector<TOutputPixel>>().swap(Values);
  }
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
