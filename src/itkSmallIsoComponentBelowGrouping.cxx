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
#include "itkSmallIsoComponentBelowGrouping.h"
#include "itkSmallIsoComponentBitCount.h"
#include "itkSmallIsoComponentPrefetch.h"
#include "itkSmallIsoComponentUnionFind.h"
#include "itkSmallIsoComponentTuning.h"
#include <algorithm>

namespace itk
{
namespace SmallIsoComponentDetail
{
// A union-find over components that work units share without locks: a root is linked
// under another root by compare-and-swap, always the larger index under the smaller, so
// every root is the smallest component of its group whatever the order of the links;
// path halving only ever replaces a parent by one of its ancestors.
BelowGrouping::BelowGrouping() = default;

BelowGrouping::BelowGrouping(const RunLabeling & labeling)
{
  this->Reset(labeling);
}

BelowGrouping::~BelowGrouping() = default;

void
BelowGrouping::Reset(const RunLabeling & labeling)
{
  m_Labeling = &labeling;
  const SizeValueType components = labeling.GetComponents().GetNumberOfComponents();
  if (components > m_Capacity)
  {
    m_Parent.reset();
    m_Capacity = 0;
    m_Parent.reset(new std::atomic<ComponentIndexType>[components]);
    m_Capacity = components;
  }
  for (SizeValueType c = 0; c < components; ++c)
  {
    m_Parent[c].store(static_cast<ComponentIndexType>(c), std::memory_order_relaxed);
  }
}

void
BelowGrouping::ReleaseMemory()
{
  m_Labeling = nullptr;
  m_Parent.reset();
  m_Capacity = 0;
}

SizeValueType
BelowGrouping::GetScratchBytes() const
{
  return m_Capacity * sizeof(std::atomic<ComponentIndexType>);
}

namespace
{
/** Joins the component of each flipped run with the below components it touches: the runs
 * beside it in its line (runs alternate sides, so those are below) and the below runs it
 * overlaps in the neighbouring lines. The neighbouring lines' runs are found from their
 * boundary bits (\a VByBits) or by a search of the run starts. Everything is forced inline:
 * the walk passes GCC's inlining limits and would otherwise become calls. */
template <bool VByBits>
class FlippedRunJoins
{
public:
  using ComponentIndexType = BelowGrouping::ComponentIndexType;
  using LineRun = BelowGrouping::LineRun;

  SMALLISO_ALWAYS_INLINE
  FlippedRunJoins(const RunLabeling & labeling, std::atomic<ComponentIndexType> * parent)
    : m_Table(labeling.GetRunTable())
    , m_Neighbors(labeling.GetLineNeighbors())
    , m_Parent(parent)
    , m_Allowance(labeling.IsFullyConnected() ? 1 : 0)
    , m_Lines(labeling.GetNumberOfLines())
    , m_Plane(labeling.GetSize().size() > 1 ? labeling.GetSize()[1] : 1)
    , m_PerVoxel(1.0 / static_cast<double>(m_Table.LineLength))
  {}

  SMALLISO_ALWAYS_INLINE void
  JoinRun(const LineRun & flippedRun)
  {
    const SizeValueType      run = flippedRun.Run;
    const SizeValueType      line = flippedRun.Line;
    const ComponentIndexType flipped = m_Table.Component[run];
    if (run > m_Table.LineBegin[line])
    {
      this->Join(flipped, m_Table.Component[run - 1]);
    }
    if (run + 1 < m_Table.LineBegin[line + 1])
    {
      this->Join(flipped, m_Table.Component[run + 1]);
    }
    // With full connectivity a run also touches the runs that end just before it or start
    // just after it in the neighbouring lines.
    const SizeValueType start = m_Table.Start[run];
    const SizeValueType from = start >= m_Allowance ? start - m_Allowance : 0;
    const SizeValueType to = m_Table.End(run, line) + m_Allowance;
    m_Neighbors.MoveTo(m_Position, line);
    m_Neighbors.ForEachNeighbor(m_Position, [&](SizeValueType other) SMALLISO_LAMBDA_ALWAYS_INLINE {
      this->JoinOverlapping(flipped, other, from, to);
    });
  }

  /** Requests the run \a ahead and where its line's and the neighbouring planes' runs (and
   * bits) begin, a few runs before PrefetchRuns() of the same run needs them. */
  SMALLISO_ALWAYS_INLINE void
  PrefetchLines(const LineRun & ahead) const
  {
    Prefetch(m_Table.Start + ahead.Run);
    Prefetch(m_Table.Component + ahead.Run);
    this->PrefetchLine(ahead.Line);
    if (ahead.Line >= m_Plane)
    {
      this->PrefetchLine(ahead.Line - m_Plane);
    }
    if (ahead.Line + m_Plane < m_Lines)
    {
      this->PrefetchLine(ahead.Line + m_Plane);
    }
  }

  /** Requests the neighbouring lines' runs near where the start of \a ahead falls if runs
   * were spread evenly along the line, where the search for the run holding it looks first. */
  SMALLISO_ALWAYS_INLINE void
  PrefetchRuns(const LineRun & ahead) const
  {
    const SizeValueType line = ahead.Line;
    const SizeValueType start = m_Table.Start[ahead.Run];
    const SizeValueType from = start >= m_Allowance ? start - m_Allowance : 0;
    if (line >= m_Plane)
    {
      this->PrefetchRunsNear(line - m_Plane, from);
    }
    if (line + m_Plane < m_Lines)
    {
      this->PrefetchRunsNear(line + m_Plane, from);
    }
    if (line >= 1)
    {
      this->PrefetchRunsNear(line - 1, from);
    }
    if (line + 1 < m_Lines)
    {
      this->PrefetchRunsNear(line + 1, from);
    }
  }

private:
  /** Joins the two components, unless they are the previous pair. */
  SMALLISO_ALWAYS_INLINE void
  Join(ComponentIndexType flipped, ComponentIndexType below)
  {
    if (flipped != m_LastFlipped || below != m_LastBelow)
    {
      m_LastFlipped = flipped;
      m_LastBelow = below;
      JoinShared(m_Parent, flipped, below);
    }
  }

  /** Joins \a flipped with the below runs of line \a other that overlap [from, to): sides
   * alternate, so every other run from the run that holds from if it is below, else from the
   * run after it, up to the run that holds to - 1. With the lines' boundary bits, a run's index
   * is its line's first run plus the count of the line's boundaries up to it, less one, and
   * the run starts (four bytes a run, where the bits are a bit a voxel) are not read. */
  SMALLISO_ALWAYS_INLINE void
  JoinOverlapping(ComponentIndexType flipped, SizeValueType other, SizeValueType from, SizeValueType to)
  {
    const SizeValueType * const lineBegin = m_Table.LineBegin;
    SizeValueType               below;
    SizeValueType               end;
    if constexpr (VByBits)
    {
      const uint64_t * const bits = m_Table.Bits + other * m_Table.BitsWords;
      const SizeValueType    lastVoxel = std::min(to, m_Table.LineLength) - 1;
      SizeValueType          word = 0;
      SizeValueType          count = lineBegin[other] - 1;
      for (; word < from / 64; ++word)
      {
        count += CountBits(bits[word]);
      }
      below = count + CountBits(bits[word] & BitsUpTo(from % 64));
      for (; word < lastVoxel / 64; ++word)
      {
        count += CountBits(bits[word]);
      }
      end = count + CountBits(bits[word] & BitsUpTo(lastVoxel % 64)) + 1;
    }
    else
    {
      // (A line of a few runs is searched whole.)
      below = lineBegin[other + 1] - lineBegin[other] > 2 * Tuning::NearRuns
                ? m_Table.RunHolding(other, from, m_Table.GuessRunHolding(other, from, m_PerVoxel))
                : m_Table.RunHolding(other, from);
      end = lineBegin[other + 1];
    }
    below += m_Table.IsAbove(below, other) ? 1 : 0;
    for (; below < end && (VByBits || m_Table.Start[below] < to); below += 2)
    {
      this->Join(flipped, m_Table.Component[below]);
    }
  }

  SMALLISO_ALWAYS_INLINE void
  PrefetchLine(SizeValueType line) const
  {
    Prefetch(m_Table.LineBegin + line);
    Prefetch(m_Table.LineFirstAbove + line);
    if constexpr (VByBits)
    {
      Prefetch(m_Table.Bits + line * m_Table.BitsWords);
    }
  }

  SMALLISO_ALWAYS_INLINE void
  PrefetchRunsNear(SizeValueType other, SizeValueType from) const
  {
    constexpr SizeValueType near = Tuning::NearRuns;
    const SizeValueType     guess = m_Table.GuessRunHolding(other, from, m_PerVoxel);
    const SizeValueType     low = guess >= near ? guess - near : 0;
    if constexpr (!VByBits)
    {
      Prefetch(m_Table.Start + low);
      Prefetch(m_Table.Start + guess);
      Prefetch(m_Table.Start + guess + near);
    }
    Prefetch(m_Table.Component + low);
    Prefetch(m_Table.Component + guess);
    Prefetch(m_Table.Component + guess + near);
  }

  const RunLabeling::RunTable       m_Table;
  const LineNeighbors &             m_Neighbors;
  LineNeighbors::Position           m_Position;
  std::atomic<ComponentIndexType> * m_Parent;
  const SizeValueType               m_Allowance;
  const SizeValueType               m_Lines;
  const SizeValueType               m_Plane;
  const double                      m_PerVoxel;
  ComponentIndexType                m_LastFlipped{ BelowGrouping::NoGroup };
  ComponentIndexType                m_LastBelow{ BelowGrouping::NoGroup };
};
} // namespace

template <bool VByBits>
SMALLISO_ALWAYS_INLINE void
BelowGrouping::JoinNeighborsOf(const LineRun * first, const LineRun * last)
{
  FlippedRunJoins<VByBits> joins(*m_Labeling, m_Parent.get());
  // The runs ahead are requested early: first the run itself and where the lines' runs begin,
  // then (a few runs later, once that has arrived) the lines' runs near the run.
  const auto runs = static_cast<SizeValueType>(last - first);
  const bool prefetch = m_Labeling->GetNumberOfRuns() >= Tuning::PrefetchMinimumRuns;
  for (SizeValueType i = 0; i < runs; ++i)
  {
    if (prefetch && i + Tuning::PrefetchLineTablesAhead < runs)
    {
      joins.PrefetchLines(first[i + Tuning::PrefetchLineTablesAhead]);
    }
    if (prefetch && i + Tuning::PrefetchRunsAhead < runs)
    {
      joins.PrefetchRuns(first[i + Tuning::PrefetchRunsAhead]);
    }
    joins.JoinRun(first[i]);
  }
}

void
BelowGrouping::JoinNeighbors(const LineRun * first, const LineRun * last)
{
  if (m_Labeling->GetRunTable().Bits == nullptr)
  {
    this->JoinNeighborsOf<false>(first, last);
    return;
  }
#if defined(SMALLISO_POPCOUNT_DISPATCH)
  if (HasPopcount())
  {
    this->JoinNeighborsByBitsWithPopcount(first, last);
    return;
  }
#endif
  this->JoinNeighborsOf<true>(first, last);
}

#if defined(SMALLISO_POPCOUNT_DISPATCH)
// The same, compiled for processors that count bits in one instruction.
__attribute__((target("popcnt"))) void
BelowGrouping::JoinNeighborsByBitsWithPopcount(const LineRun * first, const LineRun * last)
{
  this->JoinNeighborsOf<true>(first, last);
}
#endif

auto
BelowGrouping::Finish(const std::vector<uint8_t> & flipped) -> Groups
{
  Groups groups;
  this->Finish(flipped, groups);
  return groups;
}

void
BelowGrouping::Finish(const std::vector<uint8_t> & flipped, Groups & groups)
{
  const SizeValueType numberOfComponents = m_Labeling->GetComponents().GetNumberOfComponents();
  groups.GroupOfComponent.assign(numberOfComponents, NoGroup);
  groups.GroupSize.clear();
  // No FindRootShared() is needed: a component's parent is a member of its group with a smaller
  // index (roots are the smallest member, and a root is only ever linked under a smaller
  // one), so the parent's group is known by the time the component is reached.
  for (SizeValueType c = 0; c < numberOfComponents; ++c)
  {
    const auto member = static_cast<ComponentIndexType>(c);
    if (m_Labeling->GetComponents().IsComponentAbove(member) && !flipped[c])
    {
      continue;
    }
    const ComponentIndexType parent = m_Parent[c].load(std::memory_order_relaxed);
    ComponentIndexType       group;
    if (parent == member)
    {
      group = static_cast<ComponentIndexType>(groups.GroupSize.size());
      groups.GroupSize.push_back(0);
    }
    else
    {
      group = groups.GroupOfComponent[parent];
    }
    groups.GroupOfComponent[c] = group;
    groups.GroupSize[group] += m_Labeling->GetComponents().GetComponentSize(member);
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
