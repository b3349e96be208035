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
#include "sicCommandLine.h"
#include "sicImageFiles.h"
#include "sicLabelFilterSetUp.h"
#include "sicProgressReporter.h"
#include "sicScalarImageDispatch.h"
#include "sicStrings.h"
#include "sicToolError.h"

#ifdef SIC_HAVE_VTK
#  include "sicLabelSurfaces.h"
#endif

#include "itkMultiThreaderBase.h"
#include "itkSmallIsoComponentLabelImageFilter.h"

#include <chrono>
#include <map>
#include <set>
#include <type_traits>

namespace sic
{
namespace
{
// The options of scalar images, each with why it has no meaning for a label map and what is expected instead.
const std::pair<const char *, const char *> ScalarOnlyOptions[] = {
  { "--isovalue", "has no meaning for a label map, whose every distinct value is a label; expected no --isovalue" },
  { "--side", "has no meaning for a label map; expected --select all|islands|holes or a list of label ids" },
};

const char * const LabelOnlyOptions[] = { "--select", "--background", "--max-size-of", "--keep-largest" };

/** The comma-separated items of \a text, empty ones included. */
std::vector<std::string>
Items(const std::string & text)
{
  std::vector<std::string> items;
  for (size_t begin = 0;;)
  {
    const size_t comma = text.find(',', begin);
    items.push_back(Trim(text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin)));
    if (comma == std::string::npos)
    {
      return items;
    }
    begin = comma + 1;
  }
}

template <typename TFilter>
void
ReportLabels(const TFilter & filter, FilterReport & report)
{
  report.EffectiveMaximumSize = filter.GetEffectiveMaximumComponentSize();
  report.Threads = itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads();
  report.WorkUnits = filter.GetNumberOfWorkUnits();
  for (const auto & [label, statistics] : filter.GetLabelStatistics())
  {
    LabelReport entry;
    entry.Components = statistics.Components;
    entry.RemovedComponents = statistics.RemovedComponents;
    entry.RemovedVoxels = statistics.RemovedVoxels;
    entry.GainedVoxels = statistics.GainedVoxels;
    entry.Histogram.insert(statistics.Histogram.begin(), statistics.Histogram.end());
    report.Labels.emplace_back(LabelText(label), std::move(entry));
  }
  report.ModifiedVoxels = filter.GetNumberOfModifiedVoxels();
  report.UnrepairableVoxels = filter.GetNumberOfUnrepairableVoxels();
}

#ifdef SIC_HAVE_VTK
/** Each label's surface pieces, counted by WriteLabelSurfaces(), in the report's entries of the labels. */
template <typename TLabel>
void
ReportSurfacePieces(const std::vector<TLabel> & labels, const LabelSurfacePieces & pieces, FilterReport & report)
{
  std::map<std::string, LabelReport *> entries;
  for (auto & [id, entry] : report.Labels)
  {
    entries[id] = &entry;
  }
  for (std::size_t number = 1; number <= labels.size(); ++number)
  {
    LabelReport & entry = *entries.at(LabelText(labels[number - 1]));
    if (!pieces.Before.empty())
    {
      entry.SurfacePiecesBefore = pieces.Before[number];
    }
    if (!pieces.After.empty())
    {
      entry.SurfacePiecesAfter = pieces.After[number];
    }
    if (!pieces.Removed.empty())
    {
      entry.RemovedSurfacePieces = pieces.Removed[number];
    }
  }
}
#endif

template <typename TImage>
FilterReport
FilterLabels(const FilterSettings &  settings,
             const ScalarImageInfo & info,
             const StagedPaths &     staged,
             ProgressReporter &      progress)
{
  auto filter = itk::SmallIsoComponentLabelImageFilter<TImage>::New();
  SetUpLabelFilter(*filter, settings, info.ComponentType);
  progress.Stage("reading " + settings.Input, 0.0, 0.1);
  filter->SetInput(ReadImage<TImage>(settings.Input, "input", progress.Observer()));
  filter->AddObserver(itk::ProgressEvent(), progress.Observer());
  const bool surfaces = !settings.Surface.empty() || !settings.SurfaceBefore.empty() || !settings.Render.empty();
#ifdef SIC_HAVE_VTK
  // The labels and the input's surfaces are taken before filtering in place overwrites the input; the removed
  // pieces are cut from the input's surfaces with the mask.
  std::vector<typename TImage::PixelType> labels;
  vtkSmartPointer<vtkPolyData>            before;
  if constexpr (TImage::ImageDimension == 3)
  {
    if (surfaces)
    {
      labels = SurfaceLabels(*filter->GetInput(), filter->GetBackgroundValue());
    }
    if (!settings.SurfaceBefore.empty() || !settings.Render.empty())
    {
      progress.Stage("extracting the input's label surfaces", 0.1, 0.12);
      before = LabelSurfacesOf(*filter->GetInput(), labels);
      filter->GenerateRemovedMaskOn();
    }
  }
#endif

  progress.Stage("removing small components", 0.1, surfaces ? 0.85 : 0.9);
  const auto start = std::chrono::steady_clock::now();
  UpdateLabelFilter(*filter, settings);
  const auto stop = std::chrono::steady_clock::now();

  FilterReport report;
  ReportLabels(*filter, report);
#ifdef SIC_HAVE_VTK
  if constexpr (TImage::ImageDimension == 3)
  {
    if (surfaces)
    {
      ReportSurfacePieces(
        labels, WriteLabelSurfaces(settings, staged, before, labels, *filter, progress, report), report);
    }
  }
#endif

  progress.Stage("writing " + settings.Output, 0.9, settings.RemovedMask.empty() ? 1.0 : 0.97);
  WriteImage(
    filter->GetOutput(), staged.Image, settings.Output, "output image", progress.Observer(), settings.Compress);
  if (!settings.RemovedMask.empty())
  {
    progress.Stage("writing " + settings.RemovedMask, 0.97, 1.0);
    WriteImage(filter->GetRemovedMask(),
               staged.RemovedMask,
               settings.RemovedMask,
               "removed-voxel mask",
               progress.Observer(),
               settings.Compress);
  }
  report.FilterSeconds = std::chrono::duration<double>(stop - start).count();
  return report;
}
} // namespace

std::string
LabelId(const std::string & flag, const std::string & text)
{
  const bool   negative = !text.empty() && text[0] == '-';
  const size_t digits = !text.empty() && (text[0] == '-' || text[0] == '+') ? 1 : 0;
  if (text.size() == digits || text.find_first_not_of("0123456789", digits) != std::string::npos)
  {
    throw ToolError(flag + " " + Quoted(text) + " is not a label id; expected a whole number such as 3 or -1");
  }
  const size_t      first = std::min(text.find_first_not_of('0', digits), text.size() - 1);
  const std::string id = text.substr(first);
  return negative && id != "0" ? "-" + id : id;
}

void
ReadLabelSettings(const ParsedCommandLine & arguments, FilterSettings & settings)
{
  for (const auto & [flag, why] : ScalarOnlyOptions)
  {
    if (arguments.Has(flag))
    {
      throw ToolError(std::string(flag) + " " + why);
    }
  }
  if (arguments.Has("--select"))
  {
    const std::string text = arguments.Value("--select");
    const std::string word = Lowercase(Trim(text));
    if (word == "all" || word == "islands" || word == "holes")
    {
      settings.Selection = word;
    }
    else if (word.find_first_of("0123456789") == std::string::npos)
    {
      throw ToolError("--select " + Quoted(text) +
                      " is not a valid choice; expected all, islands, holes or label ids such as 3,5,12");
    }
    else
    {
      settings.Selection = "listed";
      for (const std::string & item : Items(text))
      {
        settings.SelectedLabels.push_back(LabelId("--select", item));
      }
    }
  }
  if (arguments.Has("--background"))
  {
    settings.Background = LabelId("--background", Trim(arguments.Value("--background")));
  }
  std::set<std::string> sized;
  for (const std::string & value : arguments.Values("--max-size-of"))
  {
    for (const std::string & item : Items(value))
    {
      const size_t equals = item.find('=');
      if (equals == std::string::npos)
      {
        throw ToolError("--max-size-of " + Quoted(item) +
                        " is not L=K; expected a label id, '=' and a size in voxels, such as 7=500");
      }
      const std::string id = LabelId("--max-size-of", Trim(item.substr(0, equals)));
      if (!sized.insert(id).second)
      {
        throw ToolError("--max-size-of gives label " + id + " more than one K; expected one K per label");
      }
      settings.LabelMaximumSizes.emplace_back(id, ParseCount("--max-size-of", Trim(item.substr(equals + 1))));
    }
  }
  if (arguments.Has("--keep-largest"))
  {
    settings.KeepLargest = ParseCount("--keep-largest", arguments.Value("--keep-largest"));
  }
}

void
RefuseLabelOptions(const ParsedCommandLine & arguments)
{
  for (const char * flag : LabelOnlyOptions)
  {
    if (arguments.Has(flag))
    {
      throw ToolError(std::string(flag) + " applies to label maps only; expected --labels with it, or no " + flag);
    }
  }
}

std::vector<std::pair<std::string, LabelReport>>
CountLabelComponents(const FilterSettings & settings, const ScalarImageInfo & info)
{
  return DispatchLabelImage(info, [&](auto tag) {
    auto filter = itk::SmallIsoComponentLabelImageFilter<typename decltype(tag)::ImageType>::New();
    filter->SetMaximumComponentSize(0);
    filter->SetFullyConnected(settings.FullyConnected);
    if (settings.Threads > 0)
    {
      filter->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(settings.Threads));
    }
    filter->InPlaceOn();
    filter->SetInput(ReadImage<typename decltype(tag)::ImageType>(settings.Input, "input", nullptr));
    UpdateLabelFilter(*filter, settings);
    FilterReport report;
    ReportLabels(*filter, report);
    return std::move(report.Labels);
  });
}

FilterReport
FilterLabelMap(const FilterSettings &  settings,
               const ScalarImageInfo & info,
               const StagedPaths &     staged,
               ProgressReporter &      progress)
{
  return DispatchLabelImage(
    info, [&](auto tag) { return FilterLabels<typename decltype(tag)::ImageType>(settings, info, staged, progress); });
}
} // namespace sic
