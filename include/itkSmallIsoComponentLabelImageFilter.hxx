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
#ifndef itkSmallIsoComponentLabelImageFilter_hxx
#define itkSmallIsoComponentLabelImageFilter_hxx

#include "itkSmallIsoComponentLabelImageFilter.h"
#include "itkMath.h"
#include "itkSmallIsoComponentBlockSummary.h"
#include <algorithm>
#include <cmath>
#include <functional>
#include <type_traits>

namespace itk
{
template <typename TImage>
SmallIsoComponentLabelImageFilter<TImage>::SmallIsoComponentLabelImageFilter()
{
  this->SetNumberOfRequiredOutputs(2);
  this->SetNthOutput(1, this->MakeOutput(1));
  this->InPlaceOff();
}

template <typename TImage>
DataObject::Pointer
SmallIsoComponentLabelImageFilter<TImage>::MakeOutput(DataObjectPointerArraySizeType idx)
{
  if (idx == 1)
  {
    return MaskImageType::New().GetPointer();
  }
  return Superclass::MakeOutput(idx);
}

template <typename TImage>
auto
SmallIsoComponentLabelImageFilter<TImage>::GetRemovedMask() -> MaskImageType *
{
  return itkDynamicCastInDebugMode<MaskImageType *>(this->ProcessObject::GetOutput(1));
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::SetMaximumComponentSize(SizeValueType size)
{
  if (m_MaximumComponentSize != size || m_UseMaximumComponentVolume)
  {
    m_MaximumComponentSize = size;
    m_UseMaximumComponentVolume = false;
    this->Modified();
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::SetMaximumComponentVolume(double volume)
{
  if (Math::NotExactlyEquals(m_MaximumComponentVolume, volume) || !m_UseMaximumComponentVolume)
  {
    m_MaximumComponentVolume = volume;
    m_UseMaximumComponentVolume = true;
    this->Modified();
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::SetMaximumComponentSizes(const LabelSizeMapType & sizes)
{
  if (m_MaximumComponentSizes != sizes)
  {
    m_MaximumComponentSizes = sizes;
    this->Modified();
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::SetSelectedLabels(const std::vector<LabelType> & labels)
{
  if (m_SelectedLabels != labels)
  {
    m_SelectedLabels = labels;
    this->Modified();
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::VerifyPreconditions()
#if !defined(ITKV4_COMPATIBILITY)
  const
#endif
{
  Superclass::VerifyPreconditions();
  if (m_UseMaximumComponentVolume && !(m_MaximumComponentVolume >= 0.0))
  {
    itkExceptionMacro("MaximumComponentVolume is "
                      << m_MaximumComponentVolume << "; it must be a volume >= 0 in the image's physical units cubed.");
  }
  if (static_cast<unsigned int>(m_Selection) > static_cast<unsigned int>(SelectionEnum::Listed))
  {
    itkExceptionMacro("Selection is " << static_cast<int>(m_Selection)
                                      << "; it must be All, Islands, Holes or Listed.");
  }
  if (m_Selection == SelectionEnum::Listed && m_SelectedLabels.empty())
  {
    itkExceptionMacro("Selection is Listed but no label is listed; give the labels with SetSelectedLabels().");
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  auto * input = const_cast<ImageType *>(this->GetInput());
  if (input == nullptr)
  {
    return;
  }
  // A removed component that reaches the output has at most K voxels, so it lies within K - 1 of
  // the output, its voters within K, and a voter's component, when removed, within 2K - 1: a halo
  // of 2K holds them whole, and a component that the halo's border cuts has more than K voxels
  // inside it wherever it decides an output voxel. Keep-largest needs every component whole.
  SizeValueType k = this->ComputeEffectiveMaximumComponentSize(input->GetSpacing());
  for (const auto & labelK : m_MaximumComponentSizes)
  {
    k = std::max(k, labelK.second);
  }
  const RegionType whole = input->GetLargestPossibleRegion();
  RegionType       region = this->GetOutput()->GetRequestedRegion();
  const auto halo = static_cast<OffsetValueType>(std::min<SizeValueType>(k, NumericTraits<OffsetValueType>::max() / 4));
  if (m_KeepLargestComponents > 0 || !region.Crop(whole))
  {
    region = whole;
  }
  region.PadByRadius(2 * halo);
  region.Crop(whole);
  input->SetRequestedRegion(region);
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::EnlargeOutputRequestedRegion(DataObject * output)
{
  Superclass::EnlargeOutputRequestedRegion(output);
  if (m_KeepLargestComponents > 0)
  {
    for (unsigned int i = 0; i < this->GetNumberOfIndexedOutputs(); ++i)
    {
      if (DataObject * each = this->ProcessObject::GetOutput(i))
      {
        each->SetRequestedRegionToLargestPossibleRegion();
      }
    }
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::AllocateOutputs()
{
  MaskImageType * mask = this->GetRemovedMask();
  if (!m_GenerateRemovedMask)
  {
    // The mask keeps its geometry and is allocated with no voxels.
    typename MaskImageType::RegionType none = mask->GetRequestedRegion();
    typename MaskImageType::SizeType   noSize;
    noSize.Fill(0);
    none.SetSize(noSize);
    mask->Initialize();
    mask->SetRequestedRegion(none);
  }
  Superclass::AllocateOutputs();
  if (m_GenerateRemovedMask)
  {
    mask->FillBuffer(0);
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::VerifyWholeNumbers(const LabelType * labels, const RegionType & region) const
{
  if (!std::is_floating_point<LabelType>::value)
  {
    return;
  }
  const SizeValueType     count = region.GetNumberOfPixels();
  const LabelType * const bad = std::find_if(labels, labels + count, [](LabelType value) {
    return !std::isfinite(static_cast<double>(value)) || std::trunc(value) != value;
  });
  if (bad != labels + count)
  {
    itkExceptionMacro("The label image's sample at "
                      << SmallIsoComponentDetail::IndexOf(region, static_cast<SizeValueType>(bad - labels)) << " is "
                      << static_cast<double>(*bad) << "; a label image holds whole numbers only.");
  }
}

template <typename TImage>
bool
SmallIsoComponentLabelImageFilter<TImage>::IsSelected(LabelType label) const
{
  switch (m_Selection)
  {
    case SelectionEnum::All:
      return true;
    case SelectionEnum::Islands:
      return !(label == m_BackgroundValue);
    case SelectionEnum::Holes:
      return label == m_BackgroundValue;
    case SelectionEnum::Listed:
      return std::find(m_SelectedLabels.begin(), m_SelectedLabels.end(), label) != m_SelectedLabels.end();
  }
  return false;
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::DecideRemovals()
{
  std::map<LabelType, std::vector<SizeValueType>> sizes;
  m_LabelStatistics.clear();
  for (RunIndex run = 0; run < m_Components.GetNumberOfRuns(); ++run)
  {
    if (m_Components.Component(run) == run)
    {
      const LabelType     label = m_Components.Label(run);
      const SizeValueType size = m_Components.Size(run);
      LabelStatistics &   statistics = m_LabelStatistics[label];
      ++statistics.Components;
      ++statistics.Histogram[size];
      sizes[label].push_back(size);
    }
  }
  // The size a selected label's components must reach to stay under KeepLargestComponents.
  std::map<LabelType, SizeValueType> smallestKept;
  for (auto & entry : sizes)
  {
    std::vector<SizeValueType> & labelSizes = entry.second;
    if (m_KeepLargestComponents > 0 && labelSizes.size() >= m_KeepLargestComponents)
    {
      const auto nth = labelSizes.begin() + static_cast<std::ptrdiff_t>(m_KeepLargestComponents - 1);
      std::nth_element(labelSizes.begin(), nth, labelSizes.end(), std::greater<SizeValueType>());
      smallestKept[entry.first] = *nth;
    }
  }
  m_Removed.assign(m_Components.GetNumberOfRuns(), 0);
  for (RunIndex run = 0; run < m_Components.GetNumberOfRuns(); ++run)
  {
    const LabelType label = m_Components.Label(run);
    if (m_Components.Component(run) != run || !this->IsSelected(label))
    {
      continue;
    }
    const auto          ownK = m_MaximumComponentSizes.find(label);
    const SizeValueType k = ownK != m_MaximumComponentSizes.end() ? ownK->second : m_EffectiveMaximumComponentSize;
    const auto          kept = smallestKept.find(label);
    const SizeValueType size = m_Components.Size(run);
    if (size <= k || (kept != smallestKept.end() && size < kept->second))
    {
      m_Removed[run] = 1;
      ++m_LabelStatistics[label].RemovedComponents;
      m_LabelStatistics[label].RemovedVoxels += size;
    }
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::CollectVotes(const LabelType *                  input,
                                                        const SizeType &                   size,
                                                        SizeValueType                      line,
                                                        const std::vector<SizeValueType> & coordinates,
                                                        RunIndex                           run,
                                                        SizeValueType                      x,
                                                        std::vector<Vote> &                votes) const
{
  // Along a line the walks leave the run at its ends; along the other axes they pass voxels of
  // the component's label, which are all in the component, up to the first other label.
  const auto vote = [this, &votes](RunIndex at, SizeValueType steps) {
    votes.push_back({ m_Components.Label(at), steps, !m_Removed[m_Components.Component(at)] });
  };
  votes.clear();
  const SizeValueType start = m_Components.Start(run);
  const SizeValueType end = m_Components.End(run, line);
  if (start > 0)
  {
    vote(run - 1, x - start + 1);
  }
  if (end < size[0])
  {
    vote(run + 1, end - x);
  }
  const LabelType label = m_Components.Label(run);
  SizeValueType   lineStride = 1;
  for (unsigned int a = 1; a < ImageDimension; ++a)
  {
    for (const int direction : { -1, 1 })
    {
      SizeValueType other = line;
      for (SizeValueType steps = 1; direction < 0 ? coordinates[a] >= steps : coordinates[a] + steps < size[a]; ++steps)
      {
        other = direction < 0 ? other - lineStride : other + lineStride;
        if (!(input[other * size[0] + x] == label))
        {
          vote(m_Components.RunAt(other, x), steps);
          break;
        }
      }
    }
    lineStride *= size[a];
  }
}

template <typename TImage>
auto
SmallIsoComponentLabelImageFilter<TImage>::Elect(const std::vector<Vote> & votes) -> LabelType
{
  const bool anyKept = std::any_of(votes.begin(), votes.end(), [](const Vote & vote) { return vote.Kept; });
  bool       found = false;
  LabelType  best{};
  std::pair<SizeValueType, SizeValueType> bestRank{ 0, 0 };
  for (const Vote & candidate : votes)
  {
    if (anyKept && !candidate.Kept)
    {
      continue;
    }
    // Rank: the most votes, then the nearest voter, then the smallest label.
    SizeValueType count = 0;
    SizeValueType nearest = NumericTraits<SizeValueType>::max();
    for (const Vote & vote : votes)
    {
      if ((vote.Kept || !anyKept) && vote.Label == candidate.Label)
      {
        ++count;
        nearest = std::min(nearest, vote.Steps);
      }
    }
    const std::pair<SizeValueType, SizeValueType> rank{ count, NumericTraits<SizeValueType>::max() - nearest };
    if (!found || rank > bestRank || (rank == bestRank && candidate.Label < best))
    {
      found = true;
      best = candidate.Label;
      bestRank = rank;
    }
  }
  return best;
}

template <typename TImage>
auto
SmallIsoComponentLabelImageFilter<TImage>::RepairRemoved(const LabelType *  input,
                                                         const RegionType & region,
                                                         const RegionType & outputRegion) -> std::vector<Repair>
{
  std::vector<Repair>        repairs;
  std::vector<Vote>          votes;
  std::vector<SizeValueType> coordinates(ImageDimension, 0);
  const SizeType             size = region.GetSize();
  this->ForEachRemovedRunInOutput(
    region,
    outputRegion,
    [&](SizeValueType line, RunIndex run, SizeValueType begin, SizeValueType end, SizeValueType inOutput) {
      const IndexType first = SmallIsoComponentDetail::IndexOfLine(region, line);
      for (unsigned int a = 1; a < ImageDimension; ++a)
      {
        coordinates[a] = static_cast<SizeValueType>(first[a] - region.GetIndex(a));
      }
      for (SizeValueType x = begin; x < end; ++x)
      {
        this->CollectVotes(input, size, line, coordinates, run, x, votes);
        if (votes.empty())
        {
          ++m_NumberOfUnrepairableVoxels;
          continue;
        }
        const LabelType label = Elect(votes);
        ++m_LabelStatistics[label].GainedVoxels;
        repairs.push_back({ inOutput + x - begin, label });
      }
    });
  return repairs;
}

template <typename TImage>
SizeValueType
SmallIsoComponentLabelImageFilter<TImage>::ComputeEffectiveMaximumComponentSize(const SpacingType & spacing) const
{
  if (!m_UseMaximumComponentVolume)
  {
    return m_MaximumComponentSize;
  }
  double voxelVolume = 1.0;
  for (unsigned int a = 0; a < ImageDimension; ++a)
  {
    voxelVolume *= spacing[a];
  }
  return SmallIsoComponentDetail::ComponentRules::MaximumSizeForVolume(m_MaximumComponentVolume, voxelVolume);
}

template <typename TImage>
template <typename TFunction>
void
SmallIsoComponentLabelImageFilter<TImage>::ForEachRemovedRunInOutput(const RegionType & region,
                                                                     const RegionType & outputRegion,
                                                                     TFunction &&       function) const
{
  // Lines are visited in the buffer's order and placed in the output only at their first
  // removed run: removed runs are few, so most lines cost no index arithmetic.
  const SizeValueType first = static_cast<SizeValueType>(outputRegion.GetIndex(0) - region.GetIndex(0));
  const SizeValueType last = first + outputRegion.GetSize(0);
  for (SizeValueType line = 0; line < m_Components.GetNumberOfLines(); ++line)
  {
    bool          placed = false;
    SizeValueType lineInOutput = 0;
    for (RunIndex run = m_Components.LineBegin(line); run < m_Components.LineEnd(line); ++run)
    {
      if (!m_Removed[m_Components.Component(run)])
      {
        continue;
      }
      const SizeValueType begin = std::max(first, m_Components.Start(run));
      const SizeValueType end = std::min(last, m_Components.End(run, line));
      if (begin >= end)
      {
        continue;
      }
      if (!placed)
      {
        IndexType index = SmallIsoComponentDetail::IndexOfLine(region, line);
        index[0] = outputRegion.GetIndex(0);
        if (!outputRegion.IsInside(index))
        {
          break;
        }
        placed = true;
        lineInOutput = SmallIsoComponentDetail::OffsetOf(outputRegion, index);
      }
      function(line, run, begin, end, lineInOutput + begin - first);
    }
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::GenerateData()
{
  const ImageType * input = this->GetInput();
  // The part read: the output's region and its halo, or the whole image.
  const RegionType  region = input->GetRequestedRegion();
  const LabelType * labels = input->GetBufferPointer();
  if (region != input->GetBufferedRegion())
  {
    m_Part.resize(region.GetNumberOfPixels());
    SmallIsoComponentDetail::CopyLines(labels, input->GetBufferedRegion(), m_Part.data(), region, region);
    labels = m_Part.data();
  }
  this->VerifyWholeNumbers(labels, region);
  this->AllocateOutputs();
  m_EffectiveMaximumComponentSize = this->ComputeEffectiveMaximumComponentSize(input->GetSpacing());
  m_NumberOfModifiedVoxels = 0;
  m_NumberOfUnrepairableVoxels = 0;

  const SizeType                   size = region.GetSize();
  const std::vector<SizeValueType> extent(size.begin(), size.end());
  this->GetMultiThreader()->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  m_Components.Find(labels, extent, m_FullyConnected, this->GetMultiThreader());
  this->UpdateProgress(0.5f);
  this->StopIfAborted();
  this->DecideRemovals();
  const std::vector<Repair> repairs = this->RepairRemoved(labels, region, this->GetOutput()->GetBufferedRegion());
  this->UpdateProgress(0.8f);
  this->StopIfAborted();
  this->WriteOutputs(labels, region, repairs);
  this->UpdateProgress(1.0f);
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::WriteOutputs(const LabelType *           labels,
                                                        const RegionType &          region,
                                                        const std::vector<Repair> & repairs)
{
  ImageType *      output = this->GetOutput();
  const RegionType outputRegion = output->GetBufferedRegion();
  LabelType *      outputBuffer = output->GetBufferPointer();
  if (outputBuffer != labels)
  {
    SmallIsoComponentDetail::CopyLines(
      labels, region, outputBuffer, outputRegion, outputRegion, this->GetMultiThreader());
  }
  for (const Repair & repair : repairs)
  {
    outputBuffer[repair.Offset] = repair.Label;
  }
  m_NumberOfModifiedVoxels = repairs.size();
  if (m_GenerateRemovedMask)
  {
    uint8_t * const mask = this->GetRemovedMask()->GetBufferPointer();
    this->ForEachRemovedRunInOutput(
      region,
      outputRegion,
      [mask](SizeValueType, RunIndex, SizeValueType begin, SizeValueType end, SizeValueType inOutput) {
        std::fill(mask + inOutput, mask + inOutput + (end - begin), 1);
      });
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::StopIfAborted() const
{
  if (this->GetAbortGenerateData())
  {
    ProcessAborted abort(__FILE__, __LINE__);
    abort.SetDescription("SmallIsoComponentLabelImageFilter: aborted by the user");
    throw abort;
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "MaximumComponentSize: " << m_MaximumComponentSize << std::endl;
  os << indent << "MaximumComponentVolume: " << m_MaximumComponentVolume << std::endl;
  os << indent << "UseMaximumComponentVolume: " << (m_UseMaximumComponentVolume ? "On" : "Off") << std::endl;
  os << indent << "MaximumComponentSizes: " << m_MaximumComponentSizes.size() << " labels" << std::endl;
  os << indent << "Selection: " << m_Selection << std::endl;
  os << indent << "SelectedLabels: " << m_SelectedLabels.size() << " labels" << std::endl;
  os << indent << "BackgroundValue: " << static_cast<typename NumericTraits<LabelType>::PrintType>(m_BackgroundValue)
     << std::endl;
  os << indent << "KeepLargestComponents: " << m_KeepLargestComponents << std::endl;
  os << indent << "FullyConnected: " << (m_FullyConnected ? "On" : "Off") << std::endl;
  os << indent << "GenerateRemovedMask: " << (m_GenerateRemovedMask ? "On" : "Off") << std::endl;
  os << indent << "NumberOfModifiedVoxels: " << m_NumberOfModifiedVoxels << std::endl;
  os << indent << "NumberOfUnrepairableVoxels: " << m_NumberOfUnrepairableVoxels << std::endl;
}
} // end namespace itk

#endif
