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
#include <algorithm>
#include <numeric>

namespace itk
{
namespace
{
/** Union-find over components with path halving, for GroupAfterFlip(). */
SmallIsoComponentRunLabeling::ComponentIndexType
FindRoot(std::vector<SmallIsoComponentRunLabeling::ComponentIndexType> & parent,
         SmallIsoComponentRunLabeling::ComponentIndexType                 c)
{
  while (parent[c] != c)
  {
    parent[c] = parent[parent[c]];
    c = parent[c];
  }
  return c;
}
} // namespace

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
  const SizeValueType slabs = std::max<SizeValueType>(1, std::min<SizeValueType>(maximumNumberOfSlabs, planes));
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
    LineNeighbor  neighbor;
    SizeValueType rest = code;
    unsigned int  nonZero = 0;
    int           highestNonZero = 0;
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
  m_PeakMemoryInBytes = 0;
}

void
SmallIsoComponentRunLabeling::AssembleRuns(MultiThreaderBase * threader)
{
  // SetLineRuns() stored counts one place to the right; make them offsets.
  std::partial_sum(m_LineRunBegin.begin(), m_LineRunBegin.end(), m_LineRunBegin.begin());
  const SizeValueType numberOfRuns = m_LineRunBegin.back();
  if (numberOfRuns >= NumericTraits<RunIndexType>::max())
  {
    itkGenericExceptionMacro("SmallIsoComponentRunLabeling: the image has " << numberOfRuns
                             << " scanline runs; at most " << NumericTraits<RunIndexType>::max() - 1
                             << " are supported");
  }
  m_NumberOfRuns = numberOfRuns;
  m_RunStart.reset(new CoordinateType[numberOfRuns]);
  m_RunLabel.reset(new RunIndexType[numberOfRuns]);
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
  threader->ParallelizeArray(
    0,
    this->GetNumberOfSlabs(),
    [this](SizeValueType slab) {
      const SizeValueType first = m_LineRunBegin[m_SlabBeginLine[slab]];
      std::copy(m_SlabRunStarts[slab].begin(), m_SlabRunStarts[slab].end(), m_RunStart.get() + first);
      std::vector<CoordinateType>().swap(m_SlabRunStarts[slab]);
      const SizeValueType last = m_LineRunBegin[m_SlabBeginLine[slab + 1]];
      std::iota(m_RunLabel.get() + first, m_RunLabel.get() + last, static_cast<RunIndexType>(first));
    },
    nullptr);
}

void
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

void
SmallIsoComponentRunLabeling::LinkLines(SizeValueType lineA, SizeValueType lineB)
{
  const SizeValueType aBegin = m_LineRunBegin[lineA];
  const SizeValueType aEnd = m_LineRunBegin[lineA + 1];
  const SizeValueType bBegin = m_LineRunBegin[lineB];
  const SizeValueType bEnd = m_LineRunBegin[lineB + 1];
  bool                aboveA = m_LineFirstAbove[lineA] != 0;
  bool                aboveB = m_LineFirstAbove[lineB] != 0;
  // The runs of each line partition [0, length), so one merge visits every overlapping
  // pair once: same-side pairs that overlap touch. With full connectivity runs also touch
  // diagonally where both end at the same x: then the run after each one meets the
  // other, and those pairs are on the same side exactly when the pair itself is not.
  const CoordinateType * const start = m_RunStart.get();
  const auto                   end = [this, start](SizeValueType run, SizeValueType lineEnd) {
    return run + 1 < lineEnd ? SizeValueType{ start[run + 1] } : m_Size[0];
  };
  SizeValueType a = aBegin;
  SizeValueType b = bBegin;
  SizeValueType endA = end(a, aEnd);
  SizeValueType endB = end(b, bEnd);
  while (true)
  {
    if (aboveA == aboveB)
    {
      this->Union(static_cast<RunIndexType>(a), static_cast<RunIndexType>(b));
    }
    if (endA < endB)
    {
      ++a;
      aboveA = !aboveA;
      endA = end(a, aEnd);
    }
    else if (endB < endA)
    {
      ++b;
      aboveB = !aboveB;
      endB = end(b, bEnd);
    }
    else
    {
      if (a + 1 == aEnd || b + 1 == bEnd)
      {
        return;
      }
      if (m_FullyConnected && aboveA != aboveB)
      {
        this->Union(static_cast<RunIndexType>(a), static_cast<RunIndexType>(b + 1));
        this->Union(static_cast<RunIndexType>(a + 1), static_cast<RunIndexType>(b));
      }
      ++a;
      ++b;
      aboveA = !aboveA;
      aboveB = !aboveB;
      endA = end(a, aEnd);
      endB = end(b, bEnd);
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
  for (unsigned int a = 0; a < coordinates.size(); ++a)
  {
    const OffsetValueType c = static_cast<OffsetValueType>(coordinates[a]) + neighbor.Delta[a];
    if (c < 0 || c >= static_cast<OffsetValueType>(m_Size[a + 1]))
    {
      return false;
    }
  }
  return true;
}

void
SmallIsoComponentRunLabeling::LinkRuns(MultiThreaderBase * threader)
{
  if (m_Size.size() < 2)
  {
    return;
  }
  const unsigned int lastAxis = static_cast<unsigned int>(m_Size.size()) - 2; // index into coordinates
  // Inside each slab: only runs of the slab are touched, so no locks are needed.
  threader->ParallelizeArray(
    0,
    this->GetNumberOfSlabs(),
    [this, lastAxis](SizeValueType slab) {
      std::vector<SizeValueType> coordinates;
      const SizeValueType        begin = m_SlabBeginLine[slab];
      const SizeValueType        end = m_SlabBeginLine[slab + 1];
      this->LineCoordinates(begin, coordinates);
      const SizeValueType firstPlane = coordinates[lastAxis];
      for (SizeValueType line = begin; line < end; ++line, this->NextLineCoordinates(coordinates))
      {
        for (const auto & neighbor : m_BackwardNeighbors)
        {
          const bool crossesSeam = neighbor.Delta[lastAxis] < 0 && coordinates[lastAxis] == firstPlane;
          if (!crossesSeam && this->NeighborInside(coordinates, neighbor))
          {
            this->LinkLines(line, line + neighbor.LineOffset);
          }
        }
      }
    },
    nullptr);

  // The seams: the first plane of each slab with the last plane of the previous one.
  std::vector<SizeValueType> coordinates;
  for (unsigned int slab = 1; slab < this->GetNumberOfSlabs(); ++slab)
  {
    const SizeValueType begin = m_SlabBeginLine[slab];
    const SizeValueType linesPerPlane = m_NumberOfLines / m_Size.back();
    for (SizeValueType line = begin; line < begin + linesPerPlane; ++line)
    {
      this->LineCoordinates(line, coordinates);
      for (const auto & neighbor : m_BackwardNeighbors)
      {
        if (neighbor.Delta[lastAxis] < 0 && this->NeighborInside(coordinates, neighbor))
        {
          this->LinkLines(line, line + neighbor.LineOffset);
        }
      }
    }
  }
}

void
SmallIsoComponentRunLabeling::LabelComponents()
{
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  for (SizeValueType line = 0; line < m_NumberOfLines; ++line)
  {
    for (SizeValueType run = m_LineRunBegin[line]; run < m_LineRunBegin[line + 1]; ++run)
    {
      // Parents never point to a later run, so the parent's entry already holds its
      // component number.
      const RunIndexType parent = m_RunLabel[run];
      if (parent == run)
      {
        m_RunLabel[run] = static_cast<ComponentIndexType>(m_ComponentSize.size());
        m_ComponentSize.push_back(0);
        m_ComponentAbove.push_back(this->IsRunAbove(run, line));
      }
      else
      {
        m_RunLabel[run] = m_RunLabel[parent];
      }
      m_ComponentSize[m_RunLabel[run]] += this->GetRunEnd(run, line) - m_RunStart[run];
    }
  }
}

auto
SmallIsoComponentRunLabeling::CollectRuns(const std::vector<uint8_t> & selected, MultiThreaderBase * threader) const
  -> std::vector<LineRun>
{
  std::vector<std::vector<LineRun>> perSlab(this->GetNumberOfSlabs());
  threader->ParallelizeArray(
    0,
    this->GetNumberOfSlabs(),
    [&](SizeValueType slab) {
      for (SizeValueType line = m_SlabBeginLine[slab]; line < m_SlabBeginLine[slab + 1]; ++line)
      {
        for (SizeValueType run = m_LineRunBegin[line]; run < m_LineRunBegin[line + 1]; ++run)
        {
          if (selected[m_RunLabel[run]])
          {
            perSlab[slab].push_back({ static_cast<RunIndexType>(run), static_cast<RunIndexType>(line) });
          }
        }
      }
    },
    nullptr);
  std::vector<LineRun> runs;
  for (const auto & slabRuns : perSlab)
  {
    runs.insert(runs.end(), slabRuns.begin(), slabRuns.end());
  }
  return runs;
}

void
SmallIsoComponentRunLabeling::GroupAfterFlip(const std::vector<uint8_t> &      flipped,
                                             std::vector<ComponentIndexType> & groupOfComponent,
                                             std::vector<SizeValueType> &      groupSize,
                                             MultiThreaderBase *               threader) const
{
  const SizeValueType             numberOfComponents = m_ComponentSize.size();
  std::vector<ComponentIndexType> parent(numberOfComponents);
  std::iota(parent.begin(), parent.end(), ComponentIndexType{ 0 });
  const auto join = [&parent](ComponentIndexType a, ComponentIndexType b) {
    a = FindRoot(parent, a);
    b = FindRoot(parent, b);
    parent[std::max(a, b)] = std::min(a, b);
  };

  const SizeValueType        allowance = m_FullyConnected ? 1 : 0;
  std::vector<SizeValueType> coordinates;
  for (const LineRun & flippedRun : this->CollectRuns(flipped, threader))
  {
    const SizeValueType      run = flippedRun.Run;
    const SizeValueType      line = flippedRun.Line;
    const ComponentIndexType component = m_RunLabel[run];
    // Runs alternate sides, so the runs beside a flipped (above) run are below.
    if (run > m_LineRunBegin[line])
    {
      join(component, m_RunLabel[run - 1]);
    }
    if (run + 1 < m_LineRunBegin[line + 1])
    {
      join(component, m_RunLabel[run + 1]);
    }
    this->LineCoordinates(line, coordinates);
    const SizeValueType start = m_RunStart[run];
    const SizeValueType end = this->GetRunEnd(run, line);
    const SizeValueType from = start >= allowance ? start - allowance : 0;
    for (const auto & neighbor : m_AllNeighbors)
    {
      if (!this->NeighborInside(coordinates, neighbor))
      {
        continue;
      }
      const SizeValueType other = line + neighbor.LineOffset;
      const CoordinateType * first = m_RunStart.get() + m_LineRunBegin[other];
      const CoordinateType * last = m_RunStart.get() + m_LineRunBegin[other + 1];
      // The run that contains x = from, then every run that starts before end + allowance.
      for (auto k = static_cast<SizeValueType>(std::upper_bound(first, last, from) - m_RunStart.get()) - 1;
           k < m_LineRunBegin[other + 1] && m_RunStart[k] < end + allowance;
           ++k)
      {
        if (!this->IsRunAbove(k, other))
        {
          join(component, m_RunLabel[k]);
        }
      }
    }
  }

  groupOfComponent.assign(numberOfComponents, NoGroup);
  groupSize.clear();
  for (SizeValueType c = 0; c < numberOfComponents; ++c)
  {
    if (m_ComponentAbove[c] && !flipped[c])
    {
      continue;
    }
    const ComponentIndexType root = FindRoot(parent, static_cast<ComponentIndexType>(c));
    // Roots are the smallest member, so a root's group is numbered before its members.
    if (groupOfComponent[root] == NoGroup)
    {
      groupOfComponent[root] = static_cast<ComponentIndexType>(groupSize.size());
      groupSize.push_back(0);
    }
    groupOfComponent[c] = groupOfComponent[root];
    groupSize[groupOfComponent[c]] += m_ComponentSize[c];
  }
}

SizeValueType
SmallIsoComponentRunLabeling::GetMemoryInBytes() const
{
  SizeValueType bytes = m_NumberOfRuns * (sizeof(CoordinateType) + sizeof(RunIndexType)) +
                        m_LineRunBegin.capacity() * sizeof(SizeValueType) + m_LineFirstAbove.capacity() +
                        m_ComponentSize.capacity() * sizeof(SizeValueType) + m_ComponentAbove.capacity();
  for (const auto & starts : m_SlabRunStarts)
  {
    bytes += starts.capacity() * sizeof(CoordinateType);
  }
  return bytes;
}
} // end namespace itk
