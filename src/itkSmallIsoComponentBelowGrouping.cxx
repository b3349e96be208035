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
  const SizeValueType components = labeling.GetNumberOfComponents();
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

template <bool VByBits>
SMALLISO_ALWAYS_INLINE void
BelowGrouping::JoinNeighborsOf(const LineRun * first, const LineRun * last)
{
  // Each flipped run touches the runs beside it in its line (runs alternate sides, so
  // those are below) and the below runs it overlaps in the neighbouring lines; its
  // component joins theirs. A repeat of the previous pair is skipped.
  using CoordinateType = RunLabeling::CoordinateType;
  const RunLabeling::RunTable      table = m_Labeling->GetRunTable();
  const CoordinateType * const     runStart = table.Start;
  const ComponentIndexType * const component = table.Component;
  const SizeValueType * const      lineRunBegin = table.LineBegin;
  const uint8_t * const            lineFirstAbove = table.LineFirstAbove;
  const LineNeighbors &            neighbors = m_Labeling->GetLineNeighbors();
  LineNeighbors::Position          position;
  // With full connectivity a run also touches the runs that end just before it or start
  // just after it in the neighbouring lines.
  const SizeValueType allowance = m_Labeling->IsFullyConnected() ? 1 : 0;
  ComponentIndexType  lastFlipped = NoGroup;
  ComponentIndexType  lastBelow = NoGroup;
  const auto          join = [&](ComponentIndexType flipped, ComponentIndexType below) {
    if (flipped != lastFlipped || below != lastBelow)
    {
      lastFlipped = flipped;
      lastBelow = below;
      JoinShared(m_Parent.get(), flipped, below);
    }
  };
  const SizeValueType lines = m_Labeling->GetNumberOfLines();
  const SizeValueType plane = m_Labeling->GetSize().size() > 1 ? m_Labeling->GetSize()[1] : 1;
  const double        perVoxel = 1.0 / static_cast<double>(table.LineLength);
  // The below runs of line \a other that overlap [from, to): sides alternate, so every
  // other run from the run that holds from if it is below, else from the run after it, up
  // to the run that holds to - 1. With the lines' boundary bits, a run's index is its
  // line's first run plus the count of the line's boundaries up to it, less one, and the
  // run starts (four bytes a run, where the bits are a bit a voxel) are not read.
  const auto joinOverlapping =
    [&](ComponentIndexType flipped, SizeValueType other, SizeValueType from, SizeValueType to)
      SMALLISO_LAMBDA_ALWAYS_INLINE {
        SizeValueType below;
        SizeValueType end;
        if constexpr (VByBits)
        {
          const uint64_t * const bits = table.Bits + other * table.BitsWords;
          const SizeValueType    lastVoxel = std::min(to, table.LineLength) - 1;
          SizeValueType          word = 0;
          SizeValueType          count = lineRunBegin[other] - 1;
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
          below = lineRunBegin[other + 1] - lineRunBegin[other] > 2 * Tuning::NearRuns
                    ? table.RunHolding(other, from, table.GuessRunHolding(other, from, perVoxel))
                    : table.RunHolding(other, from);
          end = lineRunBegin[other + 1];
        }
        below += table.IsAbove(below, other) ? 1 : 0;
        for (; below < end && (VByBits || runStart[below] < to); below += 2)
        {
          join(flipped, component[below]);
        }
      };
  // The runs ahead and their neighbouring lines are requested early: first the run itself
  // and where the lines' runs (and bits) begin, then (a few runs later, once that has
  // arrived) the lines' runs near where the run's start falls if runs were spread evenly
  // along the line, where the search for the run that holds it looks first.
  const auto prefetchLine = [&](SizeValueType line) {
    Prefetch(lineRunBegin + line);
    Prefetch(lineFirstAbove + line);
    if constexpr (VByBits)
    {
      Prefetch(table.Bits + line * table.BitsWords);
    }
  };
  const auto prefetchLines = [&](const LineRun & ahead) {
    const SizeValueType line = ahead.Line;
    Prefetch(runStart + ahead.Run);
    Prefetch(component + ahead.Run);
    prefetchLine(line);
    if (line >= plane)
    {
      prefetchLine(line - plane);
    }
    if (line + plane < lines)
    {
      prefetchLine(line + plane);
    }
  };
  const auto prefetchRuns = [&](const LineRun & ahead) {
    const SizeValueType     line = ahead.Line;
    const SizeValueType     start = runStart[ahead.Run];
    const SizeValueType     from = start >= allowance ? start - allowance : 0;
    constexpr SizeValueType near = Tuning::NearRuns;
    const auto              runsOf = [&](SizeValueType other) {
      const SizeValueType guess = table.GuessRunHolding(other, from, perVoxel);
      const SizeValueType low = guess >= near ? guess - near : 0;
      if constexpr (!VByBits)
      {
        Prefetch(runStart + low);
        Prefetch(runStart + guess);
        Prefetch(runStart + guess + near);
      }
      Prefetch(component + low);
      Prefetch(component + guess);
      Prefetch(component + guess + near);
    };
    if (line >= plane)
    {
      runsOf(line - plane);
    }
    if (line + plane < lines)
    {
      runsOf(line + plane);
    }
    if (line >= 1)
    {
      runsOf(line - 1);
    }
    if (line + 1 < lines)
    {
      runsOf(line + 1);
    }
  };
  const auto runs = static_cast<SizeValueType>(last - first);
  const bool prefetch = m_Labeling->GetNumberOfRuns() >= Tuning::PrefetchMinimumRuns;
  for (SizeValueType i = 0; i < runs; ++i)
  {
    if (prefetch && i + Tuning::PrefetchLineTablesAhead < runs)
    {
      prefetchLines(first[i + Tuning::PrefetchLineTablesAhead]);
    }
    if (prefetch && i + Tuning::PrefetchRunsAhead < runs)
    {
      prefetchRuns(first[i + Tuning::PrefetchRunsAhead]);
    }
    const SizeValueType      run = first[i].Run;
    const SizeValueType      line = first[i].Line;
    const ComponentIndexType flipped = component[run];
    const SizeValueType      lineBegin = lineRunBegin[line];
    const SizeValueType      lineEnd = lineRunBegin[line + 1];
    if (run > lineBegin)
    {
      join(flipped, component[run - 1]);
    }
    if (run + 1 < lineEnd)
    {
      join(flipped, component[run + 1]);
    }
    const SizeValueType start = runStart[run];
    const SizeValueType from = start >= allowance ? start - allowance : 0;
    const SizeValueType to = table.End(run, line) + allowance;
    neighbors.MoveTo(position, line);
    neighbors.ForEachNeighbor(
      position, [&](SizeValueType other) SMALLISO_LAMBDA_ALWAYS_INLINE { joinOverlapping(flipped, other, from, to); });
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
  const SizeValueType numberOfComponents = m_Labeling->GetNumberOfComponents();
  groups.GroupOfComponent.assign(numberOfComponents, NoGroup);
  groups.GroupSize.clear();
  // No FindRootShared() is needed: a component's parent is a member of its group with a smaller
  // index (roots are the smallest member, and a root is only ever linked under a smaller
  // one), so the parent's group is known by the time the component is reached.
  for (SizeValueType c = 0; c < numberOfComponents; ++c)
  {
    const auto member = static_cast<ComponentIndexType>(c);
    if (m_Labeling->IsComponentAbove(member) && !flipped[c])
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
    groups.GroupSize[group] += m_Labeling->GetComponentSize(member);
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
