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
#include <atomic>
#include <memory>
#include <numeric>

namespace itk
{
namespace SmallIsoComponentDetail
{
void
RunLabeling::Initialize(const std::vector<SizeValueType> & size, bool fullyConnected, unsigned int maximumNumberOfSlabs)
{
  if (size.empty() || size[0] == 0 || size[0] > NumericTraits<CoordinateType>::max())
  {
    itkGenericExceptionMacro("SmallIsoComponent: lines along axis 0 must have between 1 and "
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
  for (SizeValueType slab = 0; slab <= slabs; ++slab)
  {
    m_SlabBeginLine[slab] = (slab * planes / slabs) * linesPerPlane;
  }

  m_LineNeighbors = LineNeighbors(size, fullyConnected);

  // The arrays keep their memory: an image like the last one takes none afresh.
  m_NumberOfRuns = 0;
  m_LineRunBegin.assign(m_NumberOfLines + 1, 0);
  m_LineFirstAbove.assign(m_NumberOfLines, 0);
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  m_CandidateRuns.clear();
  m_PeakMemoryInBytes = 0;
}

void
RunLabeling::ReleaseMemory()
{
  *this = RunLabeling();
}

void
RunLabeling::ReserveRuns()
{
  // SetLineRuns() stored counts one place to the right; make them offsets.
  std::partial_sum(m_LineRunBegin.begin(), m_LineRunBegin.end(), m_LineRunBegin.begin());
  const SizeValueType numberOfRuns = m_LineRunBegin.back();
  if (numberOfRuns >= NumericTraits<RunIndexType>::max())
  {
    itkGenericExceptionMacro("SmallIsoComponent: the image has "
                             << numberOfRuns << " scanline runs; the filter holds at most "
                             << NumericTraits<RunIndexType>::max() - 1
                             << " at once: filter it in slabs with SmallIsoComponentStreamingImageFilter "
                                "(SmallIsoComponentFilter --memory-limit), which labels fewer at a time");
  }
  m_NumberOfRuns = numberOfRuns;
  m_RunStart.Reserve(numberOfRuns);
  m_RunLabel.Reserve(numberOfRuns);
}

void
RunLabeling::AssembleRuns(WorkTeam & team)
{
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
  team.ForEach(this->GetNumberOfSlabs(), [this](SizeValueType slab) {
    const SizeValueType first = m_LineRunBegin[m_SlabBeginLine[slab]];
    const SizeValueType last = m_LineRunBegin[m_SlabBeginLine[slab + 1]];
    std::iota(m_RunLabel.data() + first, m_RunLabel.data() + last, static_cast<RunIndexType>(first));
    // The slab's runs are in cache now: link them (only runs of this slab are touched).
    this->LinkInsideSlab(slab);
  });
}

inline void
RunLabeling::Union(RunIndexType a, RunIndexType b)
{
  // Rem's algorithm with splicing: walk both paths towards the roots, always advancing
  // the one with the larger parent and re-pointing it to the smaller parent on the way.
  // Parents only ever decrease, so every parent stays at or below its run.
  RunIndexType * parent = m_RunLabel.data();
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
RunLabeling::LinkLines(SizeValueType lineA, SizeValueType lineB)
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
  const CoordinateType * const start = m_RunStart.data();
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
RunLabeling::LinkInsideSlab(SizeValueType slab)
{
  const SizeValueType begin = m_SlabBeginLine[slab];
  const SizeValueType end = m_SlabBeginLine[slab + 1];
  auto                position = m_LineNeighbors.At(begin);
  for (SizeValueType line = begin; line < end; ++line, m_LineNeighbors.Next(position))
  {
    // The earlier lines before the slab are its seam, linked by LinkRuns().
    m_LineNeighbors.ForEachEarlier(position, [&](SizeValueType earlier) {
      if (earlier >= begin)
      {
        this->LinkLines(line, earlier);
      }
    });
  }
}

void
RunLabeling::LinkRuns()
{
  // AssembleRuns() linked the runs inside each slab. The seams: the first plane of each
  // slab with the planes before it.
  const SizeValueType linesPerPlane = m_NumberOfLines / m_Size.back();
  for (SizeValueType slab = 1; slab < this->GetNumberOfSlabs(); ++slab)
  {
    const SizeValueType begin = m_SlabBeginLine[slab];
    auto                position = m_LineNeighbors.At(begin);
    for (SizeValueType line = begin; line < begin + linesPerPlane; ++line, m_LineNeighbors.Next(position))
    {
      m_LineNeighbors.ForEachEarlier(position, [&](SizeValueType earlier) {
        if (earlier < begin)
        {
          this->LinkLines(line, earlier);
        }
      });
    }
  }
}

void
RunLabeling::LabelComponents()
{
  // Every run has at least one voxel: no run is a candidate.
  this->LabelComponents(0);
}

void
RunLabeling::LabelComponents(SizeValueType candidateSize)
{
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  m_CandidateRuns.clear();
  constexpr SizeValueType      BufferSize = 256;
  LineRun                      buffer[BufferSize];
  SizeValueType                buffered = 0;
  RunIndexType * const         label = m_RunLabel.data();
  const CoordinateType * const start = m_RunStart.data();
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
RunLabeling::CollectCandidateRuns(const std::vector<uint8_t> & selected) const -> std::vector<LineRun>
{
  std::vector<LineRun> runs;
  for (const LineRun & candidate : m_CandidateRuns)
  {
    if (selected[m_RunLabel.data()[candidate.Run]])
    {
      runs.push_back(candidate);
    }
  }
  return runs;
}

SizeValueType
RunLabeling::GetMemoryInBytes() const
{
  return m_RunStart.capacity() * sizeof(CoordinateType) + m_RunLabel.capacity() * sizeof(RunIndexType) +
         m_LineRunBegin.capacity() * sizeof(SizeValueType) + m_LineFirstAbove.capacity() +
         m_ComponentSize.capacity() * sizeof(SizeValueType) + m_ComponentAbove.capacity() +
         m_CandidateRuns.capacity() * sizeof(LineRun);
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
