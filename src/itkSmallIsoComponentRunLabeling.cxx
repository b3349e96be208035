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
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkMacro.h"
#include "itkSmallIsoComponentPrefetch.h"
#include <algorithm>
#include <atomic>
#include <memory>
#include <numeric>

namespace itk
{
void
SmallIsoComponentRunLabeling::Initialize(const std::vector<SizeValueType> & size,
                                         bool                               fullyConnected,
                                         unsigned int                       maximumNumberOfSlabs)
{
  if (size.empty() || size[0] == 0 || size[0] > NumericTraits<CoordinateType>::max())
  {
    itkGenericExceptionMacro("SmallIsoComponentRunLabeling: lines along axis 0 must have between 1 and "
                             << NumericTraits<CoordinateType>::max() << " voxels");
  }
  m_Size = size;
  m_FullyConnected = fullyConnected;
  const auto dimension = static_cast<unsigned int>(size.size());
  m_NumberOfLines = 1;
  for (unsigned int axis = 1; axis < dimension; ++axis)
  {
    m_NumberOfLines *= size[axis];
  }

  // Slabs of whole planes along the last axis (whole lines in 1-D and 2-D).
  const SizeValueType planes = dimension > 1 ? size[dimension - 1] : 1;
  const SizeValueType linesPerPlane = m_NumberOfLines / std::max<SizeValueType>(planes, 1);
  const SizeValueType wanted =
    maximumNumberOfSlabs > 1 ? SizeValueType{ maximumNumberOfSlabs } * SlabsPerWorkUnit : SizeValueType{ 1 };
  const SizeValueType slabs = std::max<SizeValueType>(1, std::min<SizeValueType>(wanted, planes));
  m_SlabBeginLine.resize(slabs + 1);
  for (SizeValueType s = 0; s <= slabs; ++s)
  {
    m_SlabBeginLine[s] = (s * planes / slabs) * linesPerPlane;
  }

  // Neighbouring lines: face connectivity moves along one axis, full connectivity along
  // any combination of axes 1..N-1 (axis 0 diagonals are handled by a one-voxel overlap).
  m_BackwardNeighbors.clear();
  m_AllNeighbors.clear();
  const unsigned int otherAxes = dimension - 1;
  SizeValueType      combinations = 1;
  for (unsigned int a = 0; a < otherAxes; ++a)
  {
    combinations *= 3;
  }
  for (SizeValueType code = 0; code < combinations; ++code)
  {
    LineNeighbor    neighbor;
    SizeValueType   rest = code;
    unsigned int    nonZero = 0;
    int             highestNonZero = 0;
    OffsetValueType stride = 1;
    neighbor.LineOffset = 0;
    for (unsigned int a = 0; a < otherAxes; ++a)
    {
      const int d = static_cast<int>(rest % 3) - 1;
      rest /= 3;
      neighbor.Delta.push_back(d);
      neighbor.LineOffset += d * stride;
      stride *= static_cast<OffsetValueType>(size[a + 1]);
      if (d != 0)
      {
        ++nonZero;
        highestNonZero = d;
        neighbor.Moves.emplace_back(a, d);
      }
    }
    if (nonZero == 0 || (!fullyConnected && nonZero > 1))
    {
      continue;
    }
    m_AllNeighbors.push_back(neighbor);
    if (highestNonZero < 0)
    {
      m_BackwardNeighbors.push_back(neighbor);
    }
  }

  m_SlabRunStarts.assign(slabs, {});
  m_NumberOfRuns = 0;
  m_RunStart.reset();
  m_LineRunBegin.assign(m_NumberOfLines + 1, 0);
  m_LineFirstAbove.assign(m_NumberOfLines, 0);
  m_RunLabel.reset();
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  m_CandidateRuns.clear();
  m_PeakMemoryInBytes = 0;
}

void
SmallIsoComponentRunLabeling::AssembleRuns(SmallIsoComponentWorkTeam & team)
{
  // SetLineRuns() stored counts one place to the right; make them offsets.
  std::partial_sum(m_LineRunBegin.begin(), m_LineRunBegin.end(), m_LineRunBegin.begin());
  const SizeValueType numberOfRuns = m_LineRunBegin.back();
  if (numberOfRuns >= NumericTraits<RunIndexType>::max())
  {
    itkGenericExceptionMacro("SmallIsoComponentRunLabeling: the image has "
                             << numberOfRuns << " scanline runs; at most " << NumericTraits<RunIndexType>::max() - 1
                             << " are supported");
  }
  m_NumberOfRuns = numberOfRuns;
  m_RunStart.reset(new CoordinateType[numberOfRuns]);
  m_RunLabel.reset(new RunIndexType[numberOfRuns]);
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
  team.ForEach(this->GetNumberOfSlabs(), [this](SizeValueType slab) {
    const SizeValueType first = m_LineRunBegin[m_SlabBeginLine[slab]];
    std::copy(m_SlabRunStarts[slab].begin(), m_SlabRunStarts[slab].end(), m_RunStart.get() + first);
    std::vector<CoordinateType>().swap(m_SlabRunStarts[slab]);
    const SizeValueType last = m_LineRunBegin[m_SlabBeginLine[slab + 1]];
    std::iota(m_RunLabel.get() + first, m_RunLabel.get() + last, static_cast<RunIndexType>(first));
    // The slab's runs are in cache now: link them (only runs of this slab are touched).
    this->LinkInsideSlab(slab);
  });
}

inline void
SmallIsoComponentRunLabeling::Union(RunIndexType a, RunIndexType b)
{
  // Rem's algorithm with splicing: walk both paths towards the roots, always advancing
  // the one with the larger parent and re-pointing it to the smaller parent on the way.
  // Parents only ever decrease, so every parent stays at or below its run.
  RunIndexType * parent = m_RunLabel.get();
  while (parent[a] != parent[b])
  {
    if (parent[a] > parent[b])
    {
      if (parent[a] == a)
      {
        parent[a] = parent[b];
        return;
      }
      const RunIndexType next = parent[a];
      parent[a] = parent[b];
      a = next;
    }
    else
    {
      if (parent[b] == b)
      {
        parent[b] = parent[a];
        return;
      }
      const RunIndexType next = parent[b];
      parent[b] = parent[a];
      b = next;
    }
  }
}

inline void
SmallIsoComponentRunLabeling::LinkLines(SizeValueType lineA, SizeValueType lineB)
{
  auto       a = static_cast<RunIndexType>(m_LineRunBegin[lineA]);
  const auto aLast = static_cast<RunIndexType>(m_LineRunBegin[lineA + 1] - 1);
  auto       b = static_cast<RunIndexType>(m_LineRunBegin[lineB]);
  const auto bLast = static_cast<RunIndexType>(m_LineRunBegin[lineB + 1] - 1);
  bool       sameSide = m_LineFirstAbove[lineA] == m_LineFirstAbove[lineB];
  if (a == aLast && b == bLast)
  {
    // Two lines that are one run each (common: empty background lines).
    if (sameSide)
    {
      this->Union(a, b);
    }
    return;
  }
  // The runs of each line partition [0, length), so one merge visits every overlapping
  // pair once: same-side pairs that overlap touch. Sides alternate along a line, so the
  // pair changes side exactly when one of its runs advances. With full connectivity runs
  // also touch diagonally where both end at the same x: then the run after each one meets
  // the other, and those pairs are on the same side exactly when the pair itself is not.
  const CoordinateType * const start = m_RunStart.get();
  const auto                   length = static_cast<CoordinateType>(m_Size[0]);
  CoordinateType               endA = a < aLast ? start[a + 1] : length;
  CoordinateType               endB = b < bLast ? start[b + 1] : length;
  while (true)
  {
    if (sameSide)
    {
      this->Union(a, b);
    }
    if (endA < endB)
    {
      ++a;
      sameSide = !sameSide;
      endA = a < aLast ? start[a + 1] : length;
    }
    else if (endB < endA)
    {
      ++b;
      sameSide = !sameSide;
      endB = b < bLast ? start[b + 1] : length;
    }
    else
    {
      if (a == aLast || b == bLast)
      {
        return;
      }
      if (m_FullyConnected && !sameSide)
      {
        this->Union(a, b + 1);
        this->Union(a + 1, b);
      }
      ++a;
      ++b;
      endA = a < aLast ? start[a + 1] : length;
      endB = b < bLast ? start[b + 1] : length;
    }
  }
}

void
SmallIsoComponentRunLabeling::LineCoordinates(SizeValueType line, std::vector<SizeValueType> & coordinates) const
{
  coordinates.resize(m_Size.size() - 1);
  for (unsigned int a = 0; a + 1 < m_Size.size(); ++a)
  {
    coordinates[a] = line % m_Size[a + 1];
    line /= m_Size[a + 1];
  }
}

void
SmallIsoComponentRunLabeling::NextLineCoordinates(std::vector<SizeValueType> & coordinates) const
{
  for (unsigned int a = 0; a < coordinates.size(); ++a)
  {
    if (++coordinates[a] < m_Size[a + 1])
    {
      return;
    }
    coordinates[a] = 0;
  }
}

bool
SmallIsoComponentRunLabeling::NeighborInside(const std::vector<SizeValueType> & coordinates,
                                             const LineNeighbor &               neighbor) const
{
  for (const auto & move : neighbor.Moves)
  {
    if (move.second < 0 ? coordinates[move.first] == 0 : coordinates[move.first] + 1 >= m_Size[move.first + 1])
    {
      return false;
    }
  }
  return true;
}

void
SmallIsoComponentRunLabeling::LinkInsideSlab(SizeValueType slab)
{
  if (m_Size.size() < 2)
  {
    return;
  }
  std::vector<SizeValueType> coordinates;
  const SizeValueType        begin = m_SlabBeginLine[slab];
  const SizeValueType        end = m_SlabBeginLine[slab + 1];
  this->LineCoordinates(begin, coordinates);
  if (!m_FullyConnected)
  {
    // Face connectivity: one backward neighbour per axis 1..N-1, inside the image when the
    // line's coordinate along that axis is not 0.
    const auto axes = static_cast<unsigned int>(coordinates.size());
    if (axes == 2)
    {
      // 3-D: the line before along y, and the line one plane before along z.
      const SizeValueType rows = m_Size[1];
      const SizeValueType plane = rows;
      SizeValueType       y = coordinates[0];
      bool                zInside = coordinates[1] > 0;
      for (SizeValueType line = begin; line < end; ++line)
      {
        if (y > 0)
        {
          this->LinkLines(line, line - 1);
        }
        if (zInside && line - begin >= plane)
        {
          this->LinkLines(line, line - plane);
        }
        if (++y == rows)
        {
          y = 0;
          zInside = true;
        }
      }
      return;
    }
    std::vector<SizeValueType> stride(axes, 1);
    for (unsigned int a = 1; a < axes; ++a)
    {
      stride[a] = stride[a - 1] * m_Size[a];
    }
    for (SizeValueType line = begin; line < end; ++line)
    {
      for (unsigned int a = 0; a < axes; ++a)
      {
        if (coordinates[a] > 0 && line - begin >= stride[a])
        {
          this->LinkLines(line, line - stride[a]);
        }
      }
      for (unsigned int a = 0; a < axes && ++coordinates[a] == m_Size[a + 1]; ++a)
      {
        coordinates[a] = 0;
      }
    }
    return;
  }
  for (SizeValueType line = begin; line < end; ++line, this->NextLineCoordinates(coordinates))
  {
    for (const auto & neighbor : m_BackwardNeighbors)
    {
      // Backward neighbours have lower line numbers; the ones before the slab are seams.
      const auto back = static_cast<SizeValueType>(-neighbor.LineOffset);
      if (line - begin >= back && this->NeighborInside(coordinates, neighbor))
      {
        this->LinkLines(line, line - back);
      }
    }
  }
}

void
SmallIsoComponentRunLabeling::LinkRuns()
{
  if (m_Size.size() < 2)
  {
    return;
  }
  // AssembleRuns() linked the runs inside each slab. The seams: the first plane of each
  // slab with the planes before it.
  std::vector<SizeValueType> coordinates;
  const SizeValueType        linesPerPlane = m_NumberOfLines / m_Size.back();
  for (SizeValueType slab = 1; slab < this->GetNumberOfSlabs(); ++slab)
  {
    const SizeValueType begin = m_SlabBeginLine[slab];
    this->LineCoordinates(begin, coordinates);
    for (SizeValueType line = begin; line < begin + linesPerPlane; ++line, this->NextLineCoordinates(coordinates))
    {
      for (const auto & neighbor : m_BackwardNeighbors)
      {
        const auto back = static_cast<SizeValueType>(-neighbor.LineOffset);
        if (line - begin < back && this->NeighborInside(coordinates, neighbor))
        {
          this->LinkLines(line, line - back);
        }
      }
    }
  }
}

void
SmallIsoComponentRunLabeling::LabelComponents()
{
  // Every run has at least one voxel: no run is a candidate.
  this->LabelComponents(0);
}

void
SmallIsoComponentRunLabeling::LabelComponents(SizeValueType candidateSize)
{
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  m_CandidateRuns.clear();
  constexpr SizeValueType      BufferSize = 256;
  LineRun                      buffer[BufferSize];
  SizeValueType                buffered = 0;
  RunIndexType * const         label = m_RunLabel.get();
  const CoordinateType * const start = m_RunStart.get();
  const SizeValueType          length = m_Size[0];
  for (SizeValueType line = 0; line < m_NumberOfLines; ++line)
  {
    const SizeValueType end = m_LineRunBegin[line + 1];
    bool                above = m_LineFirstAbove[line] != 0;
    for (SizeValueType run = m_LineRunBegin[line]; run < end; ++run, above = !above)
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
      }
      else
      {
        component = label[parent];
      }
      label[run] = component;
      const SizeValueType size =
        m_ComponentSize[component] + (run + 1 < end ? SizeValueType{ start[run + 1] } : length) - start[run];
      m_ComponentSize[component] = size;
      // A component's size only grows, so every run of a component that ends at most
      // candidateSize voxels large is kept. Written without a branch (which would be
      // mispredicted for every speck) into a small buffer, emptied when full.
      buffer[buffered] = { static_cast<RunIndexType>(run), static_cast<RunIndexType>(line) };
      buffered += size <= candidateSize ? 1 : 0;
      if (buffered == BufferSize)
      {
        m_CandidateRuns.insert(m_CandidateRuns.end(), buffer, buffer + buffered);
        buffered = 0;
      }
    }
  }
  m_CandidateRuns.insert(m_CandidateRuns.end(), buffer, buffer + buffered);
}

auto
SmallIsoComponentRunLabeling::CollectCandidateRuns(const std::vector<uint8_t> & selected) const -> std::vector<LineRun>
{
  std::vector<LineRun> runs;
  for (const LineRun & candidate : m_CandidateRuns)
  {
    if (selected[m_RunLabel[candidate.Run]])
    {
      runs.push_back(candidate);
    }
  }
  return runs;
}

// A union-find over components that work units share without locks: a root is linked
// under another root by compare-and-swap, always the larger index under the smaller, so
// every root is the smallest component of its group whatever the order of the links;
// path halving only ever replaces a parent by one of its ancestors.
SmallIsoComponentRunLabeling::FlipGrouping::FlipGrouping(const SmallIsoComponentRunLabeling & labeling)
  : m_Labeling(labeling)
  , m_Parent(new std::atomic<ComponentIndexType>[labeling.GetNumberOfComponents()])
{
  for (SizeValueType c = 0; c < labeling.GetNumberOfComponents(); ++c)
  {
    m_Parent[c].store(static_cast<ComponentIndexType>(c), std::memory_order_relaxed);
  }
}

SmallIsoComponentRunLabeling::FlipGrouping::~FlipGrouping() = default;

SizeValueType
SmallIsoComponentRunLabeling::FlipGrouping::GetScratchBytes() const
{
  return m_Labeling.GetNumberOfComponents() * sizeof(std::atomic<ComponentIndexType>);
}

inline auto
SmallIsoComponentRunLabeling::FlipGrouping::Find(ComponentIndexType c) -> ComponentIndexType
{
  while (true)
  {
    const ComponentIndexType p = m_Parent[c].load(std::memory_order_relaxed);
    if (p == c)
    {
      return c;
    }
    const ComponentIndexType grandparent = m_Parent[p].load(std::memory_order_relaxed);
    if (grandparent != p)
    {
      m_Parent[c].store(grandparent, std::memory_order_relaxed);
    }
    c = grandparent;
  }
}

inline void
SmallIsoComponentRunLabeling::FlipGrouping::Join(ComponentIndexType a, ComponentIndexType b)
{
  while (true)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a == b)
    {
      return;
    }
    if (a < b)
    {
      std::swap(a, b);
    }
    ComponentIndexType expected = a;
    if (m_Parent[a].compare_exchange_weak(expected, b, std::memory_order_relaxed))
    {
      return;
    }
  }
}

void
SmallIsoComponentRunLabeling::FlipGrouping::JoinNeighbors(const LineRun * first, const LineRun * last)
{
  // Each flipped run touches the runs beside it in its line (runs alternate sides, so
  // those are below) and the below runs it overlaps in the neighbouring lines; its
  // component joins theirs. A repeat of the previous pair is skipped.
  const SmallIsoComponentRunLabeling & l = m_Labeling;
  const SizeValueType                  allowance = l.m_FullyConnected ? 1 : 0;
  const RunIndexType * const           label = l.m_RunLabel.get();
  const CoordinateType * const         runStart = l.m_RunStart.get();
  const SizeValueType * const          lineRunBegin = l.m_LineRunBegin.data();
  const uint8_t * const                lineFirstAbove = l.m_LineFirstAbove.data();
  std::vector<SizeValueType>           coordinates;
  SizeValueType                        coordinatesLine = NumericTraits<SizeValueType>::max();
  ComponentIndexType                   lastA = NoGroup;
  ComponentIndexType                   lastB = NoGroup;
  const auto                           add = [&](ComponentIndexType a, ComponentIndexType b) {
    if (a != lastA || b != lastB)
    {
      lastA = a;
      lastB = b;
      this->Join(a, b);
    }
  };
  // The below runs of line \a other that overlap [from, to). The run that holds from
  // (the last one starting at or before it; the line's first run starts at 0) is found
  // by a binary search without branches, which the run starts would make unpredictable.
  const auto joinOverlapping =
    [&](ComponentIndexType component, SizeValueType other, SizeValueType from, SizeValueType to) {
      const SizeValueType    otherBegin = lineRunBegin[other];
      const SizeValueType    otherEnd = lineRunBegin[other + 1];
      const CoordinateType * holder = runStart + otherBegin;
      for (SizeValueType n = otherEnd - otherBegin; n > 1;)
      {
        const SizeValueType half = n / 2;
        holder = holder[half] <= from ? holder + half : holder;
        n -= half;
      }
      // The holder overlaps [from, to). Sides alternate, so the below runs that overlap are
      // every other run from the holder if it is below, else from the run after it.
      SizeValueType k = static_cast<SizeValueType>(holder - runStart);
      k += (lineFirstAbove[other] != 0) != (((k - otherBegin) & 1) != 0) ? 1 : 0;
      for (; k < otherEnd && runStart[k] < to; k += 2)
      {
        add(component, label[k]);
      }
    };
  const bool          faceConnected3D = !l.m_FullyConnected && l.m_Size.size() == 3;
  const SizeValueType plane = l.m_Size.size() > 1 ? l.m_Size[1] : 1;
  // The neighbouring lines of the runs ahead are requested early: first where their runs
  // begin, then (a few runs later, once that has arrived) their runs.
  const auto prefetchLines = [&](const LineRun & ahead) {
    const SizeValueType line = ahead.Line;
    SmallIsoComponentDetail::Prefetch(lineRunBegin + line);
    SmallIsoComponentDetail::Prefetch(lineFirstAbove + line);
    if (line >= plane)
    {
      SmallIsoComponentDetail::Prefetch(lineRunBegin + line - plane);
      SmallIsoComponentDetail::Prefetch(lineFirstAbove + line - plane);
    }
    if (line + plane < l.m_NumberOfLines)
    {
      SmallIsoComponentDetail::Prefetch(lineRunBegin + line + plane);
      SmallIsoComponentDetail::Prefetch(lineFirstAbove + line + plane);
    }
  };
  const auto prefetchRuns = [&](const LineRun & ahead) {
    const SizeValueType line = ahead.Line;
    const auto          runsOf = [&](SizeValueType other) {
      const SizeValueType begin = lineRunBegin[other];
      SmallIsoComponentDetail::Prefetch(runStart + begin);
      SmallIsoComponentDetail::Prefetch(label + begin);
    };
    runsOf(line);
    if (line >= plane)
    {
      runsOf(line - plane);
    }
    if (line + plane < l.m_NumberOfLines)
    {
      runsOf(line + plane);
    }
  };
  const auto runs = static_cast<SizeValueType>(last - first);
  for (SizeValueType i = 0; i < runs; ++i)
  {
    if (i + SmallIsoComponentDetail::PrefetchLineTablesAhead < runs)
    {
      prefetchLines(first[i + SmallIsoComponentDetail::PrefetchLineTablesAhead]);
    }
    if (i + SmallIsoComponentDetail::PrefetchRunsAhead < runs)
    {
      prefetchRuns(first[i + SmallIsoComponentDetail::PrefetchRunsAhead]);
    }
    const SizeValueType      run = first[i].Run;
    const SizeValueType      line = first[i].Line;
    const ComponentIndexType component = label[run];
    const SizeValueType      lineBegin = lineRunBegin[line];
    const SizeValueType      lineEnd = lineRunBegin[line + 1];
    if (run > lineBegin)
    {
      add(component, label[run - 1]);
    }
    if (run + 1 < lineEnd)
    {
      add(component, label[run + 1]);
    }
    const SizeValueType start = runStart[run];
    const SizeValueType end = run + 1 < lineEnd ? SizeValueType{ runStart[run + 1] } : l.m_Size[0];
    if (faceConnected3D)
    {
      // The common case, without the general neighbour tables: the lines before and
      // after along y and along z.
      const SizeValueType rows = l.m_Size[1];
      const SizeValueType y = line % rows;
      const SizeValueType z = line / rows;
      if (y > 0)
      {
        joinOverlapping(component, line - 1, start, end);
      }
      if (y + 1 < rows)
      {
        joinOverlapping(component, line + 1, start, end);
      }
      if (z > 0)
      {
        joinOverlapping(component, line - rows, start, end);
      }
      if (z + 1 < l.m_Size[2])
      {
        joinOverlapping(component, line + rows, start, end);
      }
      continue;
    }
    if (line != coordinatesLine)
    {
      l.LineCoordinates(line, coordinates);
      coordinatesLine = line;
    }
    // With full connectivity a run also touches the runs that end just before it or
    // start just after it in the neighbouring lines.
    const SizeValueType from = start >= allowance ? start - allowance : 0;
    for (const LineNeighbor & neighbor : l.m_AllNeighbors)
    {
      if (l.NeighborInside(coordinates, neighbor))
      {
        joinOverlapping(component, line + neighbor.LineOffset, from, end + allowance);
      }
    }
  }
}

auto
SmallIsoComponentRunLabeling::FlipGrouping::Finish(const std::vector<uint8_t> & flipped) -> Groups
{
  const SmallIsoComponentRunLabeling & l = m_Labeling;
  const SizeValueType                  numberOfComponents = l.GetNumberOfComponents();
  Groups                               groups;
  groups.GroupOfComponent.assign(numberOfComponents, NoGroup);
  for (SizeValueType c = 0; c < numberOfComponents; ++c)
  {
    if (l.m_ComponentAbove[c] && !flipped[c])
    {
      continue;
    }
    const ComponentIndexType root = this->Find(static_cast<ComponentIndexType>(c));
    // Roots are the smallest member, so a root's group is numbered before its members.
    if (groups.GroupOfComponent[root] == NoGroup)
    {
      groups.GroupOfComponent[root] = static_cast<ComponentIndexType>(groups.GroupSize.size());
      groups.GroupSize.push_back(0);
    }
    groups.GroupOfComponent[c] = groups.GroupOfComponent[root];
    groups.GroupSize[groups.GroupOfComponent[c]] += l.m_ComponentSize[c];
  }
  return groups;
}

SizeValueType
SmallIsoComponentRunLabeling::GetMemoryInBytes() const
{
  SizeValueType bytes = m_NumberOfRuns * (sizeof(CoordinateType) + sizeof(RunIndexType)) +
                        m_LineRunBegin.capacity() * sizeof(SizeValueType) + m_LineFirstAbove.capacity() +
                        m_ComponentSize.capacity() * sizeof(SizeValueType) + m_ComponentAbove.capacity() +
                        m_CandidateRuns.capacity() * sizeof(LineRun);
  for (const auto & starts : m_SlabRunStarts)
  {
    bytes += starts.capacity() * sizeof(CoordinateType);
  }
  return bytes;
}
} // end namespace itk
