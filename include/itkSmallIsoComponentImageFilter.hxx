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
#ifndef itkSmallIsoComponentImageFilter_hxx
#define itkSmallIsoComponentImageFilter_hxx

#include "itkSmallIsoComponentImageFilter.h"
#include "itkSmallIsoComponentRunEncoder.h"
#include "itkSmallIsoComponentRunRepair.h"
#include "itkSmallIsoComponentSizeCounter.h"
#include "itkSmallIsoComponentStreamingStores.h"
#include "itkSmallIsoComponentStreamingSweep.h"
#include "itkSmallIsoComponentThreshold.h"
#include <algorithm>
#include <atomic>
#include <cstring>

namespace itk
{
template <typename TInputImage, typename TOutputImage>
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::SmallIsoComponentImageFilter()
  : m_Working(std::make_unique<WorkingMemory>())
{}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::StatisticsOf(SideEnum side) -> SideStatistics &
{
  return const_cast<SideStatistics &>(static_cast<const Self *>(this)->StatisticsOf(side));
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::StatisticsOf(SideEnum side) const -> const SideStatistics &
{
  this->VerifyStatisticsSide(side);
  return side == SideEnum::Above ? m_AboveStatistics : m_BelowStatistics;
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GetSideCounts(SideEnum side) const ->
  typename Superclass::SideCounts
{
  return this->StatisticsOf(side);
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GetComponentSizeHistogram(SideEnum side) const
  -> const ComponentSizeHistogramType &
{
  return this->StatisticsOf(side).Histogram;
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  if (auto * input = const_cast<InputImageType *>(this->GetInput()))
  {
    input->SetRequestedRegionToLargestPossibleRegion();
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::EnlargeOutputRequestedRegion(DataObject *)
{
  for (unsigned int i = 0; i < this->GetNumberOfIndexedOutputs(); ++i)
  {
    if (DataObject * output = this->ProcessObject::GetOutput(i))
    {
      output->SetRequestedRegionToLargestPossibleRegion();
    }
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::ReleaseWorkingMemory()
{
  m_Working->ReleaseMemory();
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GetWorkingMemoryInBytes() const
{
  return m_Working->Labeling.GetMemoryInBytes() + m_Working->GetPassBytes();
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GenerateData()
{
  this->GetMultiThreader()->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  this->m_EffectiveMaximumComponentSize = this->ComputeEffectiveMaximumComponentSize(this->GetInput()->GetSpacing());
  m_SweptSlabThickness = this->ChooseSlabThickness();
  if (m_SweptSlabThickness > 0)
  {
    this->AllocateOutputs();
    this->VerifyBufferedRegions();
    this->ResetStatistics();
    this->SweepInSlabs(m_SweptSlabThickness);
    return;
  }
  // The parallel steps are short: one team of threads takes them all, instead of waking
  // the threader's pool for each. It is formed first, so that its helpers wake up while
  // the outputs are allocated.
  WorkTeam team(this->GetMultiThreader(), this->GetNumberOfWorkUnits());
  this->AllocateOutputs();
  this->VerifyBufferedRegions();
  this->ResetStatistics();

  // The components of both sides, labelled over the lines' runs.
  const auto & size = this->GetOutput()->GetBufferedRegion().GetSize();
  // The labelling's arrays, and the passes', are kept from the last update (see
  // ReleaseWorkingMemory()).
  RunLabeling & labeling = m_Working->Labeling;
  labeling.Initialize(
    std::vector<SizeValueType>(size.begin(), size.end()), this->m_FullyConnected, this->GetNumberOfWorkUnits());
  ProgressTransformer encodeProgress(0.0f, 0.3f, this);
  const DeferredFill  fill = this->EncodeRuns(team, labeling);
  m_PhaseClock.End(PhaseEnum::Encoding);
  this->EndPhase(encodeProgress);

  ProgressTransformer assembleProgress(0.3f, 0.35f, this);
  labeling.AssembleRuns(team);
  m_PhaseClock.End(PhaseEnum::Linking);
  m_ExtraMemory.Hold(labeling.GetPeakMemoryInBytes() + m_Working->GetPassBytes());
  this->EndPhase(assembleProgress);

  ProgressTransformer numberProgress(0.35f, 0.7f, this);
  this->LinkAndNumberComponents(team, labeling, fill);
  this->EndPhase(numberProgress);

  // The above pass, then the below pass on the image the above pass leaves.
  ProgressTransformer aboveProgress(0.7f, 0.8f, this);
  this->RemoveAbove(team);
  this->EndPhase(aboveProgress);

  ProgressTransformer groupProgress(0.8f, 0.85f, this);
  this->GroupBelow(team);
  m_PhaseClock.End(PhaseEnum::Deciding);
  this->EndPhase(groupProgress);

  ProgressTransformer belowProgress(0.85f, 1.0f, this);
  this->RemoveBelow(team);
  belowProgress.GetProcessObject()->UpdateProgress(1.0f);
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::ChooseSlabThickness() const
{
  if constexpr (ImageDimension != 2 && ImageDimension != 3)
  {
    return 0;
  }
  const auto &        region = this->GetOutput()->GetRequestedRegion();
  const SizeValueType voxels = region.GetNumberOfPixels();
  const SizeValueType depth = region.GetSize(ImageDimension - 1);
  if (voxels == 0)
  {
    return 0;
  }
  if (m_SlabThickness > 0)
  {
    return std::min(m_SlabThickness, depth);
  }
  if (voxels < m_SlabSweepMinimumSize)
  {
    return 0;
  }
  const SizeValueType planeVoxels = voxels / depth;
  // About ChosenSlabVoxels a slab, and at least 16 slabs.
  const SizeValueType slab = std::max<SizeValueType>(1, std::min(ChosenSlabVoxels / planeVoxels, depth / 16));
  const uint64_t      window = SmallIsoComponentDetail::StreamingSweep<OutputPixelType>::WindowPlanes(
    this->m_EffectiveMaximumComponentSize, slab, this->GetNumberOfWorkUnits());
  return 2 * window <= depth ? slab : 0;
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::SweepInSlabs(SizeValueType slabPlanes)
{
  using SweepType = SmallIsoComponentDetail::StreamingSweep<OutputPixelType>;
  const auto &                        size = this->GetOutput()->GetBufferedRegion().GetSize();
  constexpr unsigned int              last = ImageDimension - 1;
  const uint64_t                      depth = size[last];
  const uint64_t                      planeVoxels = this->GetOutput()->GetBufferedRegion().GetNumberOfPixels() / depth;
  const typename SweepType::IndexType box = ImageDimension == 3
                                              ? typename SweepType::IndexType{ size[0], size[1], size[last] }
                                              : typename SweepType::IndexType{ size[0], 1, size[last] };
  const InputPixelType *              in = this->GetInput()->GetBufferPointer();
  OutputPixelType *                   out = this->GetOutput()->GetBufferPointer();
  MaskPixelType * mask = this->m_GenerateRemovedMask ? this->GetRemovedMask()->GetBufferPointer() : nullptr;
  // The sweep copies each slab it takes, and gives out a plane only after taking it: in place,
  // the planes written are ones the sweep has taken already.
  SweepType                    sweep(box,
                  this->m_IsoValue,
                  this->m_EffectiveMaximumComponentSize,
                  this->m_Side,
                  this->m_FullyConnected,
                  slabPlanes,
                  mask != nullptr,
                  this->GetMultiThreader(),
                  this->GetNumberOfWorkUnits(),
                  [&](uint64_t plane, const OutputPixelType * values, const uint8_t * planeMask) {
                    std::copy(values, values + planeVoxels, out + plane * planeVoxels);
                    if (mask != nullptr)
                    {
                      SmallIsoComponentDetail::CopyRemovedMask(planeMask, planeVoxels, mask + plane * planeVoxels);
                    }
                    this->UpdateProgress(static_cast<float>(plane + 1) / static_cast<float>(depth));
                  });
  std::vector<OutputPixelType> converted;
  for (uint64_t first = 0; first < depth; first += slabPlanes)
  {
    const uint64_t         planes = std::min<uint64_t>(slabPlanes, depth - first);
    const InputPixelType * from = in + first * planeVoxels;
    if constexpr (std::is_same<InputPixelType, OutputPixelType>::value)
    {
      sweep.Push(from, planes);
    }
    else
    {
      converted.resize(planes * planeVoxels);
      std::transform(from, from + converted.size(), converted.begin(), [](InputPixelType v) {
        return static_cast<OutputPixelType>(v);
      });
      sweep.Push(converted.data(), planes);
    }
    this->StopIfAborted();
  }
  sweep.Finish();

  const SmallIsoComponentDetail::ComponentTally & tally = sweep.GetTally();
  for (const SideEnum side : { SideEnum::Above, SideEnum::Below })
  {
    const SmallIsoComponentDetail::SideTally & counts = side == SideEnum::Above ? tally.Above : tally.Below;
    SideStatistics &                           statistics = this->StatisticsOf(side);
    statistics.Components = counts.GetComponents();
    statistics.RemovedComponents = counts.GetRemovedComponents();
    statistics.RemovedVoxels = counts.GetRemovedVoxels();
    const auto histogram = counts.GetHistogram();
    statistics.Histogram = ComponentSizeHistogramType(histogram.begin(), histogram.end());
  }
  m_NumberOfModifiedVoxels = tally.ModifiedVoxels;
  m_NumberOfUnrepairableVoxels = tally.UnrepairableVoxels + sweep.GetNumberOfFallbackVoxels();
  m_ExtraMemory.Hold(sweep.GetPeakMemoryInBytes() + converted.capacity() * sizeof(OutputPixelType));
  this->UpdateProgress(1.0f);
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::VerifyBufferedRegions()
{
  const auto & region = this->GetOutput()->GetBufferedRegion();
  const auto & inputRegion = this->GetInput()->GetBufferedRegion();
  if (inputRegion != region || (this->m_GenerateRemovedMask && this->GetRemovedMask()->GetBufferedRegion() != region))
  {
    itkExceptionMacro("The input's buffered region " << inputRegion << " differs from the output's " << region
                                                     << "; the filter needs the whole image in one buffer.");
  }
  if (region.GetNumberOfPixels() == 0)
  {
    itkExceptionMacro("The input image is empty (size " << region.GetSize() << "); it must have at least one voxel.");
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::ResetStatistics()
{
  m_AboveStatistics = SideStatistics();
  m_BelowStatistics = SideStatistics();
  m_NumberOfModifiedVoxels = 0;
  m_NumberOfUnrepairableVoxels = 0;
  m_ExtraMemory.Reset();
  m_PhaseClock.Start();
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::EncodeRuns(WorkTeam & team, RunLabeling & labeling)
  -> DeferredFill
{
  MaskPixelType *     maskBuffer = this->m_GenerateRemovedMask ? this->GetRemovedMask()->GetBufferPointer() : nullptr;
  const SizeValueType maskPixelBytes = this->m_GenerateRemovedMask ? sizeof(MaskPixelType) : 0;
  const InputPixelType * inBuffer = this->GetInput()->GetBufferPointer();
  OutputPixelType *      outBuffer = this->GetOutput()->GetBufferPointer();
  const bool             copy = static_cast<const void *>(inBuffer) != static_cast<const void *>(outBuffer);
  const SizeValueType    length = labeling.GetLineLength();
  const SizeValueType    lines = labeling.GetNumberOfLines();
  const bool             stream = length * lines * (sizeof(OutputPixelType) + maskPixelBytes) >=
                      SmallIsoComponentDetail::Tuning::StreamingThresholdInBytes;
  const SmallIsoComponentDetail::RunEncoder<OutputPixelType> encoder(this->m_IsoValue);
  if constexpr (std::is_same<InputPixelType, OutputPixelType>::value)
  {
    if (stream)
    {
      // The output would not stay in the caches: the lines are encoded from the input,
      // which holds the same values, and the output and the mask are written later,
      // with streaming stores, while the components are numbered (a serial step that
      // leaves the other work units free). In place and without a mask, nothing is.
      encoder.Encode(inBuffer, labeling, team);
      if (!copy && maskBuffer == nullptr)
      {
        return DeferredFill();
      }
      return DeferredFill(
        inBuffer, outBuffer, length * sizeof(OutputPixelType), maskBuffer, length * maskPixelBytes, lines);
    }
  }
  // The output and the mask are filled block by block (whole lines, contiguous in
  // memory) just before the block's lines are encoded.
  encoder.Encode(
    outBuffer,
    labeling,
    team,
    [&](SizeValueType first, SizeValueType end) {
      const InputPixelType * in = inBuffer + first * length;
      OutputPixelType *      out = outBuffer + first * length;
      const SizeValueType    count = (end - first) * length;
      if constexpr (std::is_same<InputPixelType, OutputPixelType>::value)
      {
        if (copy)
        {
          std::memcpy(out, in, count * sizeof(OutputPixelType));
        }
      }
      else
      {
        std::transform(in, in + count, out, [](InputPixelType v) { return static_cast<OutputPixelType>(v); });
      }
      if (maskBuffer == nullptr)
      {
        return;
      }
      if (stream)
      {
        SmallIsoComponentDetail::StreamZero(maskBuffer + first * length, count * sizeof(MaskPixelType));
      }
      else
      {
        std::memset(maskBuffer + first * length, 0, count * sizeof(MaskPixelType));
      }
    },
    [stream] {
      if (stream)
      {
        SmallIsoComponentDetail::StreamFence();
      }
    });
  return DeferredFill();
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::LinkAndNumberComponents(WorkTeam &           team,
                                                                                 RunLabeling &        labeling,
                                                                                 const DeferredFill & fill)
{
  // Only the sides a pass removes need their candidate runs.
  const SizeValueType candidateSize = this->m_EffectiveMaximumComponentSize;
  const SizeValueType aboveCandidateSize = this->m_Side == SideEnum::Below ? 0 : candidateSize;
  const SizeValueType belowCandidateSize = this->m_Side == SideEnum::Above ? 0 : candidateSize;
  if (fill.IsEmpty() || team.GetNumberOfWorkUnits() <= 1)
  {
    labeling.LinkRuns();
    m_PhaseClock.End(PhaseEnum::Seams);
    labeling.LabelComponents(team, aboveCandidateSize, belowCandidateSize);
    for (SizeValueType block = 0; block < fill.GetNumberOfBlocks(); ++block)
    {
      fill.FillBlock(block);
    }
  }
  else
  {
    // The output and the mask are written, block by block, by the work units that would
    // otherwise wait: beside the serial linking of the seams, then wherever the numbering
    // leaves one free (LabelComponents()); what is left after it, by all of them.
    std::atomic<SizeValueType> nextBlock{ 0 };
    const SizeValueType        blocks = fill.GetNumberOfBlocks();
    const auto                 fillOne = [&fill, &nextBlock, blocks] {
      const SizeValueType block = nextBlock.fetch_add(1);
      if (block >= blocks)
      {
        return false;
      }
      fill.FillBlock(block);
      return true;
    };
    std::atomic<bool> seamsLinked{ false };
    team.ForEach(team.GetNumberOfWorkUnits(), [&](SizeValueType item) {
      if (item == 0)
      {
        labeling.LinkRuns();
        seamsLinked.store(true, std::memory_order_release);
      }
      else
      {
        while (!seamsLinked.load(std::memory_order_acquire) && fillOne())
        {}
      }
    });
    m_PhaseClock.End(PhaseEnum::Seams);
    // A fill long beside the numbering is better written beside a serial numbering, which
    // leaves every other work unit free for it, than in the moments a shared one leaves
    // (see docs/performance.md).
    // With Side Both, the memory of the groups' component table and of the removed runs,
    // taken later anyway, serves first as the scratch of a shared numbering's help: the
    // partial sizes and the candidates of the lines its first stage sums.
    const bool                                      bothSides = this->m_Side == SideEnum::Both;
    SmallIsoComponentDetail::RunComponents::Sharing sharing;
    sharing.OtherWork = fillOne;
    sharing.Pipeline = labeling.GetNumberOfRuns() * SmallIsoComponentDetail::Tuning::FillBytesPerRunToShareNumbering >=
                       fill.GetNumberOfBytes();
    sharing.PartialSizes = bothSides ? &m_Working->Groups.GroupOfComponent : nullptr;
    sharing.PartialCandidates = bothSides ? &m_Working->Runs : nullptr;
    labeling.LabelComponents(team, aboveCandidateSize, belowCandidateSize, sharing);
    if (nextBlock.load() < blocks)
    {
      team.ForEach(team.GetNumberOfWorkUnits(), [&](SizeValueType) {
        while (fillOne())
        {}
      });
    }
  }
  m_PhaseClock.End(PhaseEnum::Numbering);
  m_ExtraMemory.Hold(labeling.GetMemoryInBytes() + m_Working->GetPassBytes());
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::RemoveAbove(WorkTeam & team)
{
  WorkingMemory & working = *m_Working;
  // Without a below pass after it, the above pass flips nothing, and the below side is
  // decided on its components too, in the same pass over them; with one, the below side is
  // decided after the above pass (GroupBelow()).
  this->DecideComponentRemovals(
    team, &working.RemovedAbove, this->m_Side == SideEnum::Both ? nullptr : &working.RemovedBelow);
  this->CollectRemovedRuns(team, working.RemovedAbove, SideEnum::Above);
  // Finding the below components that the flipped ones join visits the same runs as
  // the repair, so it is done in the repair's loop.
  if (this->AbovePassFlips())
  {
    working.Grouping.Reset(working.Labeling);
  }
  m_ExtraMemory.Hold(working.Labeling.GetMemoryInBytes() + working.GetPassBytes());
  m_PhaseClock.End(PhaseEnum::Deciding);
  this->RepairRuns(team, working.Runs, SideEnum::Above, this->AbovePassFlips() ? &working.Grouping : nullptr);
  m_NumberOfModifiedVoxels += m_AboveStatistics.RemovedVoxels;
  // The flipped runs have been joined.
  working.Runs.clear();
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GroupBelow(WorkTeam & team)
{
  WorkingMemory & working = *m_Working;
  // Without a below pass after it (Side Above) the above pass flips nothing: the below
  // side's statistics describe the input. When nothing flips, the groups are the below
  // components themselves, and no grouping is needed.
  if (!this->AbovePassFlips())
  {
    if (this->m_Side == SideEnum::Both)
    {
      this->DecideComponentRemovals(team, nullptr, &working.RemovedBelow);
    }
    m_ExtraMemory.Hold(working.Labeling.GetMemoryInBytes() + working.GetPassBytes());
    return;
  }
  working.Grouping.Finish(working.RemovedAbove, working.Groups);
  const BelowGrouping::Groups & groups = working.Groups;
  this->DecideRemovals(
    team,
    groups.GroupSize.size(),
    [&groups](SizeValueType group) { return groups.GroupSize[group]; },
    [](SizeValueType) { return false; },
    nullptr,
    &working.RemovedGroups);
  // A component is removed with its group. The voxels of a removed group's flipped
  // members were counted as modified by the above pass already, and are not counted again.
  const SizeValueType components = working.Labeling.GetComponents().GetNumberOfComponents();
  working.RemovedBelow.resize(components);
  const SizeValueType                           parts = team.GetNumberOfParts(components);
  std::vector<SizeValueType>                    countedAlready(parts, 0);
  const RunLabeling::ComponentIndexType * const groupOf = groups.GroupOfComponent.data();
  const uint8_t * const                         removedGroup = working.RemovedGroups.data();
  const uint8_t * const                         removedAbove = working.RemovedAbove.data();
  uint8_t * const                               removedBelow = working.RemovedBelow.data();
  const RunLabeling &                           labeling = working.Labeling;
  team.ForEach(parts, [&](SizeValueType part) {
    const SizeValueType end = WorkTeam::PartBegin(components, part + 1, parts);
    SizeValueType       counted = 0;
    for (SizeValueType component = WorkTeam::PartBegin(components, part, parts); component < end; ++component)
    {
      const RunLabeling::ComponentIndexType group = groupOf[component];
      const uint8_t removed = group != BelowGrouping::NoGroup ? removedGroup[group] : uint8_t{ 0 };
      removedBelow[component] = removed;
      counted += labeling.GetComponents().GetComponentSize(static_cast<RunLabeling::ComponentIndexType>(component)) &
                 (SizeValueType{ 0 } - static_cast<SizeValueType>(removed & removedAbove[component]));
    }
    countedAlready[part] = counted;
  });
  for (const SizeValueType counted : countedAlready)
  {
    m_NumberOfModifiedVoxels -= counted;
  }
  m_ExtraMemory.Hold(working.Labeling.GetMemoryInBytes() + working.GetPassBytes());
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::RemoveBelow(WorkTeam & team)
{
  WorkingMemory & working = *m_Working;
  // A removed group has at most K voxels, so all of its below components' runs are
  // candidates; its flipped components' runs are candidates too.
  this->CollectRemovedRuns(team, working.RemovedBelow, SideEnum::Below);
  m_ExtraMemory.Hold(working.Labeling.GetMemoryInBytes() + working.GetPassBytes());
  m_PhaseClock.End(PhaseEnum::Deciding);
  this->RepairRuns(team, working.Runs, SideEnum::Below, nullptr);
  working.Runs.clear();
  // Every voxel of a removed group is written; those of its flipped members were counted
  // by the above pass already, and taken off again by GroupBelow(). (Without flips a group
  // is one below component, and the flags of the two passes mark components of different
  // sides.)
  m_NumberOfModifiedVoxels += m_BelowStatistics.RemovedVoxels;
}

template <typename TInputImage, typename TOutputImage>
template <typename TSizeOf, typename TIsAbove>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::DecideRemovals(WorkTeam &             team,
                                                                        SizeValueType          entries,
                                                                        TSizeOf &&             sizeOf,
                                                                        TIsAbove &&            isAbove,
                                                                        std::vector<uint8_t> * removedAbove,
                                                                        std::vector<uint8_t> * removedBelow)
{
  const SmallIsoComponentDetail::Threshold<OutputPixelType> threshold(this->m_IsoValue);
  // Per side (0 below, 1 above): whether it is decided, whether its pass removes, and
  // whether the output type has a value on the other side to repair with.
  const bool decided[2] = { removedBelow != nullptr, removedAbove != nullptr };
  const bool passRuns[2] = { decided[0] && (this->m_Side == SideEnum::Below || this->m_Side == SideEnum::Both),
                             decided[1] && (this->m_Side == SideEnum::Above || this->m_Side == SideEnum::Both) };
  const bool removable[2] = { passRuns[0] && threshold.AnyAbove(), passRuns[1] && threshold.AnyBelow() };
  const bool unrepairable[2] = { passRuns[0] && !threshold.AnyAbove(), passRuns[1] && !threshold.AnyBelow() };
  for (std::vector<uint8_t> * removed : { removedBelow, removedAbove })
  {
    if (removed != nullptr)
    {
      removed->assign(entries, 0);
    }
  }
  // An entry's flag goes to its side's array; an undecided side's entries (never removed)
  // write their 0 to the other side's, which is 0 there.
  uint8_t * const flags[2] = { (removedBelow != nullptr ? removedBelow : removedAbove)->data(),
                               (removedAbove != nullptr ? removedAbove : removedBelow)->data() };
  // One part per work unit (each holds a SizeCounter per side), counts added in the order
  // of the parts. Each part is on cache lines of its own: the work units update their
  // counts all along. Nothing in the loop branches on the entry's side, which is as often
  // one as the other.
  struct Counts
  {
    SmallIsoComponentDetail::SizeCounter Sizes;
    SizeValueType                        Components{ 0 };
    SizeValueType                        RemovedComponents{ 0 };
    SizeValueType                        RemovedVoxels{ 0 };
    SizeValueType                        UnrepairableVoxels{ 0 };
  };
  struct alignas(64) Part
  {
    Counts Side[2];
  };
  const SizeValueType parts = team.GetNumberOfParts(entries);
  std::vector<Part>   part(parts);
  const SizeValueType maximum = this->m_EffectiveMaximumComponentSize;
  team.ForEach(parts, [&](SizeValueType p) {
    Part &              mine = part[p];
    const SizeValueType end = WorkTeam::PartBegin(entries, p + 1, parts);
    for (SizeValueType i = WorkTeam::PartBegin(entries, p, parts); i < end; ++i)
    {
      const SizeValueType size = sizeOf(i);
      const unsigned int  side = isAbove(i) ? 1 : 0;
      Counts &            counts = mine.Side[side];
      // Size 0 is no entry (counted by the SizeCounter as nothing).
      counts.Components += size != 0 ? 1 : 0;
      counts.Sizes.Add(size);
      const bool small = (size != 0) & (size <= maximum);
      const bool remove = small & removable[side];
      counts.RemovedComponents += remove ? 1 : 0;
      counts.RemovedVoxels += size & (SizeValueType{ 0 } - static_cast<SizeValueType>(remove));
      counts.UnrepairableVoxels += size & (SizeValueType{ 0 } - static_cast<SizeValueType>(small & unrepairable[side]));
      flags[side][i] = remove ? 1 : 0;
    }
  });
  for (unsigned int side = 0; side < 2; ++side)
  {
    if (!decided[side])
    {
      continue;
    }
    SideStatistics & statistics = this->StatisticsOf(side == 1 ? SideEnum::Above : SideEnum::Below);
    for (SizeValueType p = 1; p < parts; ++p)
    {
      part[0].Side[side].Sizes.Add(part[p].Side[side].Sizes);
    }
    for (const Part & done : part)
    {
      statistics.Components += done.Side[side].Components;
      statistics.RemovedComponents += done.Side[side].RemovedComponents;
      statistics.RemovedVoxels += done.Side[side].RemovedVoxels;
      m_NumberOfUnrepairableVoxels += done.Side[side].UnrepairableVoxels;
    }
    statistics.Histogram = part[0].Side[side].Sizes.Histogram();
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::DecideComponentRemovals(WorkTeam &             team,
                                                                                 std::vector<uint8_t> * removedAbove,
                                                                                 std::vector<uint8_t> * removedBelow)
{
  const RunLabeling & labeling = m_Working->Labeling;
  this->DecideRemovals(
    team,
    labeling.GetComponents().GetNumberOfComponents(),
    [&labeling](SizeValueType component) {
      return labeling.GetComponents().GetComponentSize(static_cast<RunLabeling::ComponentIndexType>(component));
    },
    [&labeling](SizeValueType component) {
      return labeling.GetComponents().IsComponentAbove(static_cast<RunLabeling::ComponentIndexType>(component));
    },
    removedAbove,
    removedBelow);
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::CollectRemovedRuns(WorkTeam &                   team,
                                                                            const std::vector<uint8_t> & removed,
                                                                            SideEnum                     side)
{
  WorkingMemory & working = *m_Working;
  working.Runs.clear();
  if (this->StatisticsOf(side).RemovedComponents == 0)
  {
    return;
  }
  // Every run of a removed component is a candidate (it has at most K voxels).
  working.Labeling.GetComponents().CollectCandidateRuns(removed, team, working.Marks, working.Runs);
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::RepairRuns(WorkTeam &                   team,
                                                                    const std::vector<LineRun> & runs,
                                                                    SideEnum                     side,
                                                                    BelowGrouping *              joinFlipped)
{
  if (runs.empty())
  {
    return;
  }
  OutputImageType * output = this->GetOutput();
  // The values before the pass are the output's. In the first pass (the above pass, or
  // the below pass of Side Below), an input of the same type holds them too, and is likely
  // still in the caches, unlike a streamed output.
  const OutputPixelType * valuesBeforePass = output->GetBufferPointer();
  if constexpr (std::is_same<InputPixelType, OutputPixelType>::value)
  {
    if (side == SideEnum::Above || this->m_Side == SideEnum::Below)
    {
      valuesBeforePass = this->GetInput()->GetBufferPointer();
    }
  }
  SmallIsoComponentDetail::RunRepair<OutputPixelType, ImageDimension> repair(
    team, m_Working->Labeling, runs, output->GetBufferedRegion().GetSize(), m_Working->Values);
  uint8_t * const mask = this->m_GenerateRemovedMask ? this->GetRemovedMask()->GetBufferPointer() : nullptr;
  const uint8_t   maskValue = side == SideEnum::Above ? 1 : 2;
  const SmallIsoComponentDetail::Threshold<OutputPixelType> threshold(this->m_IsoValue);
  // Where the walks read the input, not the output, each value is written as it is found.
  const bool writeAsFound = valuesBeforePass != output->GetBufferPointer() && joinFlipped == nullptr;
  if (writeAsFound)
  {
    repair.ComputeAndWriteValues(
      valuesBeforePass, threshold, side == SideEnum::Above, output->GetBufferPointer(), mask, maskValue);
  }
  else
  {
    repair.ComputeValues(valuesBeforePass, threshold, side == SideEnum::Above, joinFlipped);
  }
  m_ExtraMemory.Hold(m_Working->Labeling.GetMemoryInBytes() + m_Working->GetPassBytes());
  m_NumberOfUnrepairableVoxels += repair.GetNumberOfUnrepairableVoxels();
  m_PhaseClock.End(PhaseEnum::Repair);
  if (!writeAsFound)
  {
    repair.WriteValues(output->GetBufferPointer(), mask, maskValue);
    m_PhaseClock.End(PhaseEnum::Writes);
  }
}

template <typename TInputImage, typename TOutputImage>
bool
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::AbovePassFlips() const
{
  return this->m_Side == SideEnum::Both && m_AboveStatistics.RemovedComponents > 0;
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::EndPhase(ProgressTransformer & progress)
{
  progress.GetProcessObject()->UpdateProgress(1.0f);
  this->StopIfAborted();
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::StopIfAborted() const
{
  if (this->GetAbortGenerateData())
  {
    ProcessAborted abort(__FILE__, __LINE__);
    abort.SetDescription("SmallIsoComponentImageFilter: aborted by the user");
    throw abort;
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "EffectiveMaximumComponentSize: " << this->m_EffectiveMaximumComponentSize << std::endl;
  os << indent << "NumberOfComponents (above, below): " << m_AboveStatistics.Components << ", "
     << m_BelowStatistics.Components << std::endl;
  os << indent << "NumberOfRemovedComponents (above, below): " << m_AboveStatistics.RemovedComponents << ", "
     << m_BelowStatistics.RemovedComponents << std::endl;
  os << indent << "NumberOfRemovedVoxels (above, below): " << m_AboveStatistics.RemovedVoxels << ", "
     << m_BelowStatistics.RemovedVoxels << std::endl;
  os << indent << "NumberOfModifiedVoxels: " << m_NumberOfModifiedVoxels << std::endl;
  os << indent << "NumberOfUnrepairableVoxels: " << m_NumberOfUnrepairableVoxels << std::endl;
  os << indent << "SlabSweepMinimumSize: " << m_SlabSweepMinimumSize << std::endl;
  os << indent << "SlabThickness: " << m_SlabThickness << std::endl;
  os << indent << "SweptSlabThickness: " << m_SweptSlabThickness << std::endl;
  os << indent << "PeakExtraMemoryInBytes: " << this->GetPeakExtraMemoryInBytes() << std::endl;
}
} // end namespace itk

#endif
