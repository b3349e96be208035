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
#ifndef itkSmallIsoComponentStreamingSweep_hxx
#define itkSmallIsoComponentStreamingSweep_hxx

#include "itkSmallIsoComponentStreamingSweep.h"
#include "itkSmallIsoComponentRepairMean.h"
#include "itkSmallIsoComponentRunSummary.h"
#include "itkMath.h"
#include <algorithm>
#include <array>
#include <cmath>

namespace itk
{
namespace SmallIsoComponentDetail
{
template <typename TPixel>
struct StreamingSweep<TPixel>::Slab
{
  struct Track
  {
    State                  AbovePass{ State::Open };
    State                  BelowPass{ State::Open };
    BlockSummary::NodeType Node{ BlockSummary::NoNode };
    uint8_t                Repaired{ 0 }; // 1: above pass written, 2: below pass written
  };
  struct Repair
  {
    uint32_t Offset; // in its plane
    uint8_t  Mask;   // 1 above pass, 2 below pass, plus 4 or 8 for the fallback value
    TPixel   Value;
  };

  uint64_t            Begin{ 0 };
  uint64_t            End{ 0 };
  std::vector<TPixel> Values;
  RunLabeling         Labeling;
  std::vector<Track>  Tracks;
  /** The runs of each component of at most K voxels: CandidateBegin[c] .. CandidateBegin[c + 1]. */
  std::vector<SizeValueType>        CandidateBegin;
  std::vector<RunLabeling::LineRun> Candidates;
  /** Components not decided yet, or decided but not written yet. */
  std::vector<SizeValueType> Unsettled;
  /** Per plane of the slab, the repaired voxels in the order they were written. */
  std::vector<std::vector<Repair>> Repairs;
  /** The slab's own summary, from its labelling until it is merged. */
  std::unique_ptr<BlockSummary> Summary;

  /** Empties the slab for its next planes; the arrays keep their memory. */
  void
  Clear()
  {
    Begin = 0;
    End = 0;
    Values.clear();
    Tracks.clear();
    CandidateBegin.clear();
    Candidates.clear();
    Unsettled.clear();
    Repairs.clear();
    Summary.reset();
  }

  SizeValueType
  GetMemoryInBytes() const
  {
    SizeValueType bytes = Values.capacity() * sizeof(TPixel) + Labeling.GetMemoryInBytes() +
                          Tracks.capacity() * sizeof(Track) + CandidateBegin.capacity() * sizeof(SizeValueType) +
                          Candidates.capacity() * sizeof(RunLabeling::LineRun) +
                          Unsettled.capacity() * sizeof(SizeValueType) + (Summary ? Summary->GetMemoryInBytes() : 0);
    for (const auto & plane : Repairs)
    {
      bytes += plane.capacity() * sizeof(Repair);
    }
    return bytes;
  }
};

template <typename TPixel>
StreamingSweep<TPixel>::StreamingSweep(const IndexType &            size,
                                       double                       isoValue,
                                       uint64_t                     maximumComponentSize,
                                       SmallIsoComponentEnums::Side side,
                                       bool                         fullyConnected,
                                       uint64_t                     slabPlanes,
                                       bool                         withMask,
                                       MultiThreaderBase *          threader,
                                       unsigned int                 workUnits,
                                       PlaneCallback                emit)
  : m_Size(size)
  , m_PlaneVoxels(size[0] * size[1])
  , m_Threshold(isoValue)
  , m_Encoder(isoValue)
  , m_SlabPlanes(std::max<uint64_t>(1, slabPlanes))
  , m_WithMask(withMask)
  , m_Threader(threader)
  , m_WorkUnits(std::max(1u, workUnits))
  , m_Emit(std::move(emit))
{
  m_Rules.MaximumComponentSize = maximumComponentSize;
  m_Rules.Side = side;
  m_Rules.FullyConnected = fullyConnected;
  m_Rules.AnyAbove = m_Threshold.AnyAbove();
  m_Rules.AnyBelow = m_Threshold.AnyBelow();
  if (m_PlaneVoxels == 0 || size[2] == 0)
  {
    itkGenericExceptionMacro("StreamingSweep: the image is empty (" << size[0] << " x " << size[1] << " x " << size[2]
                                                                    << " voxels)");
  }
  m_OutputPlane.resize(m_PlaneVoxels);
  if (m_WithMask)
  {
    m_MaskPlane.resize(m_PlaneVoxels);
  }
}

template <typename TPixel>
StreamingSweep<TPixel>::~StreamingSweep() = default;

template <typename TPixel>
uint64_t
StreamingSweep<TPixel>::WindowPlanes(uint64_t maximumComponentSize, uint64_t slabPlanes, unsigned int workUnits)
{
  // With two work units or more one slab more is held: labelled while the one before is merged.
  const uint64_t slabs = workUnits > 1 ? 3 : 2;
  return 2 * maximumComponentSize + 4 + slabs * std::max<uint64_t>(1, slabPlanes);
}

template <typename TPixel>
void
StreamingSweep<TPixel>::Push(const TPixel * values, uint64_t planes)
{
  if (m_PlanesIn + planes > m_Size[2])
  {
    itkGenericExceptionMacro("StreamingSweep: " << m_PlanesIn + planes << " planes given to an image of " << m_Size[2]
                                                << " planes");
  }
  for (uint64_t done = 0; done < planes;)
  {
    const uint64_t room = m_SlabPlanes - m_Pending.size() / m_PlaneVoxels;
    const uint64_t take = std::min(room, planes - done);
    m_Pending.insert(m_Pending.end(), values + done * m_PlaneVoxels, values + (done + take) * m_PlaneVoxels);
    done += take;
    m_PlanesIn += take;
    if (m_Pending.size() == m_SlabPlanes * m_PlaneVoxels)
    {
      this->ProcessSlab();
    }
  }
}

template <typename TPixel>
void
StreamingSweep<TPixel>::Finish()
{
  if (m_PlanesIn != m_Size[2])
  {
    itkGenericExceptionMacro("StreamingSweep: the image has " << m_Size[2] << " planes but " << m_PlanesIn
                                                              << " were given");
  }
  if (!m_Pending.empty())
  {
    this->ProcessSlab();
  }
  if (m_Labelled)
  {
    m_MergePeakBytes = 0;
    m_MergePeakPlanes = 0;
    this->MergeSlab(std::move(m_Labelled));
  }
  if (m_NextPlaneOut != m_Size[2])
  {
    itkGenericExceptionMacro("StreamingSweep: only " << m_NextPlaneOut << " of " << m_Size[2]
                                                     << " planes were settled at the end");
  }
}

template <typename TPixel>
void
StreamingSweep<TPixel>::ProcessSlab()
{
  // A slab dropped from the window is taken again, with its arrays: fresh ones would cost a
  // page fault every few kilobytes.
  std::unique_ptr<Slab> slab;
  if (m_SpareSlabs.empty())
  {
    slab = std::make_unique<Slab>();
  }
  else
  {
    slab = std::move(m_SpareSlabs.back());
    m_SpareSlabs.pop_back();
    slab->Clear();
  }
  Slab &         s = *slab;
  const uint64_t planes = m_Pending.size() / m_PlaneVoxels;
  s.Begin = m_PlanesIn - planes;
  s.End = m_PlanesIn;
  // The pending planes become the slab's; the slab's old buffer takes the next ones.
  s.Values.swap(m_Pending);
  m_Pending.clear();
  m_Pending.reserve(m_SlabPlanes * m_PlaneVoxels);

  m_MergePeakBytes = 0;
  m_MergePeakPlanes = 0;
  if (m_WorkUnits == 1)
  {
    this->LabelSlab(s, 1);
    this->MergeSlab(std::move(slab));
    return;
  }
  // With two work units or more the slab before it is merged (on this thread, which gives out the
  // planes) while this one is labelled on the background thread. The two share no data: the
  // merge reads and writes the window, the summary and the slab before; the labelling this slab
  // alone.
  if (m_Labelled)
  {
    m_Labeller.Start([this, &s] { this->LabelSlab(s, m_WorkUnits - 1); });
    try
    {
      this->MergeSlab(std::move(m_Labelled));
    }
    catch (...)
    {
      m_Labeller.WaitQuietly();
      throw;
    }
    m_Labeller.Wait();
  }
  else
  {
    this->LabelSlab(s, m_WorkUnits);
  }
  // Held at once: what the merge held, and this slab (labelled meanwhile).
  const HeldMemory held = this->GetHeldMemory();
  m_MergePeakBytes = std::max(m_MergePeakBytes, held.Bytes);
  m_MergePeakPlanes = std::max(m_MergePeakPlanes, held.Planes);
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, m_MergePeakBytes + s.GetMemoryInBytes());
  m_PeakWindowPlanes = std::max(m_PeakWindowPlanes, m_MergePeakPlanes + (s.End - s.Begin));
  m_Labelled = std::move(slab);
}

template <typename TPixel>
void
StreamingSweep<TPixel>::LabelSlab(Slab & s, unsigned int workUnits) const
{
  // Label the slab on its own.
  const uint64_t  planes = s.End - s.Begin;
  const IndexType extent{ m_Size[0], m_Size[1], planes };
  LabelBox(s.Values.data(),
           extent,
           m_Encoder,
           m_Rules.FullyConnected,
           m_Rules.MaximumComponentSize,
           m_Threader,
           workUnits,
           s.Labeling);
  const SizeValueType  components = s.Labeling.GetComponents().GetNumberOfComponents();
  std::vector<uint8_t> small(components, 0);
  for (SizeValueType c = 0; c < components; ++c)
  {
    small[c] = s.Labeling.GetComponents().GetComponentSize(static_cast<RunLabeling::ComponentIndexType>(c)) <=
               m_Rules.MaximumComponentSize;
  }
  // The runs of the small components, grouped by component (in run order within each).
  {
    const auto runs = s.Labeling.GetComponents().CollectCandidateRuns(small);
    s.CandidateBegin.assign(components + 1, 0);
    for (const auto & run : runs)
    {
      ++s.CandidateBegin[s.Labeling.GetRunTable().Component[run.Run] + 1];
    }
    for (SizeValueType c = 0; c < components; ++c)
    {
      s.CandidateBegin[c + 1] += s.CandidateBegin[c];
    }
    std::vector<SizeValueType> next(s.CandidateBegin.begin(), s.CandidateBegin.end() - 1);
    s.Candidates.resize(runs.size());
    for (const auto & run : runs)
    {
      s.Candidates[next[s.Labeling.GetRunTable().Component[run.Run]]++] = run;
    }
  }
  s.Repairs.resize(planes);
  s.Tracks.resize(components);
  s.Summary = std::make_unique<BlockSummary>(SummarizeLabeling(s.Labeling, extent, m_Size, { 0, 0, s.Begin }, m_Rules));
}

template <typename TPixel>
void
StreamingSweep<TPixel>::MergeSlab(std::unique_ptr<Slab> slab)
{
  Slab &              s = *slab;
  const SizeValueType components = s.Tracks.size();
  // The slab's summary, merged with everything before it as it is (the merge decides what the
  // slab alone would decide too); the first slab's settled alone.
  std::unique_ptr<BlockSummary> summary = std::move(s.Summary);
  if (m_Summary)
  {
    std::vector<Resolution> lower;
    std::vector<Resolution> upper;
    auto merged = std::make_unique<BlockSummary>(BlockSummary::Merge(*m_Summary, *summary, &lower, &upper));
    summary.reset();
    for (auto & older : m_Window)
    {
      for (const SizeValueType c : older->Unsettled)
      {
        if (older->Tracks[c].Node != BlockSummary::NoNode)
        {
          this->Follow(*older, c, lower[older->Tracks[c].Node]);
        }
      }
    }
    for (SizeValueType c = 0; c < components; ++c)
    {
      this->Follow(s, c, upper[c]);
    }
    m_Summary = std::move(merged);
  }
  else
  {
    std::vector<Resolution> settled;
    summary->Settle(&settled);
    for (SizeValueType c = 0; c < components; ++c)
    {
      this->Follow(s, c, settled[c]);
    }
    m_Summary = std::move(summary);
  }
  for (SizeValueType c = 0; c < components; ++c)
  {
    const auto & track = s.Tracks[c];
    const bool   decided = track.AbovePass != State::Open && track.BelowPass != State::Open;
    const bool   removed = track.AbovePass == State::Removed || track.BelowPass == State::Removed;
    if (!decided || removed)
    {
      s.Unsettled.push_back(c);
    }
  }
  m_Window.push_back(std::move(slab));
  this->UpdateMemory();
  this->RepairDecided();
  this->EmitReadyPlanes();
  this->UpdateMemory();
}

template <typename TPixel>
void
StreamingSweep<TPixel>::Follow(Slab & slab, SizeValueType component, const Resolution & resolution)
{
  auto & track = slab.Tracks[component];
  if (track.AbovePass == State::Open)
  {
    track.AbovePass = resolution.AbovePass;
  }
  track.BelowPass = resolution.BelowPass;
  track.Node = resolution.Node;
}

template <typename TPixel>
void
StreamingSweep<TPixel>::RepairDecided()
{
  // The above pass first: the below pass reads which voxels it removed.
  for (const bool abovePass : { true, false })
  {
    for (auto & slab : m_Window)
    {
      for (const SizeValueType c : slab->Unsettled)
      {
        auto &        track = slab->Tracks[c];
        const uint8_t bit = abovePass ? 1 : 2;
        const State   state = abovePass ? track.AbovePass : track.BelowPass;
        if (state == State::Removed && (track.Repaired & bit) == 0)
        {
          this->RepairComponent(*slab, c, abovePass);
          track.Repaired |= bit;
        }
      }
    }
  }
  for (auto & slab : m_Window)
  {
    auto & unsettled = slab->Unsettled;
    unsettled.erase(std::remove_if(unsettled.begin(),
                                   unsettled.end(),
                                   [&](SizeValueType c) {
                                     const auto & track = slab->Tracks[c];
                                     return track.AbovePass != State::Open && track.BelowPass != State::Open;
                                   }),
                    unsettled.end());
  }
}

template <typename TPixel>
auto
StreamingSweep<TPixel>::SlabOf(uint64_t z) -> Slab &
{
  // The window's slabs are consecutive, each of SlabPlanes planes but the image's last.
  if (!m_Window.empty() && z >= m_Window.front()->Begin)
  {
    const uint64_t index = (z - m_Window.front()->Begin) / m_SlabPlanes;
    if (index < m_Window.size() && z < m_Window[index]->End)
    {
      return *m_Window[index];
    }
  }
  itkGenericExceptionMacro("StreamingSweep: plane " << z << " is not in the window");
}

template <typename TPixel>
bool
StreamingSweep<TPixel>::IsBelowAfterAbovePass(uint64_t x, uint64_t y, uint64_t z, TPixel & value)
{
  Slab & slab = this->SlabOf(z);
  value = slab.Values[(z - slab.Begin) * m_PlaneVoxels + y * m_Size[0] + x];
  if (!m_Threshold.IsAbove(value))
  {
    return true;
  }
  // An above voxel is below after the above pass when its component was removed.
  const RunLabeling::RunTable table = slab.Labeling.GetRunTable();
  const SizeValueType         line = y + m_Size[1] * (z - slab.Begin);
  return slab.Tracks[table.Component[table.RunHolding(line, x)]].AbovePass == State::Removed;
}

template <typename TPixel>
void
StreamingSweep<TPixel>::RepairComponent(Slab & slab, SizeValueType component, bool abovePass)
{
  const TPixel fallback = abovePass ? m_Threshold.HighestBelow() : m_Threshold.LowestAbove();
  // Walks cross the voxels of the component's side as its pass sees it (the above pass: the
  // input; the below pass: the input after the above pass) and stop at the first other one.
  const auto sameSide = [&](uint64_t x, uint64_t y, uint64_t z, TPixel & value) {
    if (abovePass)
    {
      const Slab & holder = this->SlabOf(z);
      value = holder.Values[(z - holder.Begin) * m_PlaneVoxels + y * m_Size[0] + x];
      return m_Threshold.IsAbove(value);
    }
    return this->IsBelowAfterAbovePass(x, y, z, value);
  };
  const RunLabeling::RunTable table = slab.Labeling.GetRunTable();
  for (SizeValueType i = slab.CandidateBegin[component]; i < slab.CandidateBegin[component + 1]; ++i)
  {
    const auto &                  run = slab.Candidates[i];
    const SizeValueType           y = run.Line % m_Size[1];
    const SizeValueType           zInSlab = run.Line / m_Size[1];
    const uint64_t                z = slab.Begin + zInSlab;
    const std::array<uint64_t, 2> others{ y, z };
    RepairLineRun<TPixel>(
      table.Start[run.Run],
      table.End(run.Run, run.Line),
      m_Size[0],
      [&](SizeValueType x, TPixel & value) { return sameSide(x, y, z, value); },
      [&](SizeValueType x, RepairMean & mean) {
        for (unsigned int axis = 1; axis < 3; ++axis)
        {
          const uint64_t at = others[axis - 1];
          AddFirstOtherSideAlongAxis<TPixel>(
            at,
            m_Size[axis],
            [&](OffsetValueType offset, TPixel & value) {
              std::array<uint64_t, 3> p{ x, y, z };
              p[axis] = at + static_cast<uint64_t>(offset);
              return sameSide(p[0], p[1], p[2], value);
            },
            mean);
        }
      },
      [&](SizeValueType x, const RepairMean & mean) {
        TPixel  repaired = fallback;
        uint8_t maskValue = abovePass ? 1 : 2;
        if (mean.GetCount() > 0)
        {
          repaired = mean.Get<TPixel>();
        }
        else
        {
          ++m_FallbackVoxels;
          maskValue |= abovePass ? 4 : 8;
        }
        slab.Repairs[zInSlab].push_back({ static_cast<uint32_t>(y * m_Size[0] + x), maskValue, repaired });
      });
  }
}

template <typename TPixel>
void
StreamingSweep<TPixel>::EmitReadyPlanes()
{
  // Planes up to the first one that holds a component not decided (or not written) yet.
  uint64_t ready = m_Window.empty() ? m_NextPlaneOut : m_Window.back()->End;
  for (const auto & slab : m_Window)
  {
    for (const SizeValueType c : slab->Unsettled)
    {
      const auto & first = slab->Candidates[slab->CandidateBegin[c]];
      ready = std::min<uint64_t>(ready, slab->Begin + first.Line / m_Size[1]);
    }
  }
  for (; m_NextPlaneOut < ready; ++m_NextPlaneOut)
  {
    Slab &         slab = this->SlabOf(m_NextPlaneOut);
    const uint64_t zInSlab = m_NextPlaneOut - slab.Begin;
    std::copy(slab.Values.begin() + zInSlab * m_PlaneVoxels,
              slab.Values.begin() + (zInSlab + 1) * m_PlaneVoxels,
              m_OutputPlane.begin());
    if (m_WithMask)
    {
      std::fill(m_MaskPlane.begin(), m_MaskPlane.end(), 0);
    }
    for (const auto & repair : slab.Repairs[zInSlab])
    {
      m_OutputPlane[repair.Offset] = repair.Value;
      if (m_WithMask)
      {
        // The later pass's value, the fallback marks of both.
        m_MaskPlane[repair.Offset] = static_cast<uint8_t>((m_MaskPlane[repair.Offset] & 12) | repair.Mask);
      }
    }
    std::vector<typename Slab::Repair>().swap(slab.Repairs[zInSlab]);
    m_Emit(m_NextPlaneOut, m_OutputPlane.data(), m_WithMask ? m_MaskPlane.data() : nullptr);
  }
  // A slab is dropped once the plane after it is out: the walks of the components in that
  // plane may read the slab's last plane.
  while (!m_Window.empty() && (m_Window.front()->End < m_NextPlaneOut || m_NextPlaneOut == m_Size[2]))
  {
    if (m_NextPlaneOut < m_Size[2] && m_SpareSlabs.size() < Tuning::MaximumSpareSlabs)
    {
      m_SpareSlabs.push_back(std::move(m_Window.front()));
    }
    m_Window.pop_front();
  }
}

template <typename TPixel>
auto
StreamingSweep<TPixel>::GetHeldMemory() const -> HeldMemory
{
  HeldMemory held;
  held.Bytes = m_Pending.capacity() * sizeof(TPixel) + m_OutputPlane.capacity() * sizeof(TPixel) +
               m_MaskPlane.capacity() + (m_Summary ? m_Summary->GetMemoryInBytes() : 0);
  held.Planes = m_Pending.size() / m_PlaneVoxels;
  for (const auto & slab : m_Window)
  {
    held.Bytes += slab->GetMemoryInBytes();
    held.Planes += slab->End - slab->Begin;
  }
  for (const auto & slab : m_SpareSlabs)
  {
    held.Bytes += slab->GetMemoryInBytes();
  }
  if (m_Labelled)
  {
    held.Bytes += m_Labelled->GetMemoryInBytes();
    held.Planes += m_Labelled->End - m_Labelled->Begin;
  }
  return held;
}

template <typename TPixel>
void
StreamingSweep<TPixel>::UpdateMemory()
{
  // While a merge runs the next slab may be in labelling; ProcessSlab() adds it.
  const HeldMemory held = this->GetHeldMemory();
  m_MergePeakBytes = std::max(m_MergePeakBytes, held.Bytes);
  m_MergePeakPlanes = std::max(m_MergePeakPlanes, held.Planes);
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, held.Bytes);
  m_PeakWindowPlanes = std::max(m_PeakWindowPlanes, held.Planes);
}

template <typename TPixel>
void
FilterBoxPart(const TPixel *                  values,
              const BlockSummary::IndexType & extent,
              const BlockSummary::IndexType & cropBegin,
              const BlockSummary::IndexType & cropEnd,
              double                          isoValue,
              uint64_t                        maximumComponentSize,
              SmallIsoComponentEnums::Side    side,
              bool                            fullyConnected,
              MultiThreaderBase *             threader,
              unsigned int                    workUnits,
              TPixel *                        output,
              uint8_t *                       mask)
{
  for (unsigned int a = 0; a < 3; ++a)
  {
    if (!(cropBegin[a] < cropEnd[a] && cropEnd[a] <= extent[a]))
    {
      itkGenericExceptionMacro("FilterBoxPart: the part [" << cropBegin[a] << ", " << cropEnd[a] << ") along axis " << a
                                                           << " is empty or outside the box of " << extent[a]
                                                           << " voxels");
    }
  }
  const uint64_t cropWidth = cropEnd[0] - cropBegin[0];
  const uint64_t cropHeight = cropEnd[1] - cropBegin[1];
  // The planes of the part are kept; the sweep needs not hold more than a window.
  StreamingSweep<TPixel> sweep(extent,
                               isoValue,
                               maximumComponentSize,
                               side,
                               fullyConnected,
                               extent[2],
                               mask != nullptr,
                               threader,
                               workUnits,
                               [&](uint64_t plane, const TPixel * planeValues, const uint8_t * planeMask) {
                                 if (plane < cropBegin[2] || plane >= cropEnd[2])
                                 {
                                   return;
                                 }
                                 for (uint64_t y = cropBegin[1]; y < cropEnd[1]; ++y)
                                 {
                                   const uint64_t from = y * extent[0] + cropBegin[0];
                                   const uint64_t to =
                                     ((plane - cropBegin[2]) * cropHeight + (y - cropBegin[1])) * cropWidth;
                                   std::copy(planeValues + from, planeValues + from + cropWidth, output + to);
                                   if (mask != nullptr)
                                   {
                                     std::copy(planeMask + from, planeMask + from + cropWidth, mask + to);
                                   }
                                 }
                               });
  sweep.Push(values, extent[2]);
  sweep.Finish();
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
