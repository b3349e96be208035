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
SmallIsoComponentLabelImageFilter<TImage>::SetMaximumComponentSizeOfLabel(LabelType label, SizeValueType size)
{
  LabelSizeMapType sizes = m_MaximumComponentSizes;
  sizes[label] = size;
  this->SetMaximumComponentSizes(sizes);
}

template <typename TImage>
auto
SmallIsoComponentLabelImageFilter<TImage>::GetLabels() const -> std::vector<LabelType>
{
  std::vector<LabelType> labels;
  for (const auto & entry : m_LabelStatistics)
  {
    labels.push_back(entry.first);
  }
  return labels;
}

template <typename TImage>
auto
SmallIsoComponentLabelImageFilter<TImage>::StatisticsOf(LabelType label) const -> const LabelStatistics &
{
  static const LabelStatistics none;
  const auto                   found = m_LabelStatistics.find(label);
  return found == m_LabelStatistics.end() ? none : found->second;
}

template <typename TImage>
SizeValueType
SmallIsoComponentLabelImageFilter<TImage>::GetNumberOfComponents(LabelType label) const
{
  return this->StatisticsOf(label).Components;
}

template <typename TImage>
SizeValueType
SmallIsoComponentLabelImageFilter<TImage>::GetNumberOfRemovedComponents(LabelType label) const
{
  return this->StatisticsOf(label).RemovedComponents;
}

template <typename TImage>
SizeValueType
SmallIsoComponentLabelImageFilter<TImage>::GetNumberOfRemovedVoxels(LabelType label) const
{
  return this->StatisticsOf(label).RemovedVoxels;
}

template <typename TImage>
SizeValueType
SmallIsoComponentLabelImageFilter<TImage>::GetNumberOfGainedVoxels(LabelType label) const
{
  return this->StatisticsOf(label).GainedVoxels;
}

template <typename TImage>
auto
SmallIsoComponentLabelImageFilter<TImage>::GetComponentSizeHistogram(LabelType label) const
  -> ComponentSizeHistogramType
{
  return this->StatisticsOf(label).Histogram;
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
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::VerifyWholeNumbers(const LabelType * labels, const RegionType & region) const
{
  if (m_Components.HoldsWholeNumbersOnly())
  {
    return;
  }
  const SizeValueType     count = region.GetNumberOfPixels();
  const LabelType * const bad = std::find_if(
    labels, labels + count, [](LabelType value) { return !SmallIsoComponentDetail::AreWholeNumbers(&value, 1); });
  itkExceptionMacro("The label image's sample at "
                    << SmallIsoComponentDetail::IndexOf(region, static_cast<SizeValueType>(bad - labels)) << " is "
                    << static_cast<double>(*bad) << "; a label image holds whole numbers only.");
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
SmallIsoComponentLabelImageFilter<TImage>::DecideRemovals(SmallIsoComponentDetail::WorkTeam & team)
{
  // Each slab's components are counted and decided by one work unit; the sums do not depend on the slabs.
  std::vector<SlabCounts> slabs(m_Components.GetNumberOfSlabs());
  team.ForEach(slabs.size(), [&](SizeValueType slab) { this->CountComponents(slab, slabs[slab]); });
  m_LabelStatistics.clear();
  std::map<LabelType, std::vector<SizeValueType>> sizes;
  for (SlabCounts & counts : slabs)
  {
    // The first counts are taken over as they are, the others added.
    if (m_LabelStatistics.empty())
    {
      m_LabelStatistics.swap(counts.Labels);
    }
    this->AddLabelStatistics(counts.Labels);
    counts.Labels.clear();
    for (auto & entry : counts.Sizes)
    {
      std::vector<SizeValueType> & labelSizes = sizes[entry.first];
      labelSizes.insert(labelSizes.end(), entry.second.begin(), entry.second.end());
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
  team.ForEach(slabs.size(), [&](SizeValueType slab) { this->MarkRemovals(slab, smallestKept, slabs[slab]); });
  for (const SlabCounts & counts : slabs)
  {
    this->AddLabelStatistics(counts.Labels);
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::AddLabelStatistics(const LabelStatisticsMapType & counts)
{
  for (const auto & entry : counts)
  {
    LabelStatistics & statistics = m_LabelStatistics[entry.first];
    statistics.Components += entry.second.Components;
    statistics.RemovedComponents += entry.second.RemovedComponents;
    statistics.RemovedVoxels += entry.second.RemovedVoxels;
    statistics.GainedVoxels += entry.second.GainedVoxels;
    for (const auto & bin : entry.second.Histogram)
    {
      statistics.Histogram[bin.first] += bin.second;
    }
  }
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::CountComponents(SizeValueType slab, SlabCounts & counts) const
{
  m_Components.ForEachComponentOfSlab(slab, [&](RunIndex root, SizeValueType size) {
    const LabelType   label = m_Components.Label(root);
    LabelStatistics & statistics = counts.Labels[label];
    ++statistics.Components;
    ++statistics.Histogram[size];
    if (m_KeepLargestComponents > 0)
    {
      counts.Sizes[label].push_back(size);
    }
  });
}

template <typename TImage>
void
SmallIsoComponentLabelImageFilter<TImage>::MarkRemovals(SizeValueType                              slab,
                                                        const std::map<LabelType, SizeValueType> & smallestKept,
                                                        SlabCounts &                               counts)
{
  m_Components.ForEachComponentOfSlab(slab, [&](RunIndex root, SizeValueType size) {
    const LabelType label = m_Components.Label(root);
    if (!this->IsSelected(label))
    {
      return;
    }
    const auto          ownK = m_MaximumComponentSizes.find(label);
    const SizeValueType k = ownK != m_MaximumComponentSizes.end() ? ownK->second : m_EffectiveMaximumComponentSize;
    const auto          kept = smallestKept.find(label);
    if (size <= k || (kept != smallestKept.end() && size < kept->second))
    {
      m_Components.MarkRemoved(root);
      ++counts.Labels[label].RemovedComponents;
      counts.Labels[label].RemovedVoxels += size;
    }
  });
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
void
SmallIsoComponentLabelImageFilter<TImage>::GenerateData()
{
  // Formed first, so that its helpers wake up while the part is read.
  this->GetMultiThreader()->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  SmallIsoComponentDetail::WorkTeam team(this->GetMultiThreader(), this->GetNumberOfWorkUnits());
  const ImageType *                 input = this->GetInput();
  // The part read: the output's region and its halo, or the whole image.
  const RegionType  region = input->GetRequestedRegion();
  const LabelType * labels = input->GetBufferPointer();
  if (region != input->GetBufferedRegion())
  {
    m_Part.resize(region.GetNumberOfPixels());
    SmallIsoComponentDetail::CopyLines(labels, input->GetBufferedRegion(), m_Part.data(), region, region);
    labels = m_Part.data();
  }
  this->AllocateOutputs();
  m_EffectiveMaximumComponentSize = this->ComputeEffectiveMaximumComponentSize(input->GetSpacing());
  m_NumberOfModifiedVoxels = 0;
  m_NumberOfUnrepairableVoxels = 0;

  const SizeType                   size = region.GetSize();
  const std::vector<SizeValueType> extent(size.begin(), size.end());
  // The output of the whole part read (not in place) is copied as the runs are found, while each
  // line is in cache; the output of a smaller part after the decision.
  LabelType * const outputBuffer = this->GetOutput()->GetBufferPointer();
  const bool        copyWithRuns = this->GetOutput()->GetBufferedRegion() == region && outputBuffer != labels;
  m_Components.Find(labels, extent, m_FullyConnected, team, copyWithRuns ? outputBuffer : nullptr);
  this->VerifyWholeNumbers(labels, region);
  this->UpdateProgress(0.5f);
  this->StopIfAborted();
  this->DecideRemovals(team);
  // The output starts as the input; the repair marks the mask and finds the removed voxels' labels.
  uint8_t * const mask = this->CopyInputAndClearMask(labels, region, outputBuffer != labels && !copyWithRuns, team);
  m_Repair.Compute(labels, m_Components, region, this->GetOutput()->GetBufferedRegion(), mask, team);
  for (const auto & gained : m_Repair.GetGainedVoxels())
  {
    m_LabelStatistics[gained.first].GainedVoxels += gained.second;
  }
  m_NumberOfUnrepairableVoxels = m_Repair.GetNumberOfUnrepairableVoxels();
  m_NumberOfModifiedVoxels = m_Repair.GetNumberOfRepairs();
  this->UpdateProgress(0.8f);
  this->StopIfAborted();
  m_Repair.ForEachRepair(
    [outputBuffer](const typename Repair::Repair & repair) { outputBuffer[repair.Offset] = repair.Label; });
  this->UpdateProgress(1.0f);
}

template <typename TImage>
uint8_t *
SmallIsoComponentLabelImageFilter<TImage>::CopyInputAndClearMask(const LabelType *                   labels,
                                                                 const RegionType &                  region,
                                                                 bool                                copyInput,
                                                                 SmallIsoComponentDetail::WorkTeam & team)
{
  ImageType * const   output = this->GetOutput();
  const RegionType    outputRegion = output->GetBufferedRegion();
  LabelType * const   outputBuffer = output->GetBufferPointer();
  uint8_t * const     mask = m_GenerateRemovedMask ? this->GetRemovedMask()->GetBufferPointer() : nullptr;
  const SizeValueType length = outputRegion.GetSize(0);
  SmallIsoComponentDetail::ForEachLineInSlabs(
    team, SmallIsoComponentDetail::NumberOfLines(outputRegion), [&](SizeValueType line) {
      if (copyInput)
      {
        const IndexType first = SmallIsoComponentDetail::IndexOfLine(outputRegion, line);
        std::copy_n(labels + SmallIsoComponentDetail::OffsetOf(region, first), length, outputBuffer + line * length);
      }
      if (mask != nullptr)
      {
        std::fill_n(mask + line * length, length, 0);
      }
    });
  return mask;
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
