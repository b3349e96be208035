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
// The filter tools, SmallIsoComponentFilter and SmallIsoComponentLabelFilter: remove the small components on either
// side of an isovalue, or of the labels of a label map, from an image file. The command line, --help and --xml all
// come from DescribeTool().

#include "itkSmallIsoComponentImageFilter.h"
#include "sicCommandLine.h"
#include "sicFilterReport.h"
#include "sicFilterTool.h"
#include "sicLabelFilter.h"
#include "sicImageFiles.h"
#include "sicProgressReporter.h"
#include "sicScalarImageDispatch.h"
#include "sicPlatform.h"
#include "sicStagedOutputs.h"
#include "sicStreamedFilter.h"
#include "sicStreamedImageFiles.h"
#include "sicStrings.h"
#include "sicToolError.h"
#include "sicToolMain.h"

#include "itkMultiThreaderBase.h"
#include "itkSmallIsoComponentBlockSummary.h"
#include "itkSmallIsoComponentStreamingSweep.h"

#ifdef SIC_HAVE_VTK
#  include "sicHeadlessDisplay.h"
#  include "sicRender.h"
#  include "sicSurface.h"

#  include "vtkPolyData.h"
#endif

#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <tuple>

namespace
{
using sic::Option;
using sic::SlicerParameter;

/** How a parameter appears in the Slicer description. */
SlicerParameter
Parameter(const char * tag, const char * name, const char * label, const char * group)
{
  SlicerParameter slicer;
  slicer.Tag = tag;
  slicer.Name = name;
  slicer.Label = label;
  slicer.Group = group;
  return slicer;
}

SlicerParameter
ImageParameter(const char * name, const char * label, const char * channel, const char * type)
{
  SlicerParameter slicer = Parameter("image", name, label, "Input/Output");
  slicer.Channel = channel;
  slicer.ImageType = type;
  return slicer;
}

/** The options of label maps. In SmallIsoComponentFilter they follow --labels and stay out of its Slicer panel,
 * which is for scalar volumes; the label tool's panel shows them. */
std::vector<Option>
LabelOptions(sic::FilterTool kind)
{
  const bool labelTool = kind == sic::FilterTool::Labels;
  const auto slicer = [labelTool](const char * tag, const char * name, const char * label) {
    return labelTool ? Parameter(tag, name, label, "Parameters") : SlicerParameter{};
  };
  Option labels{ "--labels",
                 "",
                 labelTool ? "Implied: this tool filters label maps (SmallIsoComponentFilter --labels)."
                           : "Filter INPUT as a label map (a segmentation): every distinct value is a label, and the "
                             "small islands and holes of the selected labels are removed, each removed voxel taking "
                             "the label voted by the labels around its component. Replaces --isovalue and --side; "
                             "SmallIsoComponentLabelFilter is this tool with --labels implied.",
                 "",
                 {} };
  Option select{ "--select",
                 "all|islands|holes|L,...",
                 "Which labels lose their small components: all (islands of every label removed and holes of the "
                 "background filled), islands (every label but the background), holes (the background only), or "
                 "a comma-separated list of label ids.",
                 "all",
                 slicer("string", "selection", "Selection (all, islands, holes or label ids)") };
  select.Slicer.Default = labelTool ? "all" : "";
  Option background{ "--background",
                     "L",
                     "The background's label id, for --select islands and holes.",
                     "0",
                     slicer("integer", "background", "Background label") };
  Option maxSizeOf{ "--max-size-of",
                    "L=K,...",
                    "The largest component removed of label L, in voxels, instead of --max-size or --max-volume "
                    "(e.g. 7=500,12=0: label 7 loses components of up to 500 voxels, label 12 none by size). May "
                    "be given more than once.",
                    "",
                    slicer("string", "maxSizePerLabel", "Maximum size per label (L=K,...)") };
  Option keepLargest{ "--keep-largest",
                      "N",
                      "Also remove every component of a selected label smaller than its N-th largest (components "
                      "tied in size with it are kept); 0 leaves this rule off.",
                      "0",
                      slicer("integer", "keepLargest", "Keep the N largest components") };
  keepLargest.Slicer.Minimum = labelTool ? "0" : "";
  return { labels, select, background, maxSizeOf, keepLargest };
}

#ifdef SIC_HAVE_VTK
/** --surface, --surface-before and --render: isosurfaces at S, or the surfaces of the labels of a label map. */
std::vector<Option>
SurfaceOptions(sic::FilterTool kind)
{
  const bool labelTool = kind == sic::FilterTool::Labels;
  const auto geometry = [&](const char * name, const char * label) {
    SlicerParameter slicer = Parameter("geometry", name, label, "Surfaces");
    slicer.Channel = "output";
    slicer.FileExtensions = ".vtp,.stl,.ply,.obj";
    return slicer;
  };
  const std::string labels =
    "a surface for each label but the background, extracted with VTK's discrete Flying Edges "
    "(vtkDiscreteFlyingEdges3D), all in one file: " +
    sic::SupportedSurfaceExtensions() +
    " by FILE's extension (.vtp keeps each triangle's label id and its label's RGB colour in the pictures, as the "
    "cell-data arrays 'label' and 'colour'; .ply keeps the colour of each face; .stl and .obj keep the triangles "
    "only)";
  const std::string physical = " Points are in physical LPS coordinates (millimetres), honouring the image's "
                               "spacing, origin and direction, as ITK maps voxel indices and as 3D Slicer reads "
                               "models. 3-D images only.";
  Option            surface{ "--surface",
                  "FILE",
                  labelTool ? "Also write the surfaces of the filtered label map: " + labels + "." + physical
                                       : "Also write the isosurface of the filtered image at S, extracted with VTK's Flying "
                                         "Edges (vtkFlyingEdges3D, the same triangles as Marching Cubes), as " +
                                sic::SupportedSurfaceExtensions() + " by FILE's extension; with --labels, " + labels +
                                "." + physical,
                  "",
                  geometry("surface", labelTool ? "Label surfaces (filtered)" : "Isosurface (filtered)") };
  Option            surfaceBefore{ "--surface-before",
                        "FILE",
                        labelTool ? "Also write the surfaces of the input label map, in the same way as --surface."
                                             : "Also write the isosurface of the input image at S (with --labels, the input's "
                                               "label surfaces), in the same way as --surface.",
                        "",
                        geometry("surfaceBefore", labelTool ? "Label surfaces (input)" : "Isosurface (input)") };
  Option            render{ "--render",
                 "FILE.png",
                 std::string("Also render, off screen, a PNG of four panels with one camera: the input's ") +
                   (labelTool ? "label surfaces" : "isosurface") +
                   ", the filtered one, only the removed pieces (the input's surface pieces that filtering took "
                              "away whole; " +
                   (labelTool ? "each label in its own colour, the removed pieces in their old label's colour"
                                         : "specks red, bubbles blue; with --labels, each label in its own colour") +
                   ") and the filtered surface (translucent) with the removed pieces, each labelled with its number "
                              "of pieces. Without an X display the tool starts a virtual one (Xvfb). 3-D images only.",
                 "",
                 Parameter("file", "render", "Rendering (PNG)", "Surfaces") };
  render.Slicer.Channel = "output";
  render.Slicer.FileExtensions = ".png";
  return { surface, surfaceBefore, render };
}
#endif

sic::ToolDescription
DescribeTool(sic::FilterTool kind)
{
  const bool           labelTool = kind == sic::FilterTool::Labels;
  sic::ToolDescription tool;
  tool.Name = labelTool ? sic::LabelToolName : sic::ScalarToolName;
  tool.Usage = labelTool ? "SmallIsoComponentLabelFilter INPUT OUTPUT [--max-size K | --max-volume V] "
                           "[--select all|islands|holes|L,...] [--background L] [--max-size-of L=K,...] "
                           "[--keep-largest N] [--fully-connected] [--removed-mask FILE] [--stats FILE.json] "
#ifdef SIC_HAVE_VTK
                           "[--surface FILE] [--surface-before FILE] [--render FILE.png] "
#endif
                           "[--memory-limit BYTES] [--no-compression] [--threads N] [--quiet] [--progress-xml] "
                           "[--xml] [--help]"
                         : "SmallIsoComponentFilter INPUT OUTPUT (--isovalue S [--side above|below|both] | --labels "
                           "[--select all|islands|holes|L,...] [--background L] [--max-size-of L=K,...] "
                           "[--keep-largest N]) [--max-size K | --max-volume V] [--fully-connected] "
                           "[--removed-mask FILE] [--stats FILE.json] "
#ifdef SIC_HAVE_VTK
                           "[--surface FILE] [--surface-before FILE] [--render FILE.png] "
#endif
                           "[--memory-limit BYTES] [--no-compression] [--threads N] [--quiet] [--progress-xml] "
                           "[--xml] [--help]";
  tool.Description =
    labelTool
      ? "Removes the small islands and fills the small holes of a label map (a segmentation): each component of a "
        "selected label with at most K voxels (or V mm³) is removed, and each of its voxels takes the label voted by "
        "the labels around the component, so that a speck of one organ inside another becomes the other, not "
        "background. Every other voxel keeps its label. Label maps of any integer pixel type, or float maps of "
        "whole numbers, 2-D or 3-D, in NRRD, NIfTI, MetaImage or any format ITK reads; spacing, origin and "
        "direction are kept."
      : "Removes the small connected components that noise leaves on either side of an isovalue S: specks of voxels "
        ">= S floating outside an object and bubbles of voxels < S inside it. Only the voxels of those components "
        "change, each to a value on the other side of S (the mean of the nearest other-side values along the "
        "axes); every other voxel keeps its value bit for bit, so an isosurface extracted at S afterwards (Marching "
        "Cubes, Slicer's Grayscale Model Maker) has no tiny pieces. Any scalar 2-D or 3-D image ITK reads (NRRD, "
        "NIfTI, MetaImage, PNG, ...) is processed in its own pixel type; spacing, origin and direction are kept. "
        "With --labels it cleans label maps instead.";

  const char * const volumeType = labelTool ? "label" : "scalar";
  tool.Positionals = {
    { "INPUT",
      labelTool ? "The label map to clean, 2-D or 3-D, with pixel type " + sic::SupportedLabelPixelTypes() +
                    " (float32 and float64 holding whole numbers only)."
                : "The image to clean: a scalar image (one value per voxel), 2-D or 3-D, with pixel type " +
                    sic::SupportedPixelTypes() + "; with --labels, a label map (" + sic::SupportedLabelPixelTypes() +
                    ", floats holding whole numbers only).",
      ImageParameter("inputVolume", "Input volume", "input", volumeType) },
    { "OUTPUT",
      "Where to write the cleaned image, with the input's pixel type, in the format its extension names (.nrrd, "
      ".nhdr, .nii, .nii.gz, .mha, .mhd, .png, ...), compressed where the format allows. It must not be the "
      "input.",
      ImageParameter("outputVolume", "Output volume", "output", volumeType) },
  };

  Option isovalue{ "--isovalue",
                   "S",
                   "The isovalue, in the image's intensity units: voxels with a value >= S are above it, all "
                   "others (NaN included) below. Required.",
                   "",
                   Parameter("double", "isovalue", "Isovalue", "Parameters") };
  isovalue.Slicer.Default = "100";
  Option maxSize{ "--max-size",
                  "K",
                  "The largest component removed, in voxels: components of at most K voxels are small. 0 removes "
                  "nothing (unless --max-volume is given).",
                  "20 voxels, unless --max-volume is given",
                  Parameter("integer", "maxSize", "Maximum size (voxels)", "Parameters") };
  maxSize.Slicer.Default = "20";
  maxSize.Slicer.Minimum = "0";
  maxSize.Slicer.Maximum = "1000000000";
  Option maxVolume{ "--max-volume",
                    "V",
                    "The largest component removed, as a physical volume in mm³ (the image's spacing units "
                    "cubed): a component is small when its voxel count times the voxel volume is at most V, so "
                    "K = floor(V / voxel volume). Give --max-size or --max-volume, not both. As Slicer passes "
                    "both, a 0 does not count as given: --max-volume 0 leaves the volume unused, and --max-size 0 "
                    "lets --max-volume decide (in Slicer, set the maximum size to 0 to use the maximum volume).",
                    "unused",
                    Parameter("double", "maxVolume", "Maximum volume (mm³)", "Parameters") };
  maxVolume.Slicer.Default = "0";
  maxVolume.Slicer.Minimum = "0";
  maxVolume.Slicer.Maximum = "1e12";
  maxVolume.Slicer.Step = "0.1";
  Option side{ "--side",
               "above|below|both",
               "Which small components to remove: above (specks of voxels >= S, e.g. outside a dense object), "
               "below (bubbles of voxels < S, e.g. inside it) or both (above first, then below on the result).",
               "both",
               Parameter("string-enumeration", "side", "Side", "Parameters") };
  side.Slicer.Elements = { "above", "below", "both" };
  Option fullyConnected{ "--fully-connected",
                         "",
                         "Connect voxels that share an edge or a corner too, not only a face (26 neighbours in "
                         "3-D and 8 in 2-D, instead of 6 and 4).",
                         "face connectivity",
                         Parameter("boolean", "fullyConnected", "Fully connected", "Parameters") };
  fullyConnected.Slicer.Default = "false";
  Option removedMask{ "--removed-mask",
                      "FILE",
                      labelTool ? "Also write a mask of the removed voxels (uint8: 0 kept, 1 removed), in the format "
                                  "FILE's extension names."
                                : "Also write a mask of the changed voxels (uint8: 0 kept, 1 removed with an above "
                                  "component, 2 removed with a below component; with --labels 1 for every removed "
                                  "voxel), in the format FILE's extension names.",
                      "",
                      ImageParameter("removedMask", "Removed voxels", "output", "label") };
  Option stats{ "--stats",
                "FILE.json",
                labelTool ? "Also write the input's description, the parameters and every statistic as JSON: per "
                            "label (keyed by its id) the components, removed components, removed voxels, voxels "
                            "gained from repairs and component-size histogram ([size, count] pairs); modified and "
                            "unrepairable voxels and seconds."
                          : "Also write the input's description, the parameters and every statistic as JSON: per side "
                            "the components, removed components, removed voxels and component-size histogram ([size, "
                            "count] pairs); modified and unrepairable voxels, seconds and peak extra memory in bytes "
                            "(with --labels, per label instead of per side).",
                "",
                Parameter("file", "statsFile", "Statistics (JSON)", "Input/Output") };
  stats.Slicer.Channel = "output";
  stats.Slicer.FileExtensions = ".json";
  Option memoryLimit{ "--memory-limit",
                      "BYTES",
                      "Filter the image plane by plane along its last axis, holding at most about BYTES of memory "
                      "(a number with an optional suffix K, M, G or T, powers of 1024: 512M, 8G): for volumes "
                      "larger than memory. " +
                        std::string(labelTool ? "The output and mask are exactly those of the in-memory run; the "
                                                "statistics give each label's removed and gained voxels, but not "
                                                "its components and their sizes. "
                                              : "The output, mask and statistics are exactly those of the "
                                                "in-memory run (with --labels, each label's removed and gained "
                                                "voxels, but not its components and their sizes). ") +
                        "Needs MetaImage (.mha, .mhd) or NRRD (.nrrd, .nhdr) input and outputs; the surface options "
                        "and --keep-largest need the whole volume and cannot be combined with it. Without it, the "
                        "tool streams by itself, within three quarters of the available memory, when the input "
                        "would not fit.",
                      "the whole image in memory, unless it does not fit",
                      {} };
  Option noCompression{ "--no-compression",
                        "",
                        "Write the outputs uncompressed (faster for large volumes; .mhd and .nhdr then write .raw "
                        "data files).",
                        "compressed where the format allows",
                        {} };
  Option threads{ "--threads",
                  "N",
                  "Number of ITK work units to use, at most " + std::to_string(sic::MaximumThreads()) +
                    " (ITK's limit); the filter runs at most one thread per core. 0 uses ITK's default (the number "
                    "of cores, or ITK_GLOBAL_DEFAULT_NUMBER_OF_THREADS). The result does not depend on it.",
                  "0",
                  Parameter("integer", "threads", "Threads", "Advanced") };
  threads.Slicer.Minimum = "0";
  threads.Slicer.Maximum = std::to_string(sic::MaximumThreads());
  Option quiet{ "--quiet",
                "",
                "Print neither progress nor the summary; errors are still reported on stderr.",
                "",
                Parameter("boolean", "quiet", "Quiet", "Advanced") };
  Option progressXml{ "--progress-xml",
                      "",
                      "Report progress as 3D Slicer reads it, <filter-start>, <filter-progress> and <filter-end> "
                      "lines on stdout, instead of on stderr. Slicer passes it (a hidden parameter of --xml).",
                      "",
                      Parameter("boolean", "progressXml", "Progress for Slicer", "Advanced") };
  progressXml.Slicer.Default = "true";
  progressXml.Slicer.Hidden = true;
  std::vector<Option> labelOptions = LabelOptions(kind);
  if (labelTool)
  {
    tool.Options = { maxSize, maxVolume };
    tool.Options.insert(tool.Options.end(), labelOptions.begin() + 1, labelOptions.end());
    tool.Options.insert(tool.Options.end(), { fullyConnected, removedMask, stats });
#ifdef SIC_HAVE_VTK
    const std::vector<Option> surfaces = SurfaceOptions(kind);
    tool.Options.insert(tool.Options.end(), surfaces.begin(), surfaces.end());
#endif
    tool.Options.insert(tool.Options.end(), { memoryLimit, noCompression, threads, quiet, progressXml });
    tool.Options.push_back(labelOptions.front());
  }
  else
  {
    tool.Options = { isovalue, maxSize, maxVolume, side };
    tool.Options.insert(tool.Options.end(), labelOptions.begin(), labelOptions.end());
    tool.Options.insert(tool.Options.end(), { fullyConnected, removedMask, stats });
#ifdef SIC_HAVE_VTK
    const std::vector<Option> surfaces = SurfaceOptions(kind);
    tool.Options.insert(tool.Options.end(), surfaces.begin(), surfaces.end());
#endif
    tool.Options.insert(tool.Options.end(), { memoryLimit, noCompression, threads, quiet, progressXml });
  }
  tool.Options.push_back(
    { "--xml", "", "Print the tool's 3D Slicer Execution Model description (XML) and exit.", "", {} });
  tool.Options.push_back({ "--help", "", "Print this help and exit (also -h).", "", {} });
  tool.RepeatableOptions = { "--max-size-of" };

  tool.Epilogue =
    "While it works, the tool shows progress on stderr (a bar on a terminal, a line per\n"
    "stage otherwise), then prints a one-paragraph summary on stdout. The output image,\n"
    "the mask and the statistics appear together, once all of them were written; after\n"
    "a failure none of them is written or changed.\n"
    "\n"
    "Exit status:\n"
    "  0  success\n"
    "  1  the processing failed (e.g. out of memory)\n"
    "  2  a wrong command line, an unreadable or unsupported input, or an output that\n"
    "     cannot be written; one line on stderr says what was wrong and what was expected\n"
    "\n" +
    std::string(labelTool ? "Example: remove the islands and fill the holes of at most 50 voxels of every label,\n"
                            "and of at most 5 voxels of label 7, a small structure:\n"
                            "  SmallIsoComponentLabelFilter seg.nii.gz seg-clean.nii.gz --max-size 50 \\\n"
                            "      --max-size-of 7=5 --stats stats.json\n"
                          : "Example: remove specks and bubbles of at most 20 voxels at isovalue 150, keeping a\n"
                            "mask of the changed voxels and the statistics:\n"
                            "  SmallIsoComponentFilter ct.nrrd ct-clean.nrrd --isovalue 150 --max-size 20 \\\n"
                            "      --removed-mask removed.nrrd --stats stats.json\n"
                            "A label map: SmallIsoComponentFilter seg.nrrd seg-clean.nrrd --labels --max-size 50\n");

  tool.Category = labelTool ? "Segmentation" : "Surface Models";
  tool.Title = labelTool ? "Small Iso Component Label Filter" : "Small Iso Component Filter";
  tool.Version = SIC_VERSION;
  tool.Contributor = "SmallIsoComponent contributors";
  tool.License = "Apache 2.0";
  tool.Acknowledgements = "Built on the Insight Toolkit (ITK).";
  return tool;
}

sic::FilterSettings
ReadSettings(const sic::ToolDescription & tool, const sic::ParsedCommandLine & arguments)
{
  sic::CheckPositionals(tool, arguments);
  sic::FilterSettings settings;
  settings.Input = arguments.Positionals()[0];
  settings.Output = arguments.Positionals()[1];
  settings.Labels = tool.Name == sic::LabelToolName || arguments.Has("--labels");
  if (settings.Labels)
  {
    sic::ReadLabelSettings(arguments, settings);
  }
  else
  {
    sic::RefuseLabelOptions(arguments);
    if (!arguments.Has("--isovalue"))
    {
      throw sic::ToolError("missing --isovalue S; expected the isovalue in the image's intensity units, e.g. "
                           "--isovalue 150 (or --labels for a label map)");
    }
    settings.IsoValue = sic::ParseNumber("--isovalue", arguments.Value("--isovalue"));
  }
  if (arguments.Has("--max-size"))
  {
    settings.MaximumSize = sic::ParseCount("--max-size", arguments.Value("--max-size"));
    settings.MaximumSizeGiven = true;
  }
  if (arguments.Has("--max-volume"))
  {
    const double volume = sic::ParseNumber("--max-volume", arguments.Value("--max-volume"));
    if (volume < 0.0)
    {
      throw sic::ToolError("--max-volume '" + arguments.Value("--max-volume") +
                           "' is negative; expected a volume >= 0 in mm³");
    }
    settings.MaximumVolume = volume;
  }
  if (settings.UsesVolume() && settings.MaximumSizeGiven && settings.MaximumSize > 0)
  {
    throw sic::ToolError("both --max-size (" + arguments.Value("--max-size") + " voxels) and --max-volume (" +
                         arguments.Value("--max-volume") +
                         " mm³) are given; expected one of them (or set the other to 0)");
  }
  if (arguments.Has("--side"))
  {
    settings.Side = sic::ParseChoice("--side", arguments.Value("--side"), { "above", "below", "both" });
  }
  settings.FullyConnected = arguments.Has("--fully-connected");
  settings.RemovedMask = arguments.Value("--removed-mask");
  settings.Stats = arguments.Value("--stats");
#ifdef SIC_HAVE_VTK
  settings.Surface = arguments.Value("--surface");
  settings.SurfaceBefore = arguments.Value("--surface-before");
  settings.Render = arguments.Value("--render");
#endif
  sic::CheckPathsNotEmpty(arguments, { "--removed-mask", "--stats", "--surface", "--surface-before", "--render" });
  settings.Threads = sic::ParseThreads(arguments);
  if (arguments.Has("--memory-limit"))
  {
    settings.MemoryLimit = sic::ParseByteCount(arguments.Value("--memory-limit"), "--memory-limit");
  }
  settings.Compress = !arguments.Has("--no-compression");
  settings.Quiet = arguments.Has("--quiet");
  settings.ProgressXml = arguments.Has("--progress-xml");
  return settings;
}

itk::SmallIsoComponentEnums::Side
SideOf(const std::string & side)
{
  using SideEnum = itk::SmallIsoComponentEnums::Side;
  return side == "above" ? SideEnum::Above : side == "below" ? SideEnum::Below : SideEnum::Both;
}

template <typename TFilter>
sic::SideReport
SideStatistics(const TFilter & filter, itk::SmallIsoComponentEnums::Side side)
{
  sic::SideReport report;
  report.Components = filter.GetNumberOfComponents(side);
  report.RemovedComponents = filter.GetNumberOfRemovedComponents(side);
  report.RemovedVoxels = filter.GetNumberOfRemovedVoxels(side);
  for (const auto & [size, count] : filter.GetComponentSizeHistogram(side))
  {
    report.Histogram[size] = count;
  }
  return report;
}

using sic::StagedPaths;

#ifdef SIC_HAVE_VTK
/** The isosurfaces of a run of the filter, kept in index coordinates until the removed
 * triangles are known, then moved to physical coordinates and written or rendered. */
template <typename TImage, typename TFilter>
void
WriteSurfaces(const sic::FilterSettings &  settings,
              const StagedPaths &          staged,
              vtkSmartPointer<vtkPolyData> before,
              TFilter &                    filter,
              sic::ProgressReporter &      progress,
              sic::FilterReport &          report)
{
  const TImage *               output = filter.GetOutput();
  const sic::SurfaceGeometry   geometry = sic::SurfaceGeometryOf(*output);
  vtkSmartPointer<vtkPolyData> after;
  if (!settings.Surface.empty() || !settings.Render.empty())
  {
    progress.Stage("extracting the filtered isosurface", 0.85, 0.88);
    after = sic::ExtractIsosurface(sic::SurfaceGridOf(*output), settings.IsoValue);
    report.SurfacePiecesAfter = sic::CountSurfacePieces(*after);
  }
  sic::RemovedTriangles removed;
  if (before)
  {
    report.SurfacePiecesBefore = sic::CountSurfacePieces(*before);
    const auto & size = output->GetBufferedRegion().GetSize();
    removed = sic::TrianglesOfChangedCells(
      *before, filter.GetRemovedMask()->GetBufferPointer(), { { size[0], size[1], size[2] } }, true);
    report.RemovedSurfacePieces = sic::CountSurfacePieces(*removed.All);
  }
  if (!settings.Render.empty())
  {
    for (vtkPolyData * surface : { removed.Specks.Get(), removed.Bubbles.Get() })
    {
      sic::TransformToPhysical(*surface, geometry);
    }
  }
  for (vtkPolyData * surface : { before.Get(), after.Get() })
  {
    if (surface != nullptr)
    {
      sic::TransformToPhysical(*surface, geometry);
    }
  }
  if (!settings.SurfaceBefore.empty())
  {
    progress.Stage("writing " + settings.SurfaceBefore, 0.88, 0.9);
    sic::WriteSurface(*before, staged.SurfaceBefore, settings.SurfaceBefore, "input's isosurface");
  }
  if (!settings.Surface.empty())
  {
    progress.Stage("writing " + settings.Surface, 0.9, 0.92);
    sic::WriteSurface(*after, staged.Surface, settings.Surface, "isosurface");
  }
  if (!settings.Render.empty())
  {
    progress.Stage("rendering " + settings.Render, 0.92, 0.95);
    const auto pieces = [](std::uint64_t count) { return std::to_string(count) + (count == 1 ? " piece" : " pieces"); };
    sic::RenderScene scene;
    scene.Before = before;
    scene.After = after;
    scene.RemovedSpecks = removed.Specks;
    scene.RemovedBubbles = removed.Bubbles;
    scene.Labels = { "Original: " + pieces(*report.SurfacePiecesBefore),
                     "Filtered: " + pieces(*report.SurfacePiecesAfter),
                     "Removed: " + pieces(*report.RemovedSurfacePieces) + " (specks red, bubbles blue)",
                     "Filtered + removed: " + std::to_string(*report.SurfacePiecesAfter) + " + " +
                       pieces(*report.RemovedSurfacePieces) };
    const sic::HeadlessDisplay display;
    sic::RenderPanels(scene, staged.Render, settings.Render);
  }
}
#endif

template <typename TImage>
sic::FilterReport
FilterImage(const sic::FilterSettings & settings, const StagedPaths & staged, sic::ProgressReporter & progress)
{
  using FilterType = itk::SmallIsoComponentImageFilter<TImage>;

  progress.Stage("reading " + settings.Input, 0.0, 0.1);
  typename TImage::Pointer image = sic::ReadImage<TImage>(settings.Input, "input", progress.Observer());
#ifdef SIC_HAVE_VTK
  // The input's surface is taken before filtering in place overwrites the input.
  vtkSmartPointer<vtkPolyData> before;
  if constexpr (TImage::ImageDimension == 3)
  {
    if (!settings.SurfaceBefore.empty() || !settings.Render.empty())
    {
      progress.Stage("extracting the input's isosurface", 0.1, 0.12);
      before = sic::ExtractIsosurface(sic::SurfaceGridOf(*image), settings.IsoValue);
    }
  }
#endif

  auto filter = FilterType::New();
  filter->SetInput(image);
  // The input is not needed afterwards: filtering in place saves a copy of the volume.
  filter->InPlaceOn();
  filter->SetIsoValue(settings.IsoValue);
  if (settings.UsesVolume())
  {
    filter->SetMaximumComponentVolume(*settings.MaximumVolume);
  }
  else
  {
    filter->SetMaximumComponentSize(settings.MaximumSize);
  }
  filter->SetSide(SideOf(settings.Side));
  filter->SetFullyConnected(settings.FullyConnected);
  // The mask is a second full-size image: made only for the mask output and for the
  // surfaces of the removed pieces, which are cut from the input's surface with it.
  bool needsMask = !settings.RemovedMask.empty();
#ifdef SIC_HAVE_VTK
  needsMask = needsMask || before != nullptr;
#endif
  filter->SetGenerateRemovedMask(needsMask);
  if (settings.Threads > 0)
  {
    filter->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(settings.Threads));
  }
  filter->AddObserver(itk::ProgressEvent(), progress.Observer());
  image = nullptr;

  progress.Stage("removing small components", 0.1, 0.85);
  const auto start = std::chrono::steady_clock::now();
  filter->Update();
  const auto stop = std::chrono::steady_clock::now();

  sic::FilterReport report;
#ifdef SIC_HAVE_VTK
  if constexpr (TImage::ImageDimension == 3)
  {
    WriteSurfaces<TImage>(settings, staged, before, *filter, progress, report);
  }
#endif

  progress.Stage("writing " + settings.Output, 0.95, settings.RemovedMask.empty() ? 1.0 : 0.98);
  sic::WriteImage(
    filter->GetOutput(), staged.Image, settings.Output, "output image", progress.Observer(), settings.Compress);
  if (!settings.RemovedMask.empty())
  {
    progress.Stage("writing " + settings.RemovedMask, 0.98, 1.0);
    sic::WriteImage(filter->GetRemovedMask(),
                    staged.RemovedMask,
                    settings.RemovedMask,
                    "removed-voxel mask",
                    progress.Observer(),
                    settings.Compress);
  }

  report.EffectiveMaximumSize = filter->GetEffectiveMaximumComponentSize();
  report.Threads = itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads();
  report.WorkUnits = filter->GetNumberOfWorkUnits();
  report.Above = SideStatistics(*filter, itk::SmallIsoComponentEnums::Side::Above);
  report.Below = SideStatistics(*filter, itk::SmallIsoComponentEnums::Side::Below);
  report.ModifiedVoxels = filter->GetNumberOfModifiedVoxels();
  report.UnrepairableVoxels = filter->GetNumberOfUnrepairableVoxels();
  report.PeakExtraBytes = filter->GetPeakExtraMemoryInBytes();
  report.SlabPlanes = filter->GetSweptSlabThickness();
  report.FilterSeconds = std::chrono::duration<double>(stop - start).count();
  return report;
}

/** The memory limit to stream under: --memory-limit, or three quarters of the available memory when
 * the input would not fit in it and every file streams; 0 to filter in memory. */
std::uint64_t
StreamingLimit(const sic::FilterSettings & settings, const sic::ScalarImageInfo & info)
{
  const bool streamable = sic::IsStreamableImageFile(settings.Input) && sic::IsStreamableImageFile(settings.Output) &&
                          (settings.RemovedMask.empty() || sic::IsStreamableImageFile(settings.RemovedMask));
  const bool surfaces = !settings.Surface.empty() || !settings.SurfaceBefore.empty() || !settings.Render.empty();
  if (settings.MemoryLimit > 0)
  {
    if (!streamable)
    {
      throw sic::ToolError("--memory-limit needs an input and outputs that stream: " + sic::StreamableFormats());
    }
    if (surfaces)
    {
      throw sic::ToolError("--surface, --surface-before and --render need the whole volume in memory; they cannot be "
                           "combined with --memory-limit");
    }
    if (settings.KeepLargest > 0)
    {
      throw sic::ToolError("--keep-largest needs every component whole, so the whole volume in memory; it cannot be "
                           "combined with --memory-limit");
    }
    return settings.MemoryLimit;
  }
  // In memory the image is filtered in place: its voxels, the mask if asked for, and a fraction of a byte per
  // voxel beyond (about two bytes for a label map).
  std::uint64_t voxels = 1;
  for (const auto size : info.Size)
  {
    voxels *= size;
  }
  sic::VolumeGeometry geometry;
  geometry.ComponentType = info.ComponentType;
  const std::uint64_t needed = voxels * geometry.PixelBytes() + (settings.RemovedMask.empty() ? 0 : voxels) +
                               (settings.Labels ? 2 * voxels : voxels / 2);
  const std::uint64_t available = sic::AvailableMemoryBytes();
  if (available > 0 && needed > available && streamable && !surfaces && settings.KeepLargest == 0)
  {
    return available / 4 * 3;
  }
  return 0;
}

/** How a streamed run fits its limit: its slabs, and the figures a refusal gives. */
struct StreamingPlan
{
  std::uint64_t SlabPlanes{ 0 };
  /** The process itself, with its threads and buffers. */
  std::uint64_t ProcessBytes{ 0 };
  /** The most the run may hold: the window's bound with slabs of one plane. */
  std::uint64_t BoundBytes{ 0 };
};

/** The error for a limit too small for this image, saying \a why, the bound and what to change. The figures
 * have a MiB to spare: the process's own size varies from run to run by a fraction of one. */
sic::ToolError
LimitTooSmall(const sic::FilterSettings & settings,
              std::uint64_t               limit,
              std::uint64_t               maximumSize,
              const StreamingPlan &       plan,
              const std::string &         why)
{
  return sic::ToolError(sic::MemoryLimitText(settings, limit) + " is too small to stream this image with K = " +
                        std::to_string(maximumSize) + ": " + why + " and at most about " +
                        std::to_string((plan.BoundBytes >> 20) + 2) + " MiB; expected a larger limit or a smaller K");
}

/** The slabs to stream the input in within \a limit bytes. The window's bound holds 2K planes beyond each slab,
 * where the components that span so many planes are rare: when it does not fit, the run is tried in thin slabs,
 * which leave most of the limit to the window the data really need, and stops if it passes the limit. */
StreamingPlan
PlanStreaming(const sic::FilterSettings & settings,
              const sic::VolumeGeometry & geometry,
              std::uint64_t               maximumSize,
              std::uint64_t               limit)
{
  // The plan holds for any data: it counts the input's scanline runs and their components first, reading it once
  // more.
  const std::uint64_t labelBytes =
    sic::MostLabelBytesInAPlane(settings.Input, settings.IsoValue, settings.FullyConnected, maximumSize);
  const unsigned int workUnits = sic::StreamingWorkUnits(settings);
  // The working memory and the thickest slab within a budget, for a window that holds components of \a size voxels.
  const auto workingBytes = [&](std::uint64_t size, std::uint64_t slabPlanes) {
    return sic::StreamingWorkingBytes(geometry, labelBytes, size, slabPlanes, workUnits);
  };
  const auto thickestSlab = [&](std::uint64_t size, std::uint64_t budget) {
    return sic::SlabPlanesForBudget(geometry, labelBytes, size, budget, workUnits);
  };

  StreamingPlan plan;
  plan.ProcessBytes = sic::StreamingProcessBytes();
  const std::uint64_t boundWindow = workingBytes(maximumSize, 1);
  const std::uint64_t shallowestWindow = workingBytes(0, 1);
  const std::uint64_t budget = limit > plan.ProcessBytes ? limit - plan.ProcessBytes : 0;
  plan.BoundBytes = plan.ProcessBytes + boundWindow;
  if (boundWindow <= budget)
  {
    plan.SlabPlanes = thickestSlab(maximumSize, budget);
  }
  else if (shallowestWindow <= budget)
  {
    plan.SlabPlanes = std::max<std::uint64_t>(1, thickestSlab(0, budget / 4));
  }
  else
  {
    throw LimitTooSmall(settings,
                        limit,
                        maximumSize,
                        plan,
                        "it needs about " + std::to_string(((plan.ProcessBytes + shallowestWindow) >> 20) + 2) +
                          " MiB with the shallowest window (the process itself " +
                          std::to_string((plan.ProcessBytes >> 20) + 1) + " MiB, a slab of one plane " +
                          std::to_string((shallowestWindow >> 20) + 1) + " MiB)");
  }
  return plan;
}

/** The streaming mode: the image read, filtered and written plane by plane within \a limit bytes. */
sic::FilterReport
FilterStreamed(const sic::FilterSettings & settings,
               const StagedPaths &         staged,
               std::uint64_t               limit,
               sic::ProgressReporter &     progress)
{
  sic::PlaneReader            input(settings.Input, "input");
  const sic::VolumeGeometry & geometry = input.GetGeometry();
  std::uint64_t               maximumSize = settings.MaximumSize;
  if (settings.UsesVolume())
  {
    double voxelVolume = 1.0;
    for (const double spacing : geometry.Spacing)
    {
      voxelVolume *= spacing;
    }
    maximumSize =
      itk::SmallIsoComponentDetail::ComponentRules::MaximumSizeForVolume(*settings.MaximumVolume, voxelVolume);
  }
  const StreamingPlan plan = PlanStreaming(settings, geometry, maximumSize, limit);
  if (!settings.Compress)
  {
    // Uncompressed outputs have a known size: make sure the disk has room before the long run.
    std::uint64_t bytes = geometry.PlaneVoxels() * geometry.Planes() * geometry.PixelBytes();
    bytes += settings.RemovedMask.empty() ? 0 : geometry.PlaneVoxels() * geometry.Planes();
    std::error_code error;
    const auto      space = std::filesystem::space(std::filesystem::path(staged.Image).parent_path(), error);
    if (!error && space.available < bytes)
    {
      throw sic::ToolError("cannot write the outputs: they take " + std::to_string(bytes >> 20) +
                           " MiB and the disk has " + std::to_string(space.available >> 20) + " MiB free");
    }
  }
  progress.Stage("removing small components plane by plane", 0.0, 1.0);
  sic::FilterReport report;
  try
  {
    sic::RunStreamedFilter(
      input,
      settings,
      { staged.Image, staged.RemovedMask },
      maximumSize,
      plan.SlabPlanes,
      limit,
      [&](double done) { progress.Update(done); },
      report);
  }
  catch (const sic::MemoryLimitPassed & passed)
  {
    throw LimitTooSmall(settings,
                        limit,
                        maximumSize,
                        plan,
                        "the run passed it after " + std::to_string(passed.Planes) + " of " +
                          std::to_string(geometry.Planes()) + " planes, holding " +
                          std::to_string(passed.PeakBytes >> 20) + " MiB (the process itself " +
                          std::to_string((plan.ProcessBytes >> 20) + 1) + " MiB), so it needs more");
  }
  report.Threads = itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads();
  report.MemoryLimit = limit;
  return report;
}

int
Run(const std::string & toolName, const sic::FilterSettings & settings)
{
  const auto                 start = std::chrono::steady_clock::now();
  const sic::ScalarImageInfo info = settings.Labels ? sic::ReadLabelImageInfo(settings.Input, "input")
                                                    : sic::ReadScalarImageInfo(settings.Input, "input");

  // Every output is checked, and its staging place made, before the work starts.
  sic::StagedOutputs outputs;
  outputs.Protect(info.Files, "the input image");
  StagedPaths staged;
  staged.Image = outputs.Stage(settings.Output, "output image");
  sic::CheckImageFileFormat(settings.Output, "output image", info.Dimension);
  if (!settings.RemovedMask.empty())
  {
    staged.RemovedMask = outputs.Stage(settings.RemovedMask, "removed-voxel mask");
    sic::CheckImageFileFormat(settings.RemovedMask, "removed-voxel mask", info.Dimension);
  }
  const std::string stagedStats = settings.Stats.empty() ? "" : outputs.Stage(settings.Stats, "statistics");
#ifdef SIC_HAVE_VTK
  const bool surfaces = !settings.Surface.empty() || !settings.SurfaceBefore.empty() || !settings.Render.empty();
  if (surfaces && info.Dimension != 3)
  {
    throw sic::ToolError("--surface, --surface-before and --render need a 3-D image and '" + settings.Input + "' is " +
                         std::to_string(info.Dimension) + "-D; expected a volume");
  }
  for (const auto & [path, stagedPath, what] :
       { std::make_tuple(&settings.Surface, &staged.Surface, settings.Labels ? "label surfaces" : "isosurface"),
         std::make_tuple(&settings.SurfaceBefore,
                         &staged.SurfaceBefore,
                         settings.Labels ? "input's label surfaces" : "input's isosurface") })
  {
    if (!path->empty())
    {
      sic::CheckSurfaceFileFormat(*path, what);
      *stagedPath = outputs.Stage(*path, what);
    }
  }
  if (!settings.Render.empty())
  {
    sic::CheckPngFileName(settings.Render, "rendering");
    staged.Render = outputs.Stage(settings.Render, "rendering");
    sic::HeadlessDisplay::CheckAvailable();
  }
#endif

  if (settings.Threads > 0)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(static_cast<itk::ThreadIdType>(settings.Threads));
  }
  std::ostringstream comment;
  comment << "Removing components of at most " << (settings.UsesVolume() ? "the maximum volume" : "K voxels");
  if (settings.Labels)
  {
    comment << " from a label map";
  }
  else
  {
    comment << " at isovalue " << settings.IsoValue;
  }
  sic::ProgressReporter progress(settings.Quiet, settings.ProgressXml, toolName, comment.str());
  sic::FilterReport     report;
  const std::uint64_t   limit = StreamingLimit(settings, info);
  if (settings.Labels)
  {
    report = limit > 0 ? sic::FilterLabelMapStreamed(settings, info, staged, limit, progress)
                       : sic::FilterLabelMap(settings, info, staged, progress);
  }
  else if (limit > 0)
  {
    report = FilterStreamed(settings, staged, limit, progress);
  }
  else
  {
    report = sic::DispatchScalarImage(
      info, [&](auto tag) { return FilterImage<typename decltype(tag)::ImageType>(settings, staged, progress); });
  }
  report.PeakResidentBytes = sic::PeakResidentBytes();
  report.Input = info;
  report.TotalSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (!stagedStats.empty())
  {
    std::ostringstream json;
    sic::WriteStatisticsJson(json, toolName, SIC_VERSION, settings, report);
    sic::WriteTextFile(stagedStats, settings.Stats, "statistics", json.str());
  }
  outputs.Commit();
  progress.Finish();
  if (!settings.Quiet)
  {
    sic::WriteSummary(std::cout, settings, report);
  }
  return sic::ExitSuccess;
}
} // namespace

namespace sic
{
int
FilterToolMain(FilterTool kind, int argc, char * argv[])
{
  const ToolDescription tool = DescribeTool(kind);
  return ToolMain(tool, argc, argv, [&tool](const ParsedCommandLine & arguments) {
    return Run(tool.Name, ReadSettings(tool, arguments));
  });
}
} // namespace sic
