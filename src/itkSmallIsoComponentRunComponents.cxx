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
#include "itkSmallIsoComponentRunComponents.h"
#include "itkNumericTraits.h"
#include "itkSmallIsoComponentBitCount.h"
#include <algorithm>
#include <numeric>
#include <thread>
#include <type_traits>


namespace itk
{
namespace SmallIsoComponentDetail
{
namespace
{
/** Resizes \a sizes to \a count entries (new ones 0), its capacity doubled as often as
 * needed: the capacity is then that which adding the entries one by one gives, whatever
 * steps it was resized in (the shared numbering's depend on timing). */
void
GrowSizes(std::vector<SizeValueType> & sizes, SizeValueType count)
{
  if (count > sizes.capacity())
  {
    SizeValueType capacity = std::max<SizeValueType>(sizes.capacity(), 1);
    while (capacity < count)
    {
      capacity *= 2;
    }
    sizes.reserve(capacity);
  }
  sizes.resize(count, 0);
}

/** Candidate runs gathered in a small buffer, appended to \a runs when it is full and at the
 * end: a run is one store, and the vector is reached once per Tuning::CandidateBufferRuns runs. TEntry is
 * RunComponents::CandidateRun (a run and its component) or RunComponents::LineRun (a run and its
 * line). */
template <typename TEntry>
class CandidateBuffer
{
public:
  explicit CandidateBuffer(std::vector<TEntry> & runs)
    : m_Runs(runs)
  {}
  void
  Add(SizeValueType run, SizeValueType line, SizeValueType component)
  {
    if constexpr (std::is_same<TEntry, RunComponents::LineRun>::value)
    {
      m_Buffer[m_Count++] = { static_cast<RunComponents::RunIndexType>(run),
                              static_cast<RunComponents::RunIndexType>(line) };
    }
    else
    {
      m_Buffer[m_Count++] = { static_cast<RunComponents::RunIndexType>(run),
                              static_cast<RunComponents::ComponentIndexType>(component) };
    }
    if (m_Count == Tuning::CandidateBufferRuns)
    {
      this->Flush();
    }
  }
  void
  Flush()
  {
    m_Runs.insert(m_Runs.end(), m_Buffer, m_Buffer + m_Count);
    m_Count = 0;
  }

private:
  std::vector<TEntry> & m_Runs;
  TEntry                m_Buffer[Tuning::CandidateBufferRuns];
  SizeValueType         m_Count{ 0 };
};

/** Adds the runs of \a line to the sizes of their components (numbered already), and keeps
 * as candidates those whose component has at most candidateSize[its side] voxels so far. */
template <typename TSize, typename TEntry>
SMALLISO_ALWAYS_INLINE void
SumLine(const RunTable &          table,
        SizeValueType             line,
        TSize *                   sizes,
        const SizeValueType       candidateSize[2],
        CandidateBuffer<TEntry> & candidates)
{
  const SizeValueType end = table.LineBegin[line + 1];
  bool                above = table.LineFirstAbove[line] != 0;
  for (SizeValueType run = table.LineBegin[line]; run < end; ++run, above = !above)
  {
    const SizeValueType component = table.Component[run];
    const SizeValueType size =
      sizes[component] + (run + 1 < end ? SizeValueType{ table.Start[run + 1] } : table.LineLength) - table.Start[run];
    sizes[component] = static_cast<TSize>(size);
    if (size <= candidateSize[above])
    {
      candidates.Add(run, line, component);
    }
  }
}
} // namespace

void
RunComponents::SetRuns(const CoordinateType * start,
                       RunIndexType *         label,
                       const SizeValueType *  lineBegin,
                       const uint8_t *        lineFirstAbove,
                       SizeValueType          lineLength,
                       SizeValueType          numberOfLines)
{
  m_Start = start;
  m_Label = label;
  m_LineBegin = lineBegin;
  m_LineFirstAbove = lineFirstAbove;
  m_LineLength = lineLength;
  m_NumberOfLines = numberOfLines;
  this->Clear();
}

void
RunComponents::Clear()
{
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  m_CandidateRuns.clear();
}

void
RunComponents::ReleaseMemory()
{
  m_ComponentSize = std::vector<SizeValueType>();
  m_ComponentAbove = std::vector<uint8_t>();
  m_CandidateRuns = std::vector<CandidateRun>();
  m_ClaimBegin = std::vector<SizeValueType>();
}

RunTable
RunComponents::Table() const
{
  return { m_Start, m_Label, m_LineBegin, m_LineFirstAbove, m_LineLength, nullptr, 0 };
}

SizeValueType
RunComponents::LineOfRun(SizeValueType run) const
{
  return static_cast<SizeValueType>(std::upper_bound(m_LineBegin, m_LineBegin + m_NumberOfLines + 1, run) -
                                    m_LineBegin) -
         1;
}

void
RunComponents::Number(SizeValueType aboveCandidateSize, SizeValueType belowCandidateSize)
{
  this->Clear();
  RunIndexType * const          label = m_Label;
  const CoordinateType * const  start = m_Start;
  const SizeValueType           length = m_LineLength;
  CandidateBuffer<CandidateRun> candidates(m_CandidateRuns);
  const SizeValueType           candidateSize[2] = { belowCandidateSize, aboveCandidateSize };
  // The sizes are reached through a local pointer, renewed when a component is added, so
  // that the loop does not read the vector's again for every run.
  SizeValueType * sizes = m_ComponentSize.data();
  for (SizeValueType line = 0; line < m_NumberOfLines; ++line)
  {
    const SizeValueType end = m_LineBegin[line + 1];
    bool                above = m_LineFirstAbove[line] != 0;
    for (SizeValueType run = m_LineBegin[line]; run < end; ++run, above = !above)
    {
      // Parents never point to a later run, so the parent's entry already holds its
      // component number.
      const RunIndexType parent = label[run];
      RunIndexType       component;
      if (parent == run)
      {
        component = static_cast<ComponentIndexType>(m_ComponentSize.size());
        m_ComponentSize.push_back(0);
        m_ComponentAbove.push_back(above);
        sizes = m_ComponentSize.data();
      }
      else
      {
        component = label[parent];
      }
      label[run] = component;
      const SizeValueType size =
        sizes[component] + (run + 1 < end ? SizeValueType{ start[run + 1] } : length) - start[run];
      sizes[component] = size;
      // A component's size only grows, so every run of a component that ends at most
      // candidateSize voxels large is kept, in a small buffer emptied when full. A branch,
      // though mispredicted where a speck begins or ends, is faster than storing every run
      // into the buffer without one: few runs are candidates.
      if (size <= candidateSize[above])
      {
        candidates.Add(run, line, component);
      }
    }
  }
  candidates.Flush();
}

void
RunComponents::Number(WorkTeam &      team,
                      SizeValueType   aboveCandidateSize,
                      SizeValueType   belowCandidateSize,
                      const Sharing & sharing)
{
  const std::function<bool()> & otherWork = sharing.OtherWork;
  const auto                    doOtherWork = [&otherWork] {
    if (otherWork)
    {
      while (otherWork())
      {}
    }
  };
  if (team.GetNumberOfWorkUnits() < 2 || !sharing.Pipeline || m_LineBegin[m_NumberOfLines] < m_MinimumRunsToShare)
  {
    // Serial, the other work beside it (with one work unit, no other work: ForEach() then
    // runs item 0 alone).
    team.ForEach(team.GetNumberOfWorkUnits(), [&](SizeValueType item) {
      if (item == 0)
      {
        this->Number(aboveCandidateSize, belowCandidateSize);
      }
      else
      {
        doOtherWork();
      }
    });
    return;
  }
  this->Clear();
  const SizeValueType candidateSize[2] = { belowCandidateSize, aboveCandidateSize };
  Progress            progress;
  // The second stage takes every claim unless the first helps it.
  const SizeValueType   claims = (m_NumberOfLines + m_LinesPerClaim - 1) / m_LinesPerClaim;
  std::atomic<uint64_t> claimed{ uint64_t{ claims } << 32 };
  bool                  helped = false;
  // The items are handed out in order: whoever takes the second finds the first under way
  // (or done), and the first never waits.
  team.ForEach(team.GetNumberOfWorkUnits(), [&](SizeValueType stage) {
    if (stage == 0)
    {
      // The shorter stage: the other work after it, then the help.
      this->NumberRuns(progress);
      doOtherWork();
      if (sharing.PartialSizes != nullptr && sharing.PartialCandidates != nullptr)
      {
        helped =
          this->SumComponentsFromTheEnd(claimed, candidateSize, *sharing.PartialSizes, *sharing.PartialCandidates);
      }
    }
    else if (stage == 1)
    {
      this->SumComponents(progress, candidateSize, otherWork, claimed);
    }
    else
    {
      doOtherWork();
    }
  });
  if (helped)
  {
    this->AddSumsFromTheEnd(candidateSize, *sharing.PartialSizes, *sharing.PartialCandidates);
  }
}

void
RunComponents::AddSumsFromTheEnd(const SizeValueType                     candidateSize[2],
                                 const std::vector<ComponentIndexType> & partialSizes,
                                 std::vector<LineRun> &                  partialCandidates)
{
  // The components first met in the helper's lines have no size yet.
  const SizeValueType components = m_ComponentAbove.size();
  GrowSizes(m_ComponentSize, components);
  const ComponentIndexType * const partial = partialSizes.data();
  SizeValueType * const            sizes = m_ComponentSize.data();
  for (SizeValueType component = 0; component < components; ++component)
  {
    sizes[component] += partial[component];
  }
  // The helper's claims, taken from the end, are appended in line order, and only the
  // runs of components of at most the candidate size: its partial sizes kept others too,
  // and the candidates are never more than the serial numbering's (the arrays sized by
  // them keep the size of the first update).
  const RunIndexType * const    label = m_Label;
  CandidateBuffer<CandidateRun> candidates(m_CandidateRuns);
  for (SizeValueType claim = m_ClaimBegin.size() - 1; claim > 0; --claim)
  {
    for (SizeValueType i = m_ClaimBegin[claim - 1]; i < m_ClaimBegin[claim]; ++i)
    {
      const LineRun      candidate = partialCandidates[i];
      const RunIndexType component = label[candidate.Run];
      if (sizes[component] <= candidateSize[m_ComponentAbove[component]])
      {
        candidates.Add(candidate.Run, candidate.Line, component);
      }
    }
  }
  candidates.Flush();
  partialCandidates.clear();
}

void
RunComponents::NumberRuns(Progress & progress)
{
  RunIndexType * const label = m_Label;
  ComponentIndexType   components = 0;
  for (SizeValueType line = 0; line < m_NumberOfLines; ++line)
  {
    const SizeValueType end = m_LineBegin[line + 1];
    bool                above = m_LineFirstAbove[line] != 0;
    for (SizeValueType run = m_LineBegin[line]; run < end; ++run, above = !above)
    {
      // Parents never point to a later run, so the parent's entry already holds its
      // component number.
      const RunIndexType parent = label[run];
      RunIndexType       component;
      if (parent == run)
      {
        component = components++;
        m_ComponentAbove.push_back(above);
      }
      else
      {
        component = label[parent];
      }
      label[run] = component;
    }
    if ((line + 1) % Tuning::NumberingLinesPerStep == 0)
    {
      progress.Components.store(components, std::memory_order_relaxed);
      progress.Lines.store(line + 1, std::memory_order_release);
    }
  }
  progress.Components.store(components, std::memory_order_relaxed);
  progress.Lines.store(m_NumberOfLines, std::memory_order_release);
}

void
RunComponents::SumComponents(const Progress &              progress,
                             const SizeValueType           candidateSize[2],
                             const std::function<bool()> & otherWork,
                             std::atomic<uint64_t> &       claims)
{
  const RunTable                table = this->Table();
  CandidateBuffer<CandidateRun> candidates(m_CandidateRuns);
  SizeValueType *               sizes = m_ComponentSize.data();
  SizeValueType                 ready = 0;
  uint64_t                      claimed = claims.load(std::memory_order_relaxed);
  while (true)
  {
    // The next claim from the front, unless the first stage has taken it from the end. The
    // claims only share the lines out: the results are joined after the loop.
    const uint64_t front = claimed & 0xffffffffU;
    if (front >= (claimed >> 32))
    {
      break;
    }
    if (!claims.compare_exchange_weak(claimed, claimed + 1, std::memory_order_relaxed))
    {
      continue;
    }
    claimed = claimed + 1;
    const SizeValueType lastLine = std::min(m_NumberOfLines, (front + 1) * m_LinesPerClaim);
    for (SizeValueType line = front * m_LinesPerClaim; line < lastLine; ++line)
    {
      if (line >= ready)
      {
        // The sizes of the components numbered so far are made room for at once, rather
        // than one by one behind a branch on every run.
        while ((ready = progress.Lines.load(std::memory_order_acquire)) <= line)
        {
          if (!otherWork || !otherWork())
          {
            std::this_thread::yield();
          }
        }
        GrowSizes(m_ComponentSize, progress.Components.load(std::memory_order_relaxed));
        sizes = m_ComponentSize.data();
      }
      SumLine(table, line, sizes, candidateSize, candidates);
    }
  }
  candidates.Flush();
}

bool
RunComponents::SumComponentsFromTheEnd(std::atomic<uint64_t> &           claims,
                                       const SizeValueType               candidateSize[2],
                                       std::vector<ComponentIndexType> & partialSizes,
                                       std::vector<LineRun> &            candidateRuns)
{
  const RunTable      table = this->Table();
  const SizeValueType length = m_LineLength;
  // The partial sizes have 32 bits: the help ends before its lines could hold more voxels.
  // It ends too before the candidates could fill the capacity the scratch has already
  // (every run of a claim could be one): the help takes no memory of its own (and none
  // the first time).
  const SizeValueType voxelsPerClaim = m_LinesPerClaim * length;
  const SizeValueType room = candidateRuns.capacity();
  SizeValueType       voxels = 0;
  uint64_t            claimed = claims.load(std::memory_order_relaxed);
  bool                first = true;
  while (voxels + voxelsPerClaim <= NumericTraits<ComponentIndexType>::max())
  {
    const uint64_t back = claimed >> 32;
    if ((claimed & 0xffffffffU) >= back)
    {
      break;
    }
    const SizeValueType claim = back - 1;
    const SizeValueType firstLine = claim * m_LinesPerClaim;
    const SizeValueType lastLine = std::min(m_NumberOfLines, firstLine + m_LinesPerClaim);
    const SizeValueType claimRuns = m_LineBegin[lastLine] - m_LineBegin[firstLine];
    if (candidateRuns.size() + claimRuns > room)
    {
      break;
    }
    if (!claims.compare_exchange_weak(claimed, claimed - (uint64_t{ 1 } << 32), std::memory_order_relaxed))
    {
      continue;
    }
    claimed = claimed - (uint64_t{ 1 } << 32);
    if (first)
    {
      partialSizes.assign(m_ComponentAbove.size(), 0);
      candidateRuns.clear();
      m_ClaimBegin.assign(1, 0);
      first = false;
    }
    ComponentIndexType * const sizes = partialSizes.data();
    CandidateBuffer<LineRun>   candidates(candidateRuns);
    for (SizeValueType line = firstLine; line < lastLine; ++line)
    {
      // A component with at most candidateSize voxels has at most as many here: its runs
      // are all kept.
      SumLine(table, line, sizes, candidateSize, candidates);
    }
    candidates.Flush();
    voxels += voxelsPerClaim;
    m_ClaimBegin.push_back(candidateRuns.size());
  }
  return !first;
}

auto
RunComponents::CollectCandidateRuns(const std::vector<uint8_t> & selected) const -> std::vector<LineRun>
{
  std::vector<LineRun> runs;
  this->CollectCandidateRuns(selected, runs);
  return runs;
}

void
RunComponents::CollectCandidateRuns(const std::vector<uint8_t> & selected, std::vector<LineRun> & runs) const
{
  runs.clear();
  const SizeValueType        candidates = m_CandidateRuns.size();
  const CandidateRun * const candidate = m_CandidateRuns.data();
  if (candidates == 0)
  {
    return;
  }
  // The candidates are in run order: the line of each selected one is found by moving a
  // cursor forward from the first candidate's.
  const SizeValueType * const lineBegin = m_LineBegin;
  SizeValueType               line = this->LineOfRun(candidate[0].Run);
  for (SizeValueType i = 0; i < candidates; ++i)
  {
    if (selected[candidate[i].Component])
    {
      while (lineBegin[line + 1] <= candidate[i].Run)
      {
        ++line;
      }
      runs.push_back({ candidate[i].Run, static_cast<RunIndexType>(line) });
    }
  }
}

void
RunComponents::CollectCandidateRuns(const std::vector<uint8_t> & selected,
                                    WorkTeam &                   team,
                                    std::vector<uint8_t> &       marked,
                                    std::vector<LineRun> &       runs) const
{
  const SizeValueType candidates = m_CandidateRuns.size();
  const SizeValueType parts = team.GetNumberOfParts(candidates);
  if (parts == 1)
  {
    this->CollectCandidateRuns(selected, runs);
    return;
  }
  const CandidateRun * const candidate = m_CandidateRuns.data();
  marked.resize(candidates);
  std::vector<SizeValueType> partBegin(parts + 1, 0);
  team.ForEach(parts, [&](SizeValueType part) {
    const SizeValueType end = WorkTeam::PartBegin(candidates, part + 1, parts);
    SizeValueType       count = 0;
    for (SizeValueType i = WorkTeam::PartBegin(candidates, part, parts); i < end; ++i)
    {
      marked[i] = selected[candidate[i].Component];
      count += marked[i];
    }
    partBegin[part + 1] = count;
  });
  std::partial_sum(partBegin.begin(), partBegin.end(), partBegin.begin());
  runs.resize(partBegin[parts]);
  const SizeValueType * const lineBegin = m_LineBegin;
  team.ForEach(parts, [&](SizeValueType part) {
    const SizeValueType begin = WorkTeam::PartBegin(candidates, part, parts);
    const SizeValueType end = WorkTeam::PartBegin(candidates, part + 1, parts);
    if (begin == end)
    {
      return;
    }
    LineRun *     out = runs.data() + partBegin[part];
    SizeValueType line = this->LineOfRun(candidate[begin].Run);
    for (SizeValueType i = begin; i < end; ++i)
    {
      if (marked[i])
      {
        while (lineBegin[line + 1] <= candidate[i].Run)
        {
          ++line;
        }
        *out++ = { candidate[i].Run, static_cast<RunIndexType>(line) };
      }
    }
  });
}

SizeValueType
RunComponents::GetMemoryInBytes() const
{
  return m_ComponentSize.capacity() * sizeof(SizeValueType) + m_ComponentAbove.capacity() +
         m_CandidateRuns.capacity() * sizeof(CandidateRun) + m_ClaimBegin.capacity() * sizeof(SizeValueType);
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
