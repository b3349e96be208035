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
#ifndef itkSmallIsoComponentRunRepair_hxx
#define itkSmallIsoComponentRunRepair_hxx

#include "itkSmallIsoComponentRunRepair.h"
#include "itkMath.h"
#include "itkSmallIsoComponentBitCount.h"
#include "itkSmallIsoComponentPrefetch.h"
#include "itkSmallIsoComponentRepairMean.h"
#include <algorithm>
#include <cmath>
#include <numeric>
#include <type_traits>

namespace itk
{
namespace SmallIsoComponentDetail
{
template <typename TPixel, unsigned int VDimension>
RunRepair<TPixel, VDimension>::RunRepair(WorkTeam &                   team,
                                         const RunLabeling &          labeling,
                                         const std::vector<LineRun> & runs,
                                         const SizeType &             size)
  : RunRepair(team, labeling, runs, size, m_OwnValues)
{}

template <typename TPixel, unsigned int VDimension>
RunRepair<TPixel, VDimension>::RunRepair(WorkTeam &                         team,
                                         const RunLabeling &                labeling,
                                         const std::vector<LineRun> &       runs,
                                         const SizeType &                   size,
                                         std::vector<std::vector<TPixel>> & values)
  : m_Team(team)
  , m_Table(labeling.GetRunTable())
  , m_Runs(runs)
  , m_Size(size)
  // A few removed runs are repaired by the calling thread alone: handing them to other
  // threads costs more than it saves.
  , m_NumberOfChunks(team.GetNumberOfChunks(runs.size()))
  , m_Values(values)
  , m_Prefetch(labeling.GetNumberOfRuns() >= Tuning::PrefetchMinimumRuns)
{
  m_Stride[0] = 1;
  for (unsigned int a = 1; a < VDimension; ++a)
  {
    m_Stride[a] = m_Stride[a - 1] * static_cast<OffsetValueType>(size[a - 1]);
  }
  m_NumberOfVoxels = static_cast<SizeValueType>(m_Stride[VDimension - 1]) * size[VDimension - 1];
}

template <typename TPixel, unsigned int VDimension>
template <typename TPrefetch, typename TVisit>
void
RunRepair<TPixel, VDimension>::ForEachRunOf(SizeValueType chunk, TPrefetch && prefetch, TVisit && visit) const
{
  // Two stages: the start of a run twice the distance ahead (the run arrays are far larger
  // than the caches), then what prefetch() asks for a run ahead, which reads that start.
  const SizeValueType begin = this->ChunkBegin(chunk);
  const SizeValueType end = this->ChunkBegin(chunk + 1);
  if (!m_Prefetch)
  {
    for (SizeValueType i = begin; i < end; ++i)
    {
      visit(m_Runs[i]);
    }
    return;
  }
  for (SizeValueType i = begin; i < std::min(end, begin + 2 * Tuning::PrefetchRunsAhead); ++i)
  {
    Prefetch(m_Table.Start + m_Runs[i].Run);
  }
  for (SizeValueType i = begin; i < std::min(end, begin + Tuning::PrefetchRunsAhead); ++i)
  {
    prefetch(m_Runs[i]);
  }
  for (SizeValueType i = begin; i < end; ++i)
  {
    if (i + 2 * Tuning::PrefetchRunsAhead < end)
    {
      Prefetch(m_Table.Start + m_Runs[i + 2 * Tuning::PrefetchRunsAhead].Run);
    }
    if (i + Tuning::PrefetchRunsAhead < end)
    {
      prefetch(m_Runs[i + Tuning::PrefetchRunsAhead]);
    }
    visit(m_Runs[i]);
  }
}

template <typename TPixel, unsigned int VDimension>
void
RunRepair<TPixel, VDimension>::ComputeValues(const TPixel *            valuesBeforePass,
                                             const Threshold<TPixel> & threshold,
                                             bool                      removedAreAbove,
                                             BelowGrouping *           joinFlipped)
{
  this->Repair(Pass(valuesBeforePass, threshold, removedAreAbove), joinFlipped);
}

template <typename TPixel, unsigned int VDimension>
void
RunRepair<TPixel, VDimension>::ComputeAndWriteValues(const TPixel *            valuesBeforePass,
                                                     const Threshold<TPixel> & threshold,
                                                     bool                      removedAreAbove,
                                                     TPixel *                  output,
                                                     uint8_t *                 mask,
                                                     uint8_t                   maskValue)
{
  this->Repair(Pass(valuesBeforePass, threshold, removedAreAbove, output, mask, maskValue), nullptr);
}

template <typename TPixel, unsigned int VDimension>
void
RunRepair<TPixel, VDimension>::Repair(const Pass & pass, BelowGrouping * joinFlipped)
{
  // Each chunk's array keeps its memory from the last repair.
  m_Values.resize(m_NumberOfChunks);
  m_Unrepairable.assign(m_NumberOfChunks, 0);
  m_Team.ForEach(m_NumberOfChunks, [&](SizeValueType chunk) {
    // The chunk's array and count are worked on in this thread's own variables, not in
    // the arrays of all chunks, whose neighbouring entries other work units write.
    std::vector<TPixel> chunkValues = std::move(m_Values[chunk]);
    SizeValueType       unrepairable = 0;
    chunkValues.clear();
    if (pass.Output == nullptr)
    {
      chunkValues.reserve(2 * (this->ChunkBegin(chunk + 1) - this->ChunkBegin(chunk)));
    }
    this->ForEachRunOf(
      chunk,
      [&](const LineRun & ahead) { this->PrefetchRun(pass, ahead); },
      [&](const LineRun & removed) { this->RepairRun(pass, removed, chunkValues, unrepairable); });
    m_Values[chunk] = std::move(chunkValues);
    m_Unrepairable[chunk] = unrepairable;
    if (joinFlipped != nullptr)
    {
      joinFlipped->JoinNeighbors(m_Runs.data() + this->ChunkBegin(chunk), m_Runs.data() + this->ChunkBegin(chunk + 1));
    }
  });
}

template <typename TPixel, unsigned int VDimension>
SMALLISO_ALWAYS_INLINE void
RunRepair<TPixel, VDimension>::PrefetchRun(const Pass & pass, const LineRun & ahead) const
{
  const SizeValueType first = this->FirstVoxel(ahead);
  Prefetch(pass.ValuesBeforePass + first);
  if (pass.Output != nullptr)
  {
    Prefetch(pass.Output + first);
    if (pass.Mask != nullptr)
    {
      Prefetch(pass.Mask + first);
    }
  }
  for (unsigned int a = 1; a < VDimension; ++a)
  {
    const auto step = static_cast<SizeValueType>(m_Stride[a]);
    if (first >= step)
    {
      Prefetch(pass.ValuesBeforePass + first - step);
    }
    if (first + step < m_NumberOfVoxels)
    {
      Prefetch(pass.ValuesBeforePass + first + step);
    }
  }
}

template <typename TPixel, unsigned int VDimension>
SMALLISO_ALWAYS_INLINE void
RunRepair<TPixel, VDimension>::RepairRun(const Pass &          pass,
                                         const LineRun &       removed,
                                         std::vector<TPixel> & values,
                                         SizeValueType &       unrepairable) const
{
  const auto sameSide = [&](TPixel v) { return pass.IsoValue.IsAbove(v) == pass.RemovedAreAbove; };
  // The run's coordinates along axes 1..N-1.
  SizeValueType coordinates[VDimension];
  SizeValueType rest = removed.Line;
  for (unsigned int a = 1; a < VDimension; ++a)
  {
    coordinates[a] = rest % m_Size[a];
    rest /= m_Size[a];
  }
  const SizeValueType length = m_Size[0];
  const TPixel *      line = pass.ValuesBeforePass + removed.Line * length;
  TPixel * const      outputLine = pass.Output != nullptr ? pass.Output + removed.Line * length : nullptr;
  uint8_t * const     maskLine = pass.Mask != nullptr ? pass.Mask + removed.Line * length : nullptr;
  RepairLineRun<TPixel>(
    m_Table.Start[removed.Run],
    m_Table.End(removed.Run, removed.Line),
    length,
    [&](SizeValueType x, TPixel & value) {
      value = line[x];
      return sameSide(value);
    },
    [&](SizeValueType x, RepairMean & mean) {
      const TPixel * voxel = line + x;
      for (unsigned int a = 1; a < VDimension; ++a)
      {
        const OffsetValueType step = m_Stride[a];
        AddFirstOtherSideAlongAxis<TPixel>(
          coordinates[a],
          m_Size[a],
          [&](OffsetValueType offset, TPixel & value) {
            value = voxel[offset * step];
            return sameSide(value);
          },
          mean);
      }
    },
    [&](SizeValueType x, const RepairMean & mean) {
      const bool   repaired = mean.GetCount() > 0;
      const TPixel value = repaired ? mean.Get<TPixel>() : pass.Fallback;
      unrepairable += repaired ? 0 : 1;
      if (outputLine != nullptr)
      {
        outputLine[x] = value;
        if (maskLine != nullptr)
        {
          maskLine[x] = pass.MaskValue;
        }
      }
      else
      {
        values.push_back(value);
      }
    });
}

template <typename TPixel, unsigned int VDimension>
void
RunRepair<TPixel, VDimension>::WriteValues(TPixel * output, uint8_t * mask, uint8_t maskValue) const
{
  m_Team.ForEach(m_NumberOfChunks, [&](SizeValueType chunk) {
    auto value = m_Values[chunk].cbegin();
    this->ForEachRunOf(
      chunk,
      [&](const LineRun & ahead) {
        Prefetch(output + this->FirstVoxel(ahead));
        if (mask != nullptr)
        {
          Prefetch(mask + this->FirstVoxel(ahead));
        }
      },
      [&](const LineRun & removed) {
        const SizeValueType first = this->FirstVoxel(removed);
        const SizeValueType count = m_Table.End(removed.Run, removed.Line) - m_Table.Start[removed.Run];
        // Runs are a few voxels: plain loops, no library calls.
        for (SizeValueType i = 0; i < count; ++i)
        {
          output[first + i] = value[i];
        }
        if (mask != nullptr)
        {
          for (SizeValueType i = 0; i < count; ++i)
          {
            mask[first + i] = maskValue;
          }
        }
        value += count;
      });
  });
}

template <typename TPixel, unsigned int VDimension>
SizeValueType
RunRepair<TPixel, VDimension>::GetNumberOfUnrepairableVoxels() const
{
  return std::accumulate(m_Unrepairable.begin(), m_Unrepairable.end(), SizeValueType{ 0 });
}

template <typename TPixel, unsigned int VDimension>
SizeValueType
RunRepair<TPixel, VDimension>::GetValueBytes() const
{
  return GetValueBytes(m_Values);
}

template <typename TPixel, unsigned int VDimension>
SizeValueType
RunRepair<TPixel, VDimension>::GetValueBytes(const std::vector<std::vector<TPixel>> & values)
{
  SizeValueType bytes = 0;
  for (const auto & chunkValues : values)
  {
    bytes += chunkValues.capacity() * sizeof(TPixel);
  }
  return bytes;
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
