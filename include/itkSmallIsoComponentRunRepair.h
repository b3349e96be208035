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
#ifndef itkSmallIsoComponentRunRepair_h
#define itkSmallIsoComponentRunRepair_h

#include "itkSize.h"
#include "itkSmallIsoComponentBelowGrouping.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentThreshold.h"
#include "itkSmallIsoComponentTuning.h"
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class RunRepair
 * \brief The new values of the voxels that one pass of SmallIsoComponentImageFilter
 * removes, and their writing. Internal to the filter.
 *
 * The new value of a removed voxel is the mean of the first values on the other side of
 * the isovalue met when walking from it along each of the 2·N axis directions; a walk that
 * leaves the image finds nothing, and so does one from an above voxel that stops on a NaN.
 * A voxel whose walks all find nothing gets the representable value on the other side
 * closest to the isovalue and counts as unrepairable. The values are computed for all the
 * removed runs, in chunks shared among the work units, before any is written, so that the
 * walks read the image as it was before the pass.
 *
 * \ingroup SmallIsoComponent
 */
template <typename TPixel, unsigned int VDimension>
class ITK_TEMPLATE_EXPORT RunRepair
{
public:
  using LineRun = RunLabeling::LineRun;
  using SizeType = Size<VDimension>;

  /** The repair of \a runs (the runs of the removed components, in run order) in an image
   * of extent \a size, its chunks shared among the members of \a team. The team, the
   * labeling's runs and \a runs must outlive it. */
  RunRepair(WorkTeam & team, const RunLabeling & labeling, const std::vector<LineRun> & runs, const SizeType & size);
  /** The same, the values computed into \a values (one array per chunk), whose memory is
   * kept for the next repair. */
  RunRepair(WorkTeam &                         team,
            const RunLabeling &                labeling,
            const std::vector<LineRun> &       runs,
            const SizeType &                   size,
            std::vector<std::vector<TPixel>> & values);

  /** Computes the new values from \a valuesBeforePass (the image's voxels before the
   * pass) for runs on the side given by \a removedAreAbove. If \a joinFlipped is given,
   * the runs flip for the below pass, and the grouping joins their below neighbours in the
   * same loop, while the runs are in cache. */
  void
  ComputeValues(const TPixel *            valuesBeforePass,
                const Threshold<TPixel> & threshold,
                bool                      removedAreAbove,
                BelowGrouping *           joinFlipped);

  /** ComputeValues() and WriteValues() in one pass, each value written as it is found:
   * only where \a valuesBeforePass is not \a output's buffer (the walks read values before
   * the pass) and no grouping joins the runs. */
  void
  ComputeAndWriteValues(const TPixel *            valuesBeforePass,
                        const Threshold<TPixel> & threshold,
                        bool                      removedAreAbove,
                        TPixel *                  output,
                        uint8_t *                 mask,
                        uint8_t                   maskValue);

  /** Writes the values into \a output and, unless \a mask is null, \a maskValue into
   * \a mask for every voxel of the runs. */
  void
  WriteValues(TPixel * output, uint8_t * mask, uint8_t maskValue) const;

  /** Voxels that got the fallback value. */
  SizeValueType
  GetNumberOfUnrepairableVoxels() const;

  /** Bytes held by the computed values. */
  SizeValueType
  GetValueBytes() const;
  /** Bytes held by the values of the chunks in \a values. */
  static SizeValueType
  GetValueBytes(const std::vector<std::vector<TPixel>> & values);

private:
  /** What one pass's repair reads and, where each value is written as it is found, writes. */
  struct Pass
  {
    Pass(const TPixel *            valuesBeforePass,
         const Threshold<TPixel> & isoValue,
         bool                      removedAreAbove,
         TPixel *                  output = nullptr,
         uint8_t *                 mask = nullptr,
         uint8_t                   maskValue = 0)
      : ValuesBeforePass(valuesBeforePass)
      , IsoValue(isoValue)
      , RemovedAreAbove(removedAreAbove)
      , Fallback(removedAreAbove ? isoValue.HighestBelow() : isoValue.LowestAbove())
      , Output(output)
      , Mask(mask)
      , MaskValue(maskValue)
    {}

    const TPixel *            ValuesBeforePass;
    const Threshold<TPixel> & IsoValue;
    /** Whether the removed voxels are above; the walks stop on the other side. */
    bool RemovedAreAbove;
    /** The value of a voxel whose walks all find nothing. */
    TPixel Fallback;
    /** Null where the values are kept for WriteValues(). */
    TPixel *  Output;
    uint8_t * Mask;
    uint8_t   MaskValue;
  };

  /** ComputeValues() or, with \a output, ComputeAndWriteValues(). */
  void
  Repair(const Pass & pass, BelowGrouping * joinFlipped);

  /** Requests the voxels of \a ahead and their neighbours along the other axes. */
  void
  PrefetchRun(const Pass & pass, const LineRun & ahead) const;

  /** Repairs \a removed: writes its values, or appends them to \a values; counts its
   * unrepairable voxels in \a unrepairable. */
  void
  RepairRun(const Pass &          pass,
            const LineRun &       removed,
            std::vector<TPixel> & values,
            SizeValueType &       unrepairable) const;

  SizeValueType
  ChunkBegin(SizeValueType chunk) const
  {
    return WorkTeam::PartBegin(m_Runs.size(), chunk, m_NumberOfChunks);
  }

  /** Index of the first voxel of \a run in the image buffer. */
  SizeValueType
  FirstVoxel(const LineRun & run) const
  {
    return run.Line * m_Size[0] + m_Table.Start[run.Run];
  }

  /** Calls visit(run) for the runs of \a chunk in order, and prefetch(run) for the run
   * Tuning::PrefetchRunsAhead ahead of each. */
  template <typename TPrefetch, typename TVisit>
  void
  ForEachRunOf(SizeValueType chunk, TPrefetch && prefetch, TVisit && visit) const;

  WorkTeam &                   m_Team;
  const RunLabeling::RunTable  m_Table;
  const std::vector<LineRun> & m_Runs;
  SizeType                     m_Size;
  OffsetValueType              m_Stride[VDimension];
  SizeValueType                m_NumberOfVoxels{ 0 };
  SizeValueType                m_NumberOfChunks;
  /** The new values of each chunk's voxels, in run order, and its unrepairable voxels. */
  std::vector<std::vector<TPixel>>   m_OwnValues;
  std::vector<std::vector<TPixel>> & m_Values;
  std::vector<SizeValueType>         m_Unrepairable;
  /** Whether the loops request what runs ahead read (see Tuning::PrefetchMinimumRuns). */
  bool m_Prefetch;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentRunRepair.hxx"
#endif

#endif
