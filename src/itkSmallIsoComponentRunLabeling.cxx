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
#include "itkNumericTraits.h"
#include <algorithm>
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
    maximumNumberOfSlabs > 1 ? SizeValueType{ maximumNumberOfSlabs } * Tuning::SlabsPerWorkUnit : SizeValueType{ 1 };
  const SizeValueType slabs = std::max<SizeValueType>(1, std::min<SizeValueType>(wanted, planes));
  m_SlabBeginLine.resize(slabs + 1);
  for (SizeValueType slab = 0; slab <= slabs; ++slab)
  {
    m_SlabBeginLine[slab] = (slab * planes / slabs) * linesPerPlane;
  }

  m_Linking.Initialize(size, fullyConnected);

  // The arrays keep their memory: an image like the last one takes none afresh.
  m_NumberOfRuns = 0;
  m_LineRunBegin.assign(m_NumberOfLines + 1, 0);
  m_LineFirstAbove.assign(m_NumberOfLines, 0);
  m_Components.Clear();
  m_PeakMemoryInBytes = 0;
}

void
RunLabeling::ReleaseMemory()
{
  const LineLinking   linking = m_Linking.GetLineLinking();
  const SizeValueType bitsCacheBytes = m_Linking.GetBitsCacheBytes();
  // The components keep their ways of sharing the numbering.
  RunComponents components = std::move(m_Components);
  components.ReleaseMemory();
  *this = RunLabeling();
  m_Components = std::move(components);
  this->SetLineLinking(linking, bitsCacheBytes);
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
  m_Linking.SetRuns(m_RunStart.data(), m_RunLabel.data(), m_LineRunBegin.data(), m_LineFirstAbove.data(), numberOfRuns);
  m_Components.SetRuns(
    m_RunStart.data(), m_RunLabel.data(), m_LineRunBegin.data(), m_LineFirstAbove.data(), m_Size[0], m_NumberOfLines);
}

void
RunLabeling::AssembleRuns(WorkTeam & team)
{
  // One ring per work unit, made before the loop so that the memory held does not depend
  // on how the slabs met the work units.
  m_Linking.MakeLineBits(team.GetNumberOfWorkUnits());
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
  team.ForEach(this->GetNumberOfSlabs(), [this](SizeValueType slab) {
    const SizeValueType begin = m_SlabBeginLine[slab];
    const SizeValueType end = m_SlabBeginLine[slab + 1];
    const SizeValueType first = m_LineRunBegin[begin];
    const SizeValueType last = m_LineRunBegin[end];
    std::iota(m_RunLabel.data() + first, m_RunLabel.data() + last, static_cast<RunIndexType>(first));
    // The slab's runs are in cache now: link them (only runs of this slab are touched).
    m_Linking.LinkInsideSlab(begin, end);
  });
}

void
RunLabeling::LinkRuns()
{
  // AssembleRuns() linked the runs inside each slab.
  m_Linking.LinkSeams(m_SlabBeginLine);
}

void
RunLabeling::LabelComponents(SizeValueType aboveCandidateSize, SizeValueType belowCandidateSize)
{
  m_Components.Number(aboveCandidateSize, belowCandidateSize);
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
}

void
RunLabeling::LabelComponents(WorkTeam &                     team,
                             SizeValueType                  aboveCandidateSize,
                             SizeValueType                  belowCandidateSize,
                             const RunComponents::Sharing & sharing)
{
  m_Components.Number(team, aboveCandidateSize, belowCandidateSize, sharing);
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
}

SizeValueType
RunLabeling::GetMemoryInBytes() const
{
  return m_RunStart.capacity() * sizeof(CoordinateType) + m_RunLabel.capacity() * sizeof(RunIndexType) +
         m_LineRunBegin.capacity() * sizeof(SizeValueType) + m_LineFirstAbove.capacity() +
         m_Components.GetMemoryInBytes() + m_Linking.GetMemoryInBytes();
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
