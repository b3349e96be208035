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
#include "sicLabelFilter.h"
#include "sicLabelFilterSetUp.h"
#include "sicPlatform.h"
#include "sicProgressReporter.h"
#include "sicScalarImageDispatch.h"
#include "sicStreamedFilter.h"

#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>

namespace sic
{
namespace
{
using Clock = std::chrono::steady_clock;

/** What the label filter takes per voxel of the part it reads, planned for: twice what real segmentations take.
 * A map of noise, every voxel a component of its own, takes up to about 56; a run that passes the limit stops. */
constexpr std::uint64_t PlannedWorkingBytesPerVoxel = 4;

/** A window on an image's planes, read in order through \a reader: every plane is read once and kept while the
 * windows ask for it. */
template <typename TLabel>
class PlaneWindow
{
public:
  PlaneWindow(PlaneReader & reader, std::uint64_t mostPlanes)
    : m_Reader(reader)
    , m_PlaneVoxels(reader.GetGeometry().PlaneVoxels())
    , m_Voxels(mostPlanes * m_PlaneVoxels)
  {}

  /** Holds the planes [begin, end): drops those before \a begin, reads those up to \a end. Neither goes back, and
   * \a begin is never beyond the planes held or read. */
  void
  Hold(std::uint64_t begin, std::uint64_t end)
  {
    const std::uint64_t dropped = begin - m_First;
    std::copy(Plane(begin), Plane(m_First + m_Count), m_Voxels.data());
    m_Count -= dropped;
    m_First = begin;
    m_Reader.Read(Plane(m_First + m_Count), end - m_First - m_Count);
    m_Count = end - m_First;
  }

  TLabel *
  Plane(std::uint64_t plane)
  {
    return m_Voxels.data() + (plane - m_First) * m_PlaneVoxels;
  }

private:
  PlaneReader &       m_Reader;
  std::uint64_t       m_PlaneVoxels;
  std::vector<TLabel> m_Voxels;
  std::uint64_t       m_First{ 0 };
  std::uint64_t       m_Count{ 0 };
};

/** The region of planes [first, end) along the last axis of an image of \a geometry. */
template <typename TImage>
typename TImage::RegionType
PlanesRegion(const VolumeGeometry & geometry, std::uint64_t first, std::uint64_t end)
{
  constexpr unsigned int      last = TImage::ImageDimension - 1;
  typename TImage::RegionType region;
  for (unsigned int a = 0; a < TImage::ImageDimension; ++a)
  {
    region.SetSize(a, geometry.Size[a]);
  }
  region.SetIndex(last, static_cast<itk::IndexValueType>(first));
  region.SetSize(last, end - first);
  return region;
}

/** An image of \a geometry's spacing, origin and direction, without voxels. */
template <typename TImage>
typename TImage::Pointer
EmptyImage(const VolumeGeometry & geometry)
{
  auto                           image = TImage::New();
  typename TImage::SpacingType   spacing;
  typename TImage::PointType     origin;
  typename TImage::DirectionType direction;
  constexpr unsigned int         n = TImage::ImageDimension;
  for (unsigned int a = 0; a < n; ++a)
  {
    spacing[a] = geometry.Spacing[a];
    origin[a] = geometry.Origin[a];
    for (unsigned int row = 0; row < n; ++row)
    {
      direction[row][a] = geometry.Direction[row * n + a];
    }
  }
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(direction);
  return image;
}

/** The planes the filter reads beyond each side of the planes it writes: its halo, found by asking it for one
 * plane's input with the whole image's extent (all planes but one when the halo covers the image). */
template <typename TFilter>
std::uint64_t
HaloPlanes(TFilter & filter, const VolumeGeometry & geometry)
{
  using ImageType = typename TFilter::ImageType;
  auto whole = EmptyImage<ImageType>(geometry);
  whole->SetLargestPossibleRegion(PlanesRegion<ImageType>(geometry, 0, geometry.Planes()));
  filter.SetInput(whole);
  ImageType * output = filter.GetOutput();
  output->UpdateOutputInformation();
  output->SetRequestedRegion(PlanesRegion<ImageType>(geometry, 0, 1));
  output->PropagateRequestedRegion();
  return whole->GetRequestedRegion().GetSize(ImageType::ImageDimension - 1) - 1;
}

/** The error for a limit too small for this map, saying \a why. */
ToolError
LimitTooSmall(const FilterSettings & settings, std::uint64_t limit, const std::string & why)
{
  return ToolError(MemoryLimitText(settings, limit) + " is too small to stream this label map: " + why +
                   "; expected a larger limit or a smaller K");
}

/** The thickest slab whose planes, with the halo on both sides, fit in what \a limit leaves beside the process. */
std::uint64_t
SlabPlanes(const FilterSettings & settings, const VolumeGeometry & geometry, std::uint64_t halo, std::uint64_t limit)
{
  const std::uint64_t planeVoxels = geometry.PlaneVoxels();
  const std::uint64_t process = StreamingProcessBytes();
  const auto          bytes = [&](std::uint64_t slab) {
    const std::uint64_t window = std::min(geometry.Planes(), slab + 2 * halo);
    return window * planeVoxels * (geometry.PixelBytes() + PlannedWorkingBytesPerVoxel) +
           slab * planeVoxels * (geometry.PixelBytes() + 1);
  };
  if (process + bytes(1) > limit)
  {
    // A MiB to spare: the process's own size varies from run to run by a fraction of one.
    throw LimitTooSmall(settings,
                        limit,
                        "a slab of one plane and the " + std::to_string(2 * halo) +
                          " planes around it that the filter reads take about " +
                          std::to_string(((process + bytes(1)) >> 20) + 2) + " MiB with the process itself (" +
                          std::to_string((process >> 20) + 1) + " MiB)");
  }
  std::uint64_t slab = 1;
  while (slab < geometry.Planes() && process + bytes(slab + 1) <= limit)
  {
    ++slab;
  }
  return slab;
}

/** The output and, when asked for, the mask, written plane by plane. */
class OutputPlanes
{
public:
  OutputPlanes(const FilterSettings & settings, const StagedPaths & staged, const VolumeGeometry & geometry)
    : m_Image(staged.Image, settings.Output, "output image", geometry, settings.Compress)
  {
    if (!staged.RemovedMask.empty())
    {
      VolumeGeometry maskGeometry = geometry;
      maskGeometry.ComponentType = itk::IOComponentEnum::UCHAR;
      m_Mask = std::make_unique<PlaneWriter>(
        staged.RemovedMask, settings.RemovedMask, "removed-voxel mask", maskGeometry, settings.Compress);
    }
  }

  void
  Write(const void * image, const std::uint8_t * mask, std::uint64_t planes)
  {
    m_Image.Write(image, planes);
    if (m_Mask)
    {
      m_Mask->Write(mask, planes);
    }
  }

  void
  Finish()
  {
    m_Image.Finish();
    if (m_Mask)
    {
      m_Mask->Finish();
    }
  }

private:
  PlaneWriter                  m_Image;
  std::unique_ptr<PlaneWriter> m_Mask;
};

/** Adds what the filter's last run removed and repaired in its slab to \a labels and \a report: the removed
 * voxels by their label in \a before, the slab's input. */
template <typename TFilter>
void
AddSlabCounts(TFilter &                                            filter,
              const typename TFilter::LabelType *                  before,
              std::map<typename TFilter::LabelType, LabelReport> & labels,
              FilterReport &                                       report)
{
  const std::uint8_t * removed = filter.GetRemovedMask()->GetBufferPointer();
  const std::uint64_t  voxels = filter.GetRemovedMask()->GetBufferedRegion().GetNumberOfPixels();
  for (std::uint64_t i = 0; i < voxels; ++i)
  {
    if (removed[i] != 0)
    {
      ++labels[before[i]].RemovedVoxels;
    }
  }
  for (const auto & [label, statistics] : filter.GetLabelStatistics())
  {
    labels[label].GainedVoxels += statistics.GainedVoxels;
  }
  report.ModifiedVoxels += filter.GetNumberOfModifiedVoxels();
  report.UnrepairableVoxels += filter.GetNumberOfUnrepairableVoxels();
}

template <typename TImage>
FilterReport
StreamLabels(const FilterSettings & settings,
             PlaneReader &          input,
             const StagedPaths &    staged,
             std::uint64_t          limit,
             ProgressReporter &     progress)
{
  using LabelType = typename TImage::PixelType;
  const VolumeGeometry & geometry = input.GetGeometry();
  auto                   filter = itk::SmallIsoComponentLabelImageFilter<TImage>::New();
  SetUpLabelFilter(*filter, settings, geometry.ComponentType);
  // The window's planes are the next window's halo: they stay as they were read.
  filter->InPlaceOff();
  filter->GenerateRemovedMaskOn();
  const std::uint64_t    halo = HaloPlanes(*filter, geometry);
  const std::uint64_t    slab = SlabPlanes(settings, geometry, halo, limit);
  const std::uint64_t    planes = geometry.Planes();
  OutputPlanes           outputs(settings, staged, geometry);
  PlaneWindow<LabelType> window(input, std::min(planes, slab + 2 * halo));
  auto                   part = EmptyImage<TImage>(geometry);
  filter->SetInput(part);

  FilterReport                     report;
  std::map<LabelType, LabelReport> labels;
  Clock::duration                  reading{};
  Clock::duration                  writing{};
  const auto                       start = Clock::now();
  for (std::uint64_t first = 0; first < planes; first += slab)
  {
    const std::uint64_t end = std::min(planes, first + slab);
    const std::uint64_t partFirst = first - std::min(first, halo);
    const std::uint64_t partEnd = std::min(planes, end + halo);
    const auto          readStart = Clock::now();
    window.Hold(partFirst, partEnd);
    reading += Clock::now() - readStart;
    // The part read is the whole image to the filter: what it writes of the slab depends on that part alone.
    part->SetRegions(PlanesRegion<TImage>(geometry, partFirst, partEnd));
    part->GetPixelContainer()->SetImportPointer(
      window.Plane(partFirst), (partEnd - partFirst) * geometry.PlaneVoxels(), false);
    part->Modified();
    filter->GetOutput()->SetRequestedRegion(PlanesRegion<TImage>(geometry, first, end));
    UpdateLabelFilter(*filter, settings);
    AddSlabCounts(*filter, window.Plane(first), labels, report);
    const auto writeStart = Clock::now();
    outputs.Write(filter->GetOutput()->GetBufferPointer(), filter->GetRemovedMask()->GetBufferPointer(), end - first);
    writing += Clock::now() - writeStart;
    progress.Update(static_cast<double>(end) / static_cast<double>(planes));
    const std::uint64_t peak = PeakResidentBytes();
    if (peak > limit && end < planes)
    {
      throw LimitTooSmall(settings,
                          limit,
                          "the run passed it after " + std::to_string(end) + " of " + std::to_string(planes) +
                            " planes, holding " + std::to_string(peak >> 20) + " MiB, so it needs more");
    }
  }
  input.Finish();
  const auto finishStart = Clock::now();
  outputs.Finish();
  writing += Clock::now() - finishStart;

  for (auto & [label, entry] : labels)
  {
    report.Labels.emplace_back(LabelText(label), std::move(entry));
  }
  report.EffectiveMaximumSize = filter->GetEffectiveMaximumComponentSize();
  report.WorkUnits = filter->GetNumberOfWorkUnits();
  report.Streaming = true;
  report.SlabPlanes = slab;
  report.ReadSeconds = std::chrono::duration<double>(reading).count();
  report.WriteSeconds = std::chrono::duration<double>(writing).count();
  report.FilterSeconds =
    std::chrono::duration<double>(Clock::now() - start).count() - report.ReadSeconds - report.WriteSeconds;
  return report;
}
} // namespace

FilterReport
FilterLabelMapStreamed(const FilterSettings &  settings,
                       const ScalarImageInfo & info,
                       const StagedPaths &     staged,
                       std::uint64_t           limit,
                       ProgressReporter &      progress)
{
  PlaneReader input(settings.Input, "input");
  progress.Stage("removing small components plane by plane", 0.0, 1.0);
  FilterReport report = DispatchLabelImage(info, [&](auto tag) {
    return StreamLabels<typename decltype(tag)::ImageType>(settings, input, staged, limit, progress);
  });
  report.Threads = itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads();
  report.MemoryLimit = limit;
  return report;
}
} // namespace sic
