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
#ifndef itkSmallIsoComponentRunComponents_h
#define itkSmallIsoComponentRunComponents_h

#include "itkIntTypes.h"
#include "itkSmallIsoComponentRunTable.h"
#include "itkSmallIsoComponentTuning.h"
#include "itkSmallIsoComponentWorkTeam.h"
#include "SmallIsoComponentExport.h"
#include <atomic>
#include <functional>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class RunComponents
 * \brief The components of linked runs: numbers them in order of their first run, sums
 * their sizes and keeps the runs of the small ones as candidates for removal.
 * Internal to RunLabeling, which holds the runs and lends this class its run arrays.
 *
 * Each run's label holds its parent, never a later run, once the runs are linked: one pass
 * in run order turns the parents into dense component numbers. With several work units the
 * pass can be shared as a pipeline (one numbers, the other sums behind it) with the same
 * result as the serial pass.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT RunComponents
{
public:
  using RunIndexType = uint32_t;
  using ComponentIndexType = RunTable::ComponentIndexType;
  using CoordinateType = RunTable::CoordinateType;

  /** A run and its line (lines are fewer than runs, so both fit the run index type). */
  struct LineRun
  {
    RunIndexType Run;
    RunIndexType Line;
  };

  /** The runs to number: RunLabeling's arrays, valid until they are made room for again.
   * \a label holds each run's parent and receives its component. Clears the components. */
  void
  SetRuns(const CoordinateType * start,
          RunIndexType *         label,
          const SizeValueType *  lineBegin,
          const uint8_t *        lineFirstAbove,
          SizeValueType          lineLength,
          SizeValueType          numberOfLines);
  /** Forgets the components (their arrays keep their memory). */
  void
  Clear();
  /** Gives back the memory of the arrays; the ways of sharing stay. */
  void
  ReleaseMemory();

  /** Numbers the components and sums their sizes, keeping as candidates (see
   * CollectCandidateRuns()) every run whose component has at most the candidate size of its
   * side up to and including that run: all the runs of every component of at most that size,
   * and a few runs of the larger ones. A side whose candidate size is 0 keeps none. */
  void
  Number(SizeValueType aboveCandidateSize, SizeValueType belowCandidateSize);

  /** How Number() may share its work among the work units of a team. */
  struct Sharing
  {
    /** Does one piece of some other work and returns true, or returns false when none is
     * left; called concurrently by the work units that would wait, so it must hand out its
     * pieces safely. What it leaves is the caller's. */
    std::function<bool()> OtherWork;
    /** Whether the pipeline may run at all (else the numbering is serial, the other work
     * beside it). */
    bool Pipeline{ true };
    /** Scratch for the first stage's help from the end (contents lost, memory kept): the
     * partial sizes and the candidates of the lines it sums, while they fit the capacity the
     * candidates' array has already. None: no help. */
    std::vector<ComponentIndexType> * PartialSizes{ nullptr };
    std::vector<LineRun> *            PartialCandidates{ nullptr };
  };
  /** Number(), as a pipeline between two work units of \a team when it has several and
   * there are at least Tuning::MinimumRunsToShareNumbering runs: the first numbers the runs,
   * line by line, and the second follows it, summing the sizes and keeping the candidates.
   * The first, once done, does the other work and then sums lines from the end into the
   * scratch, whose sums are added at the end. Sizes and sides are those of the serial
   * numbering, and so are the candidates except in the lines summed from the end: there only
   * the runs of components of at most the candidate size are kept. */
  void
  Number(WorkTeam & team, SizeValueType aboveCandidateSize, SizeValueType belowCandidateSize, const Sharing & sharing);

  SizeValueType
  GetNumberOfComponents() const
  {
    return m_ComponentSize.size();
  }
  SizeValueType
  GetComponentSize(ComponentIndexType component) const
  {
    return m_ComponentSize[component];
  }
  bool
  IsComponentAbove(ComponentIndexType component) const
  {
    return m_ComponentAbove[component] != 0;
  }

  /** The candidate runs whose component is flagged in \a selected, in run order: every run
   * of the selected components if they have at most the candidate size. Visits the
   * candidates only, not every run. */
  std::vector<LineRun>
  CollectCandidateRuns(const std::vector<uint8_t> & selected) const;
  /** The same into \a runs (which keeps its memory). */
  void
  CollectCandidateRuns(const std::vector<uint8_t> & selected, std::vector<LineRun> & runs) const;
  /** The same, the candidates shared among the work units of \a team in as many parts: each
   * part marks its selected candidates in \a marked (one byte per candidate) and counts them,
   * then copies them to its place in \a runs. */
  void
  CollectCandidateRuns(const std::vector<uint8_t> & selected,
                       WorkTeam &                   team,
                       std::vector<uint8_t> &       marked,
                       std::vector<LineRun> &       runs) const;

  /** Bytes held by the component and candidate arrays. */
  SizeValueType
  GetMemoryInBytes() const;

  /** Ways of sharing the numbering that only the tests choose (never its result): the runs
   * from which it is shared, and the lines per claim (at least 1). */
  void
  SetMinimumRunsToShare(SizeValueType runs)
  {
    m_MinimumRunsToShare = runs;
  }
  void
  SetLinesPerClaim(SizeValueType lines)
  {
    m_LinesPerClaim = std::max(lines, SizeValueType{ 1 });
  }

private:
  /** A candidate run and its component: the collection reads which components are selected
   * without reading the components array, and finds the lines by a cursor. */
  struct CandidateRun
  {
    RunIndexType       Run;
    ComponentIndexType Component;
  };
  /** How far the first stage of the pipeline is: the lines whose runs have their
   * components, and the components numbered by then (at least). */
  struct Progress
  {
    std::atomic<SizeValueType> Lines{ 0 };
    std::atomic<SizeValueType> Components{ 0 };
  };

  RunTable
  Table() const;
  /** The line of \a run (a binary search over the lines' first runs). */
  SizeValueType
  LineOfRun(SizeValueType run) const;
  /** The pipeline's first stage: gives every run its component and every component its
   * side, and says in \a progress how far it is. */
  void
  NumberRuns(Progress & progress);
  /** The second stage: the sizes and candidates of the components, line by line as
   * \a progress allows. */
  void
  SumComponents(const Progress &              progress,
                const SizeValueType           candidateSize[2],
                const std::function<bool()> & otherWork,
                std::atomic<uint64_t> &       claims);
  /** The first stage's help: the lines it takes from the end, a claim at a time, summed
   * into \a partialSizes, their candidates (by these partial sizes) into \a candidates, where
   * each claim's begin in m_ClaimBegin. Returns whether it took any. */
  bool
  SumComponentsFromTheEnd(std::atomic<uint64_t> &           claims,
                          const SizeValueType               candidateSize[2],
                          std::vector<ComponentIndexType> & partialSizes,
                          std::vector<LineRun> &            candidates);
  /** Adds the help's partial sums to the sizes and its candidates, in line order. */
  void
  AddSumsFromTheEnd(const SizeValueType                     candidateSize[2],
                    const std::vector<ComponentIndexType> & partialSizes,
                    std::vector<LineRun> &                  partialCandidates);

  const CoordinateType * m_Start{ nullptr };
  RunIndexType *         m_Label{ nullptr };
  const SizeValueType *  m_LineBegin{ nullptr };
  const uint8_t *        m_LineFirstAbove{ nullptr };
  SizeValueType          m_LineLength{ 0 };
  SizeValueType          m_NumberOfLines{ 0 };

  std::vector<SizeValueType> m_ComponentSize;
  std::vector<uint8_t>       m_ComponentAbove;
  std::vector<CandidateRun>  m_CandidateRuns;
  /** Where each claim the help took begins in its candidates (kept between updates). */
  std::vector<SizeValueType> m_ClaimBegin;
  SizeValueType              m_MinimumRunsToShare{ Tuning::MinimumRunsToShareNumbering };
  SizeValueType              m_LinesPerClaim{ Tuning::LinesPerClaim };
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
