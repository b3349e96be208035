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
#ifndef itkSmallIsoComponentRunLabeling_h
#define itkSmallIsoComponentRunLabeling_h

#include "itkIntTypes.h"
#include "itkSmallIsoComponentLargeArray.h"
#include "itkSmallIsoComponentLineNeighbors.h"
#include "itkSmallIsoComponentRunComponents.h"
#include "itkSmallIsoComponentRunLinking.h"
#include "itkSmallIsoComponentRunTable.h"
#include "itkSmallIsoComponentWorkTeam.h"
#include "SmallIsoComponentExport.h"
#include "itkSmallIsoComponentTuning.h"
#include <algorithm>
#include <type_traits>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class RunLabeling
 * \brief Connected components of both sides of an isovalue, computed over scanline runs.
 * Internal to SmallIsoComponentImageFilter; the report tool's component counts
 * (sicReportCounting.h, under apps/) are its one other user.
 *
 * The image is seen as lines along axis 0. Each line is split into maximal runs of
 * voxels on one side of the isovalue; runs alternate between the sides, so a line is
 * described by the start of each run and the side of its first run. One union-find over
 * the runs of both sides gives the components of both sides at once.
 *
 * Linking is parallel without locks: the lines are split into slabs of whole planes along
 * the last axis (several per work unit, handed out to the work units as they become free,
 * so that a volume whose runs sit in a few planes still keeps every work unit busy), the
 * runs inside each slab are linked by whoever handles the slab, and the seams between
 * slabs are linked afterwards. The union-find is Rem's algorithm with splicing, linking
 * towards the smaller run index: every parent index stays at or below its run's index,
 * so one pass in run order turns parents into dense component numbers, and the result
 * does not depend on the number of slabs.
 *
 * Two neighbouring lines are linked by a merge of their runs, or, where runs are dense,
 * from the lines' boundary bits (a bit per voxel where a run starts), which finds the
 * touching pairs by bit counts without a branch per run: RunLinking does it, on this
 * class's run arrays.
 *
 * Memory: 4 bytes per run for its start, 4 bytes per run for its parent (later its
 * component), 9 bytes per line, 9 bytes per component, 8 bytes per candidate run
 * (LabelComponents()), and for each work unit the boundary bits of the lines
 * a line reaches back to (at most Tuning::BitsCacheBytes); where lines have Tuning::BitsRunsPerWord / 2 runs
 * per 64 voxels or more on average, the boundary bits of every line instead (one bit per
 * voxel, at most 1/6 byte per run). The arrays keep their memory from one Initialize() to
 * the next (the run arrays take huge pages where the system offers them), so that
 * labelling an image like the last one takes no fresh memory; ReleaseMemory() gives it
 * back. The object is on cache lines of its own: while one work unit numbers the
 * components, which writes the ends of the component arrays all along, others work
 * beside it, and on a cache line it shared with their data both would wait on each other.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT RunLabeling
{
public:
  using RunIndexType = RunLinking::RunIndexType;
  using ComponentIndexType = RunComponents::ComponentIndexType;
  using CoordinateType = RunLinking::CoordinateType;

  /** Sets the image extent (axis 0 is the scanline axis), the connectivity, and the
   * number of work units the work will be shared among (the lines are cut into up to
   * Tuning::SlabsPerWorkUnit slabs per work unit, one slab for one work unit). Clears earlier
   * results. */
  void
  Initialize(const std::vector<SizeValueType> & size, bool fullyConnected, unsigned int maximumNumberOfSlabs);

  SizeValueType
  GetLineLength() const
  {
    return m_Size[0];
  }
  SizeValueType
  GetNumberOfLines() const
  {
    return m_NumberOfLines;
  }
  /** The number of runs (after ReserveRuns()). */
  SizeValueType
  GetNumberOfRuns() const
  {
    return m_NumberOfRuns;
  }
  SizeValueType
  GetNumberOfSlabs() const
  {
    return m_SlabBeginLine.size() - 1;
  }
  /** First line of a slab; GetSlabBeginLine(GetNumberOfSlabs()) is the number of lines. */
  SizeValueType
  GetSlabBeginLine(SizeValueType slab) const
  {
    return m_SlabBeginLine[slab];
  }

  /** \name Run encoding
   * RunEncoder calls SetLineRuns() once per line with the line's number of runs, then
   * ReserveRuns(), then writes the starts of each line's runs at GetLineRunStarts(line);
   * different lines may be done concurrently. AssembleRuns() then links the runs inside
   * each slab. */
  /** @{ */
  void
  SetLineRuns(SizeValueType line, SizeValueType numberOfRuns, bool firstRunIsAbove)
  {
    m_LineRunBegin[line + 1] = numberOfRuns;
    m_LineFirstAbove[line] = firstRunIsAbove;
  }
  /** Turns the lines' run counts into the first run of each line and makes room for all
   * the runs (memory kept from an earlier image of as many runs or more is reused). Throws
   * if there are 2^32 - 1 runs or more. */
  void
  ReserveRuns();
  /** Where the starts of \a line's runs go (after ReserveRuns()). */
  CoordinateType *
  GetLineRunStarts(SizeValueType line)
  {
    return m_RunStart.data() + m_LineRunBegin[line];
  }
  /** Where \a line's boundary bits go (after ReserveRuns()), or nullptr when they are not
   * kept: kept, for every line, where the lines have Tuning::BitsRunsPerWord / 2 runs per 64 voxels
   * or more on average (and lines are linked automatically); whoever writes the line's
   * starts writes them too (bit 0 set, since a run starts there), as RunEncoder does from
   * the words of changes of side it finds the starts with. */
  uint64_t *
  GetKeptLineBits(SizeValueType line)
  {
    return m_Linking.GetKeptLineBits(line);
  }
  /** Links the runs inside each slab, the slabs shared among the members of \a team. */
  void
  AssembleRuns(WorkTeam & team);
  /** @} */

  /** Links the runs of each side that touch under the chosen connectivity (what
   * AssembleRuns() left: the seams between slabs). */
  void
  LinkRuns();

  /** Numbers the components in order of their first run and sums their sizes, keeping the
   * candidate runs of each side (RunComponents::Number()); with \a team, shared as
   * \a sharing allows. */
  void
  LabelComponents(SizeValueType aboveCandidateSize, SizeValueType belowCandidateSize);
  void
  LabelComponents(WorkTeam &                     team,
                  SizeValueType                  aboveCandidateSize,
                  SizeValueType                  belowCandidateSize,
                  const RunComponents::Sharing & sharing = {});

  /** The components, after LabelComponents(): sizes, sides and candidate runs. */
  const RunComponents &
  GetComponents() const
  {
    return m_Components;
  }
  using LineRun = RunComponents::LineRun;

  /** The runs, read-only, as arrays (RunTable): valid from AssembleRuns() until the next
   * Initialize(). */
  using RunTable = SmallIsoComponentDetail::RunTable;
  static_assert(std::is_same_v<RunTable::CoordinateType, CoordinateType> &&
                  std::is_same_v<RunTable::ComponentIndexType, ComponentIndexType>,
                "RunTable reads the run arrays with their own types");
  RunTable
  GetRunTable() const
  {
    return { m_RunStart.data(), m_RunLabel.data(),       m_LineRunBegin.data(),   m_LineFirstAbove.data(),
             m_Size[0],         m_Linking.GetKeptBits(), m_Linking.GetBitsWords() };
  }

  /** The image extent given to Initialize() (axis 0 along the lines). */
  const std::vector<SizeValueType> &
  GetSize() const
  {
    return m_Size;
  }
  bool
  IsFullyConnected() const
  {
    return m_FullyConnected;
  }
  /** The neighbouring lines of each line under the connectivity. */
  const SmallIsoComponentDetail::LineNeighbors &
  GetLineNeighbors() const
  {
    return m_Linking.GetLineNeighbors();
  }

  /** Bytes held now by the run, line and component arrays (with what they keep from an
   * earlier, larger image). */
  SizeValueType
  GetMemoryInBytes() const;
  /** Most bytes held at once so far. */
  SizeValueType
  GetPeakMemoryInBytes() const
  {
    return std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
  }

  /** Gives back all the memory the arrays hold; Initialize() must come before the next
   * use. Otherwise the arrays keep their memory from one image to the next. */
  void
  ReleaseMemory();

protected:
  /** \name Ways of working that only the tests choose
   * Each changes how the work is done, never its result; the tests reach them through a
   * class derived for the purpose. */
  /** @{ */
  /** How two neighbouring lines have their runs linked. */
  using LineLinking = RunLinking::LineLinking;
  /** Chooses how lines are linked and how many bytes of boundary bits a work unit keeps,
   * from the next Initialize() on. */
  void
  SetLineLinking(LineLinking linking, SizeValueType bitsCacheBytes = Tuning::BitsCacheBytes)
  {
    m_Linking.SetLineLinking(linking, bitsCacheBytes);
  }
  /** Sets the runs from which the numbering is shared, and the lines per claim of a
   * shared numbering (at least 1). */
  void
  SetMinimumRunsToShareNumbering(SizeValueType runs)
  {
    m_Components.SetMinimumRunsToShare(runs);
  }
  void
  SetLinesPerClaim(SizeValueType lines)
  {
    m_Components.SetLinesPerClaim(lines);
  }
  /** @} */

private:
  // The aligned member aligns the object: GCC refuses alignas on an exported class.
  alignas(64) std::vector<SizeValueType> m_Size;
  SizeValueType              m_NumberOfLines{ 0 };
  bool                       m_FullyConnected{ false };
  std::vector<SizeValueType> m_SlabBeginLine;

  SizeValueType m_NumberOfRuns{ 0 };
  /** Arrays of at least m_NumberOfRuns entries, left uninitialised so that the parallel
   * fill touches their pages first. */
  LargeArray<CoordinateType> m_RunStart;
  std::vector<SizeValueType> m_LineRunBegin;
  std::vector<uint8_t>       m_LineFirstAbove;
  LargeArray<RunIndexType>   m_RunLabel;
  SizeValueType              m_PeakMemoryInBytes{ 0 };
  /** The components of the linked runs. */
  RunComponents m_Components;
  /** The linking of the runs of neighbouring lines, with its boundary bits. */
  RunLinking m_Linking;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
