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
// SmallIsoComponentReport: how many components each side of an isovalue has, how many a
// maximum size K would remove and how many voxels that changes, for many isovalues and K;
// with --labels, the same for each label of a label map.
// The command line and --help come from DescribeTool().

#include "sicCommandLine.h"
#include "sicImageFiles.h"
#include "sicLabelFilter.h"
#include "sicReportCounting.h"
#include "sicReportPlot.h"
#include "sicReportRanges.h"
#include "sicReportTable.h"
#include "sicScalarImageDispatch.h"
#include "sicStagedOutputs.h"
#include "sicToolError.h"
#include "sicToolMain.h"

#include "itkMultiThreaderBase.h"
#include "itkSmallIsoComponentImageFilter.h"

#ifdef SIC_HAVE_VTK
#  include "sicSurface.h"

#  include "vtkPolyData.h"
#endif

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

namespace
{
const char * const ToolName = "SmallIsoComponentReport";

/** No sweep may ask for more isovalues or sizes than this. */
constexpr std::uint64_t MaximumSweep = 100000;

struct ReportSettings
{
  std::string                  Input;
  std::vector<double>          IsoValues;
  std::vector<std::uint64_t>   MaximumSizes;
  bool                         FullyConnected{ false };
  std::string                  Format{ "markdown" };
  std::string                  Output;
  std::string                  Plot;
  std::optional<std::uint64_t> PlotSize;
  std::optional<double>        PlotIsoValue;
  std::uint64_t                Threads{ 0 };
  bool                         Surfaces{ true };
  bool                         Labels{ false };
};

sic::ToolDescription
DescribeTool()
{
  sic::ToolDescription tool;
  tool.Name = ToolName;
  tool.Usage = "SmallIsoComponentReport INPUT (--isovalue S [--isovalue S2 ...] [--isovalue-range START:STOP:STEP] "
               "| --labels) [--sizes 1,5,10,20,50] [--sizes-range START:STOP:STEP] [--fully-connected] "
               "[--format markdown|csv|json] [--output FILE] [--plot FILE.png] [--plot-size K] "
               "[--plot-isovalue S] [--no-surfaces] [--threads N] [--help]";
  tool.Description =
    "Measures what removing small components would do to a volume, without changing it: for every isovalue S, "
    "the active cubes (grid cells with corners on both sides of S, those Marching Cubes turns into triangles), "
    "the number of components above S (voxels >= S) and below S (all others, NaN included), and for every "
    "maximum size K the components of each side with at most K voxels and the voxels in them. Each side is "
    "counted on the original volume. One labelling per isovalue serves every K."
#ifdef SIC_HAVE_VTK
    " For 3-D images it also runs the filter with side both at every isovalue and K and counts the connected "
    "pieces of the isosurface (VTK's Flying Edges) before and after filtering."
#endif
    " With --labels, the input is a label map, and the report gives for every label its components and, for every "
    "K, those with at most K voxels and the voxels in them: what SmallIsoComponentFilter --labels removes with that "
    "K and --select all. One labelling serves every K.";
  tool.Positionals = { { "INPUT",
                         "The image to measure: a scalar 2-D or 3-D image with pixel type " +
                           sic::SupportedPixelTypes() + "; with --labels, a label map of type " +
                           sic::SupportedLabelPixelTypes() + ".",
                         {} } };
  tool.Options = {
    { "--isovalue",
      "S",
      "An isovalue, in the image's intensity units; may be given several times. At least one --isovalue or "
      "--isovalue-range is required, unless --labels is given.",
      "",
      {} },
    { "--isovalue-range",
      "START:STOP:STEP",
      "Adds the isovalues START, START+STEP, ... up to STOP (included when a step lands on it); STEP > 0.",
      "",
      {} },
    { "--sizes",
      "K1,K2,...",
      "The maximum sizes K, in voxels, comma-separated whole numbers >= 0.",
      "1,5,10,20,50 unless --sizes-range is given",
      {} },
    { "--sizes-range", "START:STOP:STEP", "Adds the sizes START, START+STEP, ... up to STOP; STEP >= 1.", "", {} },
    { "--labels",
      "",
      "The input is a label map (integer ids, or floating-point samples that are whole numbers): report each "
      "label's small components instead of the sides of isovalues. No isovalue or plot is taken.",
      "",
      {} },
    { "--fully-connected",
      "",
      "Connect voxels that share an edge or a corner too (26 neighbours in 3-D, 8 in 2-D), not only a face.",
      "face connectivity",
      {} },
    { "--format",
      "markdown|csv|json",
      "The report's form: a markdown table, CSV (one line per isovalue, side and K) or JSON.",
      "markdown",
      {} },
    { "--output", "FILE", "Write the report to FILE instead of stdout.", "stdout", {} },
    { "--plot",
      "FILE.png",
      "Also draw the removal curves with gnuplot: components removed and voxels modified against the isovalue "
      "(at one K) and against K (at one isovalue), per side.",
      "",
      {} },
    { "--plot-size", "K", "The K of the curves against the isovalue; one of the sizes.", "the largest size", {} },
    { "--plot-isovalue",
      "S",
      "The isovalue of the curves against K; one of the isovalues.",
      "the first --isovalue, or the range's START",
      {} },
    { "--no-surfaces",
      "",
      "Skip the filter runs and isosurface piece counts (which cost one filter run and one surface "
      "extraction per isovalue and K; worth skipping for long sweeps). Only tools built with VTK count "
      "surface pieces; without VTK this option changes nothing.",
      "surfaces counted for 3-D images when built with VTK",
      {} },
    { "--threads",
      "N",
      "Number of threads (ITK work units), at most " + std::to_string(sic::MaximumThreads()) +
        " (ITK's limit); 0 uses ITK's default. The report does not depend on it.",
      "0",
      {} },
    { "--help", "", "Print this help and exit (also -h).", "", {} },
  };
  tool.RepeatableOptions = { "--isovalue" };
  tool.Epilogue = "Isovalues and sizes are reported in ascending order, each once. Outputs (--output, --plot)\n"
                  "appear together once all were written; after a failure neither is written or changed.\n"
                  "\n"
                  "Exit status:\n"
                  "  0  success\n"
                  "  1  the processing failed (e.g. out of memory)\n"
                  "  2  a wrong command line, an unreadable or unsupported input, an output that cannot\n"
                  "     be written, or no gnuplot for --plot; one line on stderr says what was wrong\n"
                  "\n"
                  "Example: a table for three isovalues, and a sweep drawn as curves:\n"
                  "  SmallIsoComponentReport ct.nrrd --isovalue 100 --isovalue 150 --isovalue 200\n"
                  "  SmallIsoComponentReport ct.nrrd --isovalue-range 50:250:2 --sizes-range 1:100:1 \\\n"
                  "      --format csv --output sweep.csv --plot sweep.png\n"
                  "and what each K would remove from each label of a segmentation:\n"
                  "  SmallIsoComponentReport seg.nii.gz --labels --sizes 10,50,200\n";
  return tool;
}

template <typename T>
void
SortUnique(std::vector<T> & values)
{
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
}

ReportSettings
ReadSettings(const sic::ToolDescription & tool, const sic::ParsedCommandLine & arguments)
{
  sic::CheckPositionals(tool, arguments);
  ReportSettings settings;
  settings.Input = arguments.Positionals()[0];
  settings.Labels = arguments.Has("--labels");
  if (settings.Labels)
  {
    for (const char * flag : { "--isovalue", "--isovalue-range", "--plot", "--plot-size", "--plot-isovalue" })
    {
      if (arguments.Has(flag))
      {
        throw sic::ToolError(std::string(flag) + " is not taken with --labels: a label map has no isovalue, and its "
                                                 "report has no curves to plot");
      }
    }
  }
  for (const std::string & text : arguments.Values("--isovalue"))
  {
    settings.IsoValues.push_back(sic::ParseNumber("--isovalue", text));
  }
  if (!settings.IsoValues.empty())
  {
    settings.PlotIsoValue = settings.IsoValues.front();
  }
  if (arguments.Has("--isovalue-range"))
  {
    const auto range = sic::ParseNumberRange("--isovalue-range", arguments.Value("--isovalue-range"), MaximumSweep);
    settings.IsoValues.insert(settings.IsoValues.end(), range.begin(), range.end());
  }
  if (settings.IsoValues.empty() && !settings.Labels)
  {
    throw sic::ToolError("no isovalue; expected --isovalue S (e.g. --isovalue 150) or --isovalue-range "
                         "START:STOP:STEP");
  }
  if (!settings.PlotIsoValue && !settings.Labels)
  {
    settings.PlotIsoValue = settings.IsoValues.front();
  }
  SortUnique(settings.IsoValues);

  if (arguments.Has("--sizes"))
  {
    settings.MaximumSizes = sic::ParseCountList("--sizes", arguments.Value("--sizes"));
  }
  if (arguments.Has("--sizes-range"))
  {
    const auto range = sic::ParseCountRange("--sizes-range", arguments.Value("--sizes-range"), MaximumSweep);
    settings.MaximumSizes.insert(settings.MaximumSizes.end(), range.begin(), range.end());
  }
  if (settings.MaximumSizes.empty())
  {
    settings.MaximumSizes = { 1, 5, 10, 20, 50 };
  }
  SortUnique(settings.MaximumSizes);

  settings.FullyConnected = arguments.Has("--fully-connected");
  if (arguments.Has("--format"))
  {
    settings.Format = sic::ParseChoice("--format", arguments.Value("--format"), { "markdown", "csv", "json" });
  }
  settings.Output = arguments.Value("--output");
  settings.Plot = arguments.Value("--plot");
  sic::CheckPathsNotEmpty(arguments, { "--output", "--plot" });
  if (!settings.Plot.empty())
  {
    sic::CheckPngFileName(settings.Plot, "plot");
  }
  if (arguments.Has("--plot-size"))
  {
    settings.PlotSize = sic::ParseCount("--plot-size", arguments.Value("--plot-size"));
    if (!std::binary_search(settings.MaximumSizes.begin(), settings.MaximumSizes.end(), *settings.PlotSize))
    {
      throw sic::ToolError("--plot-size " + arguments.Value("--plot-size") +
                           " is not one of the sizes; expected a K given by --sizes or --sizes-range");
    }
  }
  if (arguments.Has("--plot-isovalue"))
  {
    settings.PlotIsoValue = sic::ParseNumber("--plot-isovalue", arguments.Value("--plot-isovalue"));
    if (!std::binary_search(settings.IsoValues.begin(), settings.IsoValues.end(), *settings.PlotIsoValue))
    {
      throw sic::ToolError("--plot-isovalue " + arguments.Value("--plot-isovalue") +
                           " is not one of the isovalues; expected an S given by --isovalue or --isovalue-range");
    }
  }
  if ((settings.PlotSize || arguments.Has("--plot-isovalue")) && settings.Plot.empty())
  {
    throw sic::ToolError("--plot-size and --plot-isovalue choose curves of --plot FILE.png, which is not given");
  }
  settings.Threads = sic::ParseThreads(arguments);
  settings.Surfaces = !arguments.Has("--no-surfaces");
  return settings;
}

#ifdef SIC_HAVE_VTK
/** Runs the filter (side Both) at every isovalue and K of \a rows and counts the pieces of the
 * isosurface before and after. */
template <typename TImage>
void
MeasureSurfaces(const ReportSettings & settings, TImage & image, std::vector<sic::ReportRow> & rows)
{
  using FilterType = itk::SmallIsoComponentImageFilter<TImage>;
  auto filter = FilterType::New();
  filter->SetInput(&image);
  filter->SetSide(itk::SmallIsoComponentEnums::Side::Both);
  filter->SetFullyConnected(settings.FullyConnected);
  if (settings.Threads > 0)
  {
    filter->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(settings.Threads));
  }
  for (sic::ReportRow & row : rows)
  {
    sic::FilteredRow filtered;
    filtered.SurfacePiecesBefore =
      sic::CountSurfacePieces(*sic::ExtractIsosurface(sic::SurfaceGridOf(image), row.IsoValue));
    filter->SetIsoValue(row.IsoValue);
    for (const std::uint64_t k : settings.MaximumSizes)
    {
      filter->SetMaximumComponentSize(k);
      filter->Update();
      filtered.RemovedComponents.push_back(
        filter->GetNumberOfRemovedComponents(itk::SmallIsoComponentEnums::Side::Above) +
        filter->GetNumberOfRemovedComponents(itk::SmallIsoComponentEnums::Side::Below));
      filtered.ModifiedVoxels.push_back(filter->GetNumberOfModifiedVoxels());
      filtered.SurfacePiecesAfter.push_back(
        sic::CountSurfacePieces(*sic::ExtractIsosurface(sic::SurfaceGridOf(*filter->GetOutput()), row.IsoValue)));
    }
    row.Filtered = std::move(filtered);
  }
}
#endif

template <typename TImage>
std::vector<sic::ReportRow>
MeasureImage(const ReportSettings & settings, itk::MultiThreaderBase * threader)
{
  using PixelType = typename TImage::PixelType;
  const typename TImage::Pointer        image = sic::ReadImage<TImage>(settings.Input, "input", nullptr);
  const auto &                          extent = image->GetBufferedRegion().GetSize();
  const std::vector<itk::SizeValueType> size(extent.begin(), extent.end());
  const PixelType *                     buffer = image->GetBufferPointer();

  // Sizes above the number of voxels cannot occur: the histograms stop there.
  const itk::SizeValueType largestSize =
    std::min<itk::SizeValueType>(settings.MaximumSizes.back(), image->GetBufferedRegion().GetNumberOfPixels());
  const sic::ActiveCubeCounter<PixelType> activeCubes(buffer, size, threader);
  std::vector<sic::ReportRow>             rows;
  for (const double isoValue : settings.IsoValues)
  {
    sic::SideHistogram above;
    sic::SideHistogram below;
    sic::LabelSides(buffer, size, settings.FullyConnected, isoValue, largestSize, threader, above, below);
    sic::ReportRow row;
    row.IsoValue = isoValue;
    row.ActiveCubes = activeCubes.Count(isoValue);
    row.Above = sic::SummarizeSide(above, settings.MaximumSizes);
    row.Below = sic::SummarizeSide(below, settings.MaximumSizes);
    rows.push_back(row);
  }
#ifdef SIC_HAVE_VTK
  if constexpr (TImage::ImageDimension == 3)
  {
    if (settings.Surfaces)
    {
      MeasureSurfaces(settings, *image, rows);
    }
  }
#endif
  return rows;
}

/** \a report (a Report or a LabelMapReport) as \a format asks: markdown, csv or json. */
template <typename TReport>
std::string
ReportText(const TReport & report, const std::string & format)
{
  std::ostringstream text;
  if (format == "json")
  {
    sic::WriteReportJson(text, report);
  }
  else if (format == "csv")
  {
    sic::WriteReportCsv(text, report);
  }
  else
  {
    sic::WriteReportMarkdown(text, report);
  }
  return text.str();
}

/** The label map's report, in the form settings.Format asks for. */
std::string
ReportLabelMap(const ReportSettings & settings, const sic::ScalarImageInfo & info)
{
  sic::FilterSettings counting;
  counting.Input = settings.Input;
  counting.FullyConnected = settings.FullyConnected;
  counting.Threads = settings.Threads;
  sic::LabelMapReport report;
  report.Input = settings.Input;
  report.Size = info.Size;
  report.FullyConnected = settings.FullyConnected;
  report.MaximumSizes = settings.MaximumSizes;
  std::uint64_t voxels = 1;
  for (const std::uint64_t extent : info.Size)
  {
    voxels *= extent;
  }
  // Sizes above the number of voxels cannot occur: the histograms stop there.
  const std::uint64_t largestSize = std::min(settings.MaximumSizes.back(), voxels);
  for (const auto & [label, counts] : sic::CountLabelComponents(counting, info))
  {
    sic::SideHistogram histogram;
    histogram.Components = counts.Components;
    histogram.CountOfSize.assign(largestSize + 1, 0);
    for (const auto & [size, count] : counts.Histogram)
    {
      if (size <= largestSize)
      {
        histogram.CountOfSize[size] += count;
      }
    }
    report.Labels.emplace_back(label, sic::SummarizeSide(histogram, settings.MaximumSizes));
  }
  return ReportText(report, settings.Format);
}

/** Writes \a text to its staged output, or to stdout once the outputs are committed when there is none. */
int
Deliver(const std::string &    text,
        const ReportSettings & settings,
        const std::string &    stagedOutput,
        sic::StagedOutputs &   outputs)
{
  if (!stagedOutput.empty())
  {
    sic::WriteTextFile(stagedOutput, settings.Output, "report", text);
  }
  outputs.Commit();
  if (stagedOutput.empty())
  {
    std::cout << text << std::flush;
  }
  return sic::ExitSuccess;
}

int
Run(const ReportSettings & settings)
{
  if (settings.Labels)
  {
    const sic::ScalarImageInfo info = sic::ReadLabelImageInfo(settings.Input, "input");
    sic::StagedOutputs         outputs;
    outputs.Protect(info.Files, "the input image");
    const std::string stagedOutput = settings.Output.empty() ? "" : outputs.Stage(settings.Output, "report");
    return Deliver(ReportLabelMap(settings, info), settings, stagedOutput, outputs);
  }
  const sic::ScalarImageInfo info = sic::ReadScalarImageInfo(settings.Input, "input");
  if (!settings.Plot.empty())
  {
    sic::CheckPlotterAvailable();
  }
  sic::StagedOutputs outputs;
  outputs.Protect(info.Files, "the input image");
  const std::string stagedOutput = settings.Output.empty() ? "" : outputs.Stage(settings.Output, "report");
  const std::string stagedPlot = settings.Plot.empty() ? "" : outputs.Stage(settings.Plot, "plot");

  auto threader = itk::MultiThreaderBase::New();
  if (settings.Threads > 0)
  {
    threader->SetMaximumNumberOfThreads(static_cast<itk::ThreadIdType>(settings.Threads));
    threader->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(settings.Threads));
  }

  sic::Report report;
  report.Input = settings.Input;
  report.Size = info.Size;
  report.FullyConnected = settings.FullyConnected;
  report.MaximumSizes = settings.MaximumSizes;
  report.Rows = sic::DispatchScalarImage(
    info, [&](auto tag) { return MeasureImage<typename decltype(tag)::ImageType>(settings, threader.GetPointer()); });

  const std::string text = ReportText(report, settings.Format);

  if (!stagedPlot.empty())
  {
    const auto   plotSize = settings.PlotSize.value_or(report.MaximumSizes.back());
    const size_t kIndex =
      std::lower_bound(report.MaximumSizes.begin(), report.MaximumSizes.end(), plotSize) - report.MaximumSizes.begin();
    const size_t rowIndex =
      std::lower_bound(settings.IsoValues.begin(), settings.IsoValues.end(), *settings.PlotIsoValue) -
      settings.IsoValues.begin();
    const std::string title = std::filesystem::path(settings.Input).filename().string() + ", " +
                              (settings.FullyConnected ? "full" : "face") + " connectivity";
    sic::PlotReport(report, kIndex, rowIndex, stagedPlot, settings.Plot, title);
  }
  return Deliver(text, settings, stagedOutput, outputs);
}
} // namespace

int
main(int argc, char * argv[])
{
  const sic::ToolDescription tool = DescribeTool();
  return sic::ToolMain(
    tool, argc, argv, [&tool](const sic::ParsedCommandLine & arguments) { return Run(ReadSettings(tool, arguments)); });
}
