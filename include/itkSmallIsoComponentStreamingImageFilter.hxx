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
#ifndef itkSmallIsoComponentStreamingImageFilter_hxx
#define itkSmallIsoComponentStreamingImageFilter_hxx

#include "itkSmallIsoComponentStreamingImageFilter.h"
#include <algorithm>

namespace itk
{
template <typename TInputImage, typename TOutputImage>
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::~SmallIsoComponentStreamingImageFilter() = default;

template <typename TInputImage, typename TOutputImage>
bool
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::CanRunInPlace() const
{
  return false;
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::BytesOf(const ReadyPlane & ready)
{
  return ready.Values.size() * sizeof(OutputPixelType) + ready.Mask.size() * sizeof(MaskPixelType);
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::EnlargeOutputRequestedRegion(DataObject * output)
{
  auto * image = dynamic_cast<ImageBase<ImageDimension> *>(output);
  if (image == nullptr)
  {
    return;
  }
  // Whole planes of the requested range, for every output.
  auto       region = image->GetRequestedRegion();
  const auto largest = image->GetLargestPossibleRegion();
  for (unsigned int a = 0; a + 1 < ImageDimension; ++a)
  {
    region.SetIndex(a, largest.GetIndex(a));
    region.SetSize(a, largest.GetSize(a));
  }
  for (unsigned int i = 0; i < this->GetNumberOfIndexedOutputs(); ++i)
  {
    if (auto * other = dynamic_cast<ImageBase<ImageDimension> *>(this->ProcessObject::GetOutput(i)))
    {
      other->SetRequestedRegion(region);
    }
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::RequestedPlanes(uint64_t & first,
                                                                                  uint64_t & end) const
{
  const auto &           requested = this->GetOutput()->GetRequestedRegion();
  const auto &           largest = this->GetOutput()->GetLargestPossibleRegion();
  constexpr unsigned int last = ImageDimension - 1;
  first = static_cast<uint64_t>(requested.GetIndex(last) - largest.GetIndex(last));
  end = first + requested.GetSize(last);
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::StartSweep()
{
  const InputImageType * input = this->GetInput();
  const auto &           size = input->GetLargestPossibleRegion().GetSize();
  this->m_EffectiveMaximumComponentSize = this->ComputeEffectiveMaximumComponentSize(input->GetSpacing());
  const typename SweepType::IndexType box =
    ImageDimension == 3 ? typename SweepType::IndexType{ size[0], size[1], size[ImageDimension - 1] }
                        : typename SweepType::IndexType{ size[0], 1, size[ImageDimension - 1] };
  m_Ready.clear();
  m_ReadyBytes = 0;
  m_PlanesTaken = 0;
  m_PlanesGiven = 0;
  m_Complete = false;
  m_PeakMemoryInBytes = 0;
  m_Sweep = std::make_unique<SweepType>(box,
                                        this->GetIsoValue(),
                                        this->GetEffectiveMaximumComponentSize(),
                                        this->GetSide(),
                                        this->GetFullyConnected(),
                                        m_SlabThickness,
                                        this->GetGenerateRemovedMask(),
                                        this->GetMultiThreader(),
                                        this->GetNumberOfWorkUnits(),
                                        [this](uint64_t plane, const OutputPixelType * values, const uint8_t * mask) {
                                          this->KeepReadyPlane(plane, values, mask);
                                        });
  m_SweepTime = std::max(this->GetMTime(), input->GetPipelineMTime());
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::KeepReadyPlane(uint64_t                plane,
                                                                                 const OutputPixelType * values,
                                                                                 const uint8_t *         mask)
{
  const auto & largest = this->GetOutput()->GetLargestPossibleRegion();
  const auto planeVoxels = static_cast<std::size_t>(largest.GetNumberOfPixels() / largest.GetSize(ImageDimension - 1));
  ReadyPlane ready;
  ready.Plane = plane;
  ready.Values.assign(values, values + planeVoxels);
  if (mask != nullptr)
  {
    ready.Mask.resize(planeVoxels);
    SmallIsoComponentDetail::CopyRemovedMask(mask, planeVoxels, ready.Mask.data());
  }
  m_ReadyBytes += BytesOf(ready);
  m_Ready.push_back(std::move(ready));
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  auto * input = const_cast<InputImageType *>(this->GetInput());
  if (input == nullptr)
  {
    return;
  }
  uint64_t first;
  uint64_t end;
  this->RequestedPlanes(first, end);
  // The sweep starts again when its data changed or an earlier piece is asked for.
  const uint64_t available = !m_Sweep ? 0 : (m_Ready.empty() ? m_Sweep->GetNumberOfPlanesOut() : m_Ready.front().Plane);
  if (!m_Sweep || std::max(this->GetMTime(), input->GetPipelineMTime()) > m_SweepTime || first < available)
  {
    this->StartSweep();
  }
  const auto &           largest = input->GetLargestPossibleRegion();
  constexpr unsigned int last = ImageDimension - 1;
  const uint64_t         depth = largest.GetSize(last);
  // Planes beyond the piece decide it: at most the window's reach.
  const uint64_t reach =
    SweepType::WindowPlanes(this->GetEffectiveMaximumComponentSize(), m_SlabThickness, this->GetNumberOfWorkUnits());
  const uint64_t ready = m_Ready.empty() ? m_Sweep->GetNumberOfPlanesOut() : m_Ready.back().Plane + 1;
  m_InputEnd = ready >= end ? m_PlanesTaken : std::min(depth, std::max(m_PlanesTaken, end + reach));
  auto region = largest;
  // A piece that needs no new input still asks for one plane (a region cannot be empty).
  const uint64_t from = std::min(m_PlanesTaken, depth - 1);
  region.SetIndex(last, largest.GetIndex(last) + static_cast<IndexValueType>(from));
  region.SetSize(last, std::max<uint64_t>(1, m_InputEnd - std::min(m_InputEnd, from)));
  input->SetRequestedRegion(region);
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::GenerateData()
{
  this->AllocateOutputs();
  const InputImageType * input = this->GetInput();
  constexpr unsigned int last = ImageDimension - 1;
  const auto &           largest = input->GetLargestPossibleRegion();
  const uint64_t         depth = largest.GetSize(last);
  const uint64_t         planeVoxels = largest.GetNumberOfPixels() / depth;
  const auto &           buffered = input->GetBufferedRegion();
  const uint64_t         bufferedFirst = static_cast<uint64_t>(buffered.GetIndex(last) - largest.GetIndex(last));

  // Take the new planes, converted to the output type.
  if (m_InputEnd > m_PlanesTaken)
  {
    if (bufferedFirst > m_PlanesTaken || bufferedFirst + buffered.GetSize(last) < m_InputEnd ||
        buffered.GetNumberOfPixels() != buffered.GetSize(last) * planeVoxels)
    {
      itkExceptionMacro("The input holds planes " << bufferedFirst << " to " << bufferedFirst + buffered.GetSize(last)
                                                  << " of whole planes only partly; planes " << m_PlanesTaken << " to "
                                                  << m_InputEnd << " were asked for.");
    }
    const InputPixelType *       in = input->GetBufferPointer() + (m_PlanesTaken - bufferedFirst) * planeVoxels;
    std::vector<OutputPixelType> planes((m_InputEnd - m_PlanesTaken) * planeVoxels);
    std::transform(
      in, in + planes.size(), planes.begin(), [](InputPixelType v) { return static_cast<OutputPixelType>(v); });
    m_Sweep->Push(planes.data(), m_InputEnd - m_PlanesTaken);
    m_PlanesTaken = m_InputEnd;
    if (m_PlanesTaken == depth)
    {
      m_Sweep->Finish();
    }
  }
  m_PeakMemoryInBytes = std::max<SizeValueType>(m_PeakMemoryInBytes, m_Sweep->GetPeakMemoryInBytes() + m_ReadyBytes);

  // Give out the piece.
  uint64_t first;
  uint64_t end;
  this->RequestedPlanes(first, end);
  OutputPixelType * output = this->GetOutput()->GetBufferPointer();
  MaskPixelType *   mask = this->GetGenerateRemovedMask() ? this->GetRemovedMask()->GetBufferPointer() : nullptr;
  for (uint64_t plane = first; plane < end; ++plane)
  {
    while (!m_Ready.empty() && m_Ready.front().Plane < plane)
    {
      m_ReadyBytes -= BytesOf(m_Ready.front());
      m_Ready.pop_front();
    }
    if (m_Ready.empty() || m_Ready.front().Plane != plane)
    {
      itkExceptionMacro("Plane " << plane << " is not ready after planes 0 to " << m_PlanesTaken << " of the input.");
    }
    const auto & ready = m_Ready.front();
    std::copy(ready.Values.begin(), ready.Values.end(), output + (plane - first) * planeVoxels);
    if (mask != nullptr)
    {
      std::copy(ready.Mask.begin(), ready.Mask.end(), mask + (plane - first) * planeVoxels);
    }
    m_ReadyBytes -= BytesOf(ready);
    m_Ready.pop_front();
    m_PlanesGiven = plane + 1;
  }
  m_Complete = m_PlanesGiven == depth && m_PlanesTaken == depth;
  this->UpdateProgress(static_cast<float>(m_PlanesGiven) / static_cast<float>(depth));
}

template <typename TInputImage, typename TOutputImage>
const SmallIsoComponentDetail::SideTally &
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::TallyOf(SideEnum side) const
{
  this->VerifyStatisticsSide(side);
  if (!m_Sweep)
  {
    itkExceptionMacro("No statistics yet: the filter has not run.");
  }
  return side == SideEnum::Above ? m_Sweep->GetTally().Above : m_Sweep->GetTally().Below;
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::GetSideCounts(SideEnum side) const ->
  typename Superclass::SideCounts
{
  const SmallIsoComponentDetail::SideTally & tally = this->TallyOf(side);
  typename Superclass::SideCounts            counts;
  counts.Components = tally.GetComponents();
  counts.RemovedComponents = tally.GetRemovedComponents();
  counts.RemovedVoxels = tally.GetRemovedVoxels();
  return counts;
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::GetComponentSizeHistogram(SideEnum side) const
  -> ComponentSizeHistogramType
{
  const auto histogram = this->TallyOf(side).GetHistogram();
  return ComponentSizeHistogramType(histogram.begin(), histogram.end());
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::GetNumberOfModifiedVoxels() const
{
  return m_Sweep ? m_Sweep->GetTally().ModifiedVoxels : 0;
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::GetNumberOfUnrepairableVoxels() const
{
  return m_Sweep ? m_Sweep->GetTally().UnrepairableVoxels + m_Sweep->GetNumberOfFallbackVoxels() : 0;
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentStreamingImageFilter<TInputImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "SlabThickness: " << m_SlabThickness << std::endl;
  os << indent << "EffectiveMaximumComponentSize: " << this->GetEffectiveMaximumComponentSize() << std::endl;
  os << indent << "PeakMemoryInBytes: " << m_PeakMemoryInBytes << std::endl;
  os << indent << "Complete: " << (m_Complete ? "On" : "Off") << std::endl;
}
} // end namespace itk

#endif
