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
#include "sicStreamedFilter.h"
#include "sicPlatform.h"
#include "sicScalarImageDispatch.h"
#include "sicToolError.h"

#include "itkMultiThreaderBase.h"
#include "itkSmallIsoComponentStreamingSweep.h"
#include "itkSmallIsoComponentThreshold.h"
#include "itkSmallIsoComponentUnionFind.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace sic
{
namespace
{
using Clock = std::chrono::steady_clock;

double
Seconds(Clock::duration duration)
{
  return std::chrono::duration<double>(duration).count();
}

itk::SmallIsoComponentEnums::Side
SideOf(const std::string & side)
{
  using Side = itk::SmallIsoComponentEnums::Side;
  return side == "above" ? Side::Above : (side == "below" ? Side::Below : Side::Both);
}

void
Fill(SideReport & report, const itk::SmallIsoComponentDetail::SideTally & tally)
{
  report.Components = tally.GetComponents();
  report.RemovedComponents = tally.GetRemovedComponents();
  report.RemovedVoxels = tally.GetRemovedVoxels();
  report.Histogram = tally.GetHistogram();
}

itk::MultiThreaderBase::Pointer
NewThreader(const FilterSettings & settings)
{
  auto threader = itk::MultiThreaderBase::New();
  if (settings.Threads > 0)
  {
    threader->SetMaximumNumberOfThreads(static_cast<unsigned int>(settings.Threads));
    threader->SetNumberOfWorkUnits(static_cast<unsigned int>(settings.Threads));
  }
  return threader;
}

template <typename TPixel>
void
RunStreamed(PlaneReader &                       input,
            const FilterSettings &              settings,
            const StreamedOutputs &             outputs,
            std::uint64_t                       maximumSize,
            std::uint64_t                       slabPlanes,
            std::uint64_t                       memoryLimit,
            const std::function<void(double)> & progress,
            FilterReport &                      report)
{
  const VolumeGeometry & geometry = input.GetGeometry();
  PlaneWriter            image(outputs.Image, settings.Output, "output image", geometry, settings.Compress);
  VolumeGeometry         maskGeometry = geometry;
  maskGeometry.ComponentType = itk::IOComponentEnum::UCHAR;
  std::unique_ptr<PlaneWriter> mask;
  if (!outputs.RemovedMask.empty())
  {
    mask = std::make_unique<PlaneWriter>(
      outputs.RemovedMask, settings.RemovedMask, "removed-voxel mask", maskGeometry, settings.Compress);
  }
  // The image as a box whose planes are along its last axis (a 2-D image's are its lines).
  const itk::SmallIsoComponentDetail::BlockSummary::IndexType box =
    geometry.Dimension == 3
      ? itk::SmallIsoComponentDetail::BlockSummary::IndexType{ geometry.Size[0], geometry.Size[1], geometry.Size[2] }
      : itk::SmallIsoComponentDetail::BlockSummary::IndexType{ geometry.Size[0], 1, geometry.Size[1] };
  auto               threader = NewThreader(settings);
  const unsigned int workUnits = threader->GetNumberOfWorkUnits();

  Clock::duration                                      writing{};
  std::vector<uint8_t>                                 maskPlane(geometry.PlaneVoxels());
  const uint64_t                                       planes = geometry.Planes();
  itk::SmallIsoComponentDetail::StreamingSweep<TPixel> sweep(
    box,
    settings.IsoValue,
    maximumSize,
    SideOf(settings.Side),
    settings.FullyConnected,
    slabPlanes,
    mask != nullptr,
    threader,
    workUnits,
    [&](uint64_t plane, const TPixel * values, const uint8_t * planeMask) {
      const auto start = Clock::now();
      image.Write(values, 1);
      if (mask)
      {
        itk::SmallIsoComponentDetail::CopyRemovedMask(planeMask, maskPlane.size(), maskPlane.data());
        mask->Write(maskPlane.data(), 1);
      }
      writing += Clock::now() - start;
      progress(static_cast<double>(plane + 1) / static_cast<double>(planes));
    });

  const auto          start = Clock::now();
  Clock::duration     reading{};
  std::vector<TPixel> slab(slabPlanes * geometry.PlaneVoxels());
  for (uint64_t done = 0; done < planes;)
  {
    const uint64_t count = std::min(slabPlanes, planes - done);
    const auto     readStart = Clock::now();
    input.Read(slab.data(), count);
    reading += Clock::now() - readStart;
    sweep.Push(slab.data(), count);
    done += count;
    const std::uint64_t peak = PeakResidentBytes();
    if (memoryLimit > 0 && peak > memoryLimit && done < planes)
    {
      throw MemoryLimitPassed{ done, peak };
    }
  }
  input.Finish();
  sweep.Finish();
  const auto finishStart = Clock::now();
  image.Finish();
  if (mask)
  {
    mask->Finish();
  }
  writing += Clock::now() - finishStart;
  const double total = Seconds(Clock::now() - start);

  const auto & tally = sweep.GetTally();
  report.EffectiveMaximumSize = maximumSize;
  report.WorkUnits = workUnits;
  Fill(report.Above, tally.Above);
  Fill(report.Below, tally.Below);
  report.ModifiedVoxels = tally.ModifiedVoxels;
  report.UnrepairableVoxels = tally.UnrepairableVoxels + sweep.GetNumberOfFallbackVoxels();
  report.PeakExtraBytes = sweep.GetPeakMemoryInBytes();
  report.Streaming = true;
  report.SlabPlanes = slabPlanes;
  report.ReadSeconds = Seconds(reading);
  report.WriteSeconds = Seconds(writing);
  report.FilterSeconds = total - report.ReadSeconds - report.WriteSeconds;
}
} // namespace

std::uint64_t
ParseByteCount(const std::string & text, const std::string & option)
{
  const auto bad = [&] {
    throw ToolError(option + " '" + text +
                    "' is not a byte count; expected a whole number with an optional suffix "
                    "K, M, G or T (powers of 1024), e.g. 512M or 8G");
  };
  std::size_t digits = 0;
  while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits])))
  {
    ++digits;
  }
  if (digits == 0 || digits > 15)
  {
    bad();
  }
  const uint64_t number = std::stoull(text.substr(0, digits));
  std::string    suffix = text.substr(digits);
  for (char & c : suffix)
  {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  if (suffix.size() == 2 && suffix[1] == 'B')
  {
    suffix.pop_back();
  }
  unsigned int shift = 0;
  if (suffix == "K")
  {
    shift = 10;
  }
  else if (suffix == "M")
  {
    shift = 20;
  }
  else if (suffix == "G")
  {
    shift = 30;
  }
  else if (suffix == "T")
  {
    shift = 40;
  }
  else if (!suffix.empty() && suffix != "B")
  {
    bad();
  }
  if (number == 0 || number > (std::numeric_limits<uint64_t>::max() >> shift))
  {
    bad();
  }
  return number << shift;
}

std::string
MemoryLimitText(const FilterSettings & settings, std::uint64_t limit)
{
  return (settings.MemoryLimit > 0 ? "--memory-limit "
                                   : "the memory the tool may use (three quarters of the available memory), ") +
         std::to_string(limit >> 20) + " MiB";
}

unsigned int
StreamingWorkUnits(const FilterSettings & settings)
{
  return NewThreader(settings)->GetNumberOfWorkUnits();
}

namespace
{
/** What a scanline run takes in the window beside its component: its run entry, its label in the slab, its
 * entries in the summaries' face layers, with the allocator's slack. Measured on stripes (a run at every voxel,
 * a few long components). */
constexpr std::uint64_t BytesPerRun = 16;

/** What a component takes in the window: its fate, its candidate and summary entries. With BytesPerRun and
 * BytesPerRepairedVoxel, measured on the checkerboard (every voxel a run and a small component of its own). */
constexpr std::uint64_t BytesPerComponent = 80;

/** What a voxel of a small component takes while it is repaired. Measured on stripes that are all small
 * components. */
constexpr std::uint64_t BytesPerRepairedVoxel = 32;

/** What a streamed run adds to the process beside its window: its threads' stacks, the readers' and writers'
 * buffers (zlib's included). */
constexpr std::uint64_t RunOverheadBytes = std::uint64_t{ 8 } << 20;

/** A scanline run of one side of the isovalue: its voxels [Begin, End) on its line, its entry in the plane's
 * union-find. */
struct LineRun
{
  std::uint64_t Begin;
  std::uint64_t End;
  std::uint64_t Index;
  bool          Above;
};

/** The groups of a plane's runs: each run's parent, and the voxels of the runs below each root. */
struct PlaneComponents
{
  std::vector<std::uint64_t> Parent;
  std::vector<std::uint64_t> Voxels;
};

/** The bytes a plane's labelling takes: its runs; its components of runs (runs of a side joined across
 * consecutive lines), which bound the components of the volume that meet the plane; and the voxels of those of
 * at most \a maximumSize voxels, the only ones that can be of a small component. */
template <typename TPixel>
std::uint64_t
PlaneLabelBytes(const std::vector<TPixel> &                             plane,
                std::uint64_t                                           lineVoxels,
                const itk::SmallIsoComponentDetail::Threshold<TPixel> & threshold,
                bool                                                    fullyConnected,
                std::uint64_t                                           maximumSize,
                PlaneComponents &                                       components)
{
  // Diagonal neighbours join runs that only touch at a corner.
  const std::uint64_t  reach = fullyConnected ? 1 : 0;
  std::vector<LineRun> previous;
  std::vector<LineRun> current;
  components.Parent.clear();
  components.Voxels.clear();
  for (std::uint64_t start = 0; start < plane.size(); start += lineVoxels)
  {
    current.clear();
    const TPixel * line = plane.data() + start;
    for (std::uint64_t begin = 0, end = 0; begin < lineVoxels; begin = end)
    {
      const bool above = threshold.IsAbove(line[begin]);
      end = threshold.NextSideChange(line, begin + 1, lineVoxels, above);
      current.push_back({ begin, end, components.Parent.size(), above });
      components.Parent.push_back(components.Parent.size());
      components.Voxels.push_back(end - begin);
    }
    std::size_t first = 0;
    for (const LineRun & run : current)
    {
      while (first < previous.size() && previous[first].End + reach <= run.Begin)
      {
        ++first;
      }
      for (std::size_t p = first; p < previous.size() && previous[p].Begin < run.End + reach; ++p)
      {
        std::uint64_t a = previous[p].Index;
        std::uint64_t b = run.Index;
        if (previous[p].Above == run.Above && itk::SmallIsoComponentDetail::JoinRoots(components.Parent.data(), a, b))
        {
          components.Voxels[a] += components.Voxels[b];
        }
      }
    }
    std::swap(previous, current);
  }
  const std::uint64_t runs = components.Parent.size();
  std::uint64_t       bytes = runs * BytesPerRun;
  for (std::uint64_t run = 0; run < runs; ++run)
  {
    if (components.Parent[run] == run)
    {
      const std::uint64_t voxels = components.Voxels[run];
      bytes += BytesPerComponent + (voxels <= maximumSize ? voxels * BytesPerRepairedVoxel : 0);
    }
  }
  return bytes;
}

template <typename TPixel>
std::uint64_t
MostLabelBytes(PlaneReader & input, double isoValue, bool fullyConnected, std::uint64_t maximumSize)
{
  const VolumeGeometry & geometry = input.GetGeometry();
  std::vector<TPixel>    plane(geometry.PlaneVoxels());
  PlaneComponents        components;
  // The filter's own classification: NaN is below.
  const itk::SmallIsoComponentDetail::Threshold<TPixel> threshold(isoValue);
  std::uint64_t                                         most = 0;
  for (std::uint64_t z = 0; z < geometry.Planes(); ++z)
  {
    input.Read(plane.data(), 1);
    most = std::max(most, PlaneLabelBytes(plane, geometry.Size[0], threshold, fullyConnected, maximumSize, components));
  }
  input.Finish();
  return most;
}
} // namespace

std::uint64_t
MostLabelBytesInAPlane(const std::string & path, double isoValue, bool fullyConnected, std::uint64_t maximumSize)
{
  PlaneReader input(path, "input");
  return DispatchPixelType(
    input.GetGeometry().ComponentType,
    [&](auto pixel) {
      return MostLabelBytes<typename decltype(pixel)::PixelType>(input, isoValue, fullyConnected, maximumSize);
    },
    [&] {
      return ToolError("cannot stream the input: pixel type " + PixelTypeName(input.GetGeometry().ComponentType) +
                       " is not supported; expected one of " + SupportedPixelTypes());
    });
}

std::uint64_t
StreamingProcessBytes()
{
  return PeakResidentBytes() + RunOverheadBytes;
}

std::uint64_t
StreamingWorkingBytes(const VolumeGeometry & geometry,
                      std::uint64_t          labelBytesPerPlane,
                      std::uint64_t          maximumSize,
                      std::uint64_t          slabPlanes,
                      unsigned int           workUnits)
{
  const uint64_t planeVoxels = geometry.PlaneVoxels();
  const uint64_t window =
    std::min(itk::SmallIsoComponentDetail::StreamingSweep<uint8_t>::WindowPlanes(maximumSize, slabPlanes, workUnits),
             geometry.Planes());
  const uint64_t perPlane = planeVoxels * geometry.PixelBytes() + labelBytesPerPlane;
  // Beside the window: the slab being read (twice: read, and taken by the sweep) and the planes being written.
  return window * perPlane + 2 * slabPlanes * planeVoxels * geometry.PixelBytes() + 2 * planeVoxels * 2;
}

std::uint64_t
SlabPlanesForBudget(const VolumeGeometry & geometry,
                    std::uint64_t          labelBytesPerPlane,
                    std::uint64_t          maximumSize,
                    std::uint64_t          budget,
                    unsigned int           workUnits)
{
  uint64_t best = 0;
  for (uint64_t planes = 1; planes <= geometry.Planes(); planes = planes < 8 ? planes + 1 : planes + planes / 4)
  {
    if (StreamingWorkingBytes(geometry, labelBytesPerPlane, maximumSize, planes, workUnits) > budget)
    {
      break;
    }
    best = planes;
  }
  return best;
}

void
RunStreamedFilter(PlaneReader &                       input,
                  const FilterSettings &              settings,
                  const StreamedOutputs &             outputs,
                  std::uint64_t                       maximumSize,
                  std::uint64_t                       slabPlanes,
                  std::uint64_t                       memoryLimit,
                  const std::function<void(double)> & progress,
                  FilterReport &                      report)
{
  DispatchPixelType(
    input.GetGeometry().ComponentType,
    [&](auto pixel) {
      RunStreamed<typename decltype(pixel)::PixelType>(
        input, settings, outputs, maximumSize, slabPlanes, memoryLimit, progress, report);
    },
    [&] {
      return ToolError("cannot stream the input: pixel type " + PixelTypeName(input.GetGeometry().ComponentType) +
                       " is not supported; expected one of " + SupportedPixelTypes());
    });
}
} // namespace sic
