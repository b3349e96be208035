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
#include "sicFilterReport.h"

#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

namespace sic
{
namespace
{
using Json = nlohmann::ordered_json;

/** [size, count] pairs. */
Json
HistogramJson(const std::map<std::uint64_t, std::uint64_t> & histogram)
{
  Json pairs = Json::array();
  for (const auto & [size, count] : histogram)
  {
    pairs.push_back({ size, count });
  }
  return pairs;
}

Json
SideJson(const SideReport & side)
{
  return { { "components", side.Components },
           { "removed_components", side.RemovedComponents },
           { "removed_voxels", side.RemovedVoxels },
           { "size_histogram", HistogramJson(side.Histogram) } };
}

/** Each label's statistics, keyed by its id: a JSON key is a string, which holds any id exactly. */
Json
LabelsJson(const FilterReport & report)
{
  Json labels = Json::object();
  for (const auto & [id, label] : report.Labels)
  {
    // A streamed run does not count components: one may span more planes than any window holds.
    const auto counted = [&report](Json value) { return report.Streaming ? Json() : value; };
    labels[id] = { { "components", counted(label.Components) },
                   { "removed_components", counted(label.RemovedComponents) },
                   { "removed_voxels", label.RemovedVoxels },
                   { "gained_voxels", label.GainedVoxels },
                   { "size_histogram", counted(HistogramJson(label.Histogram)) } };
    for (const auto & [key, pieces] : { std::make_pair("surface_components_before", &label.SurfacePiecesBefore),
                                        std::make_pair("surface_components_after", &label.SurfacePiecesAfter),
                                        std::make_pair("removed_surface_components", &label.RemovedSurfacePieces) })
    {
      if (*pieces)
      {
        labels[id][key] = **pieces;
      }
    }
  }
  return labels;
}

/** The parameters of a label map's run, its label ids as strings as in LabelsJson(). */
void
AddLabelParameters(Json & parameters, const FilterSettings & settings)
{
  parameters["selection"] = settings.Selection;
  if (settings.Selection == "listed")
  {
    parameters["selected_labels"] = settings.SelectedLabels;
  }
  parameters["background"] = settings.Background;
  Json sizes = Json::object();
  for (const auto & [id, size] : settings.LabelMaximumSizes)
  {
    sizes[id] = size;
  }
  parameters["max_size_of"] = std::move(sizes);
  parameters["keep_largest"] = settings.KeepLargest;
}

std::uint64_t
Sum(const FilterReport & report, std::uint64_t SideReport::*member)
{
  std::uint64_t sum = 0;
  for (const auto & entry : report.Labels)
  {
    sum += entry.second.*member;
  }
  return sum;
}

double
VoxelVolume(const ScalarImageInfo & info)
{
  double volume = 1.0;
  for (const double spacing : info.Spacing)
  {
    volume *= spacing;
  }
  return volume;
}
} // namespace

void
WriteSummary(std::ostream & out, const FilterSettings & settings, const FilterReport & report)
{
  std::ostringstream text;
  if (settings.Labels)
  {
    text << "Label map of " << report.Labels.size() << (report.Labels.size() == 1 ? " label" : " labels");
  }
  else
  {
    text << "Isovalue " << settings.IsoValue;
  }
  text << ", K = " << report.EffectiveMaximumSize << " voxels";
  if (settings.UsesVolume())
  {
    text << " (from --max-volume " << *settings.MaximumVolume << " mm³, " << VoxelVolume(report.Input)
         << " mm³ per voxel)";
  }
  if (settings.Labels)
  {
    text << (settings.LabelMaximumSizes.empty() ? "" : " (some labels their own)") << ", selection "
         << settings.Selection << ", " << (settings.FullyConnected ? "full" : "face") << " connectivity: removed ";
    if (!report.Streaming)
    {
      text << Sum(report, &SideReport::RemovedComponents) << " of " << Sum(report, &SideReport::Components)
           << " components (";
    }
    text << Sum(report, &SideReport::RemovedVoxels) << (report.Streaming ? " voxels; " : " voxels); ");
  }
  else
  {
    text << ", side " << settings.Side << ", " << (settings.FullyConnected ? "full" : "face") << " connectivity: ";
    text << "removed " << report.Above.RemovedComponents << " of " << report.Above.Components << " above components ("
         << report.Above.RemovedVoxels << " voxels) and " << report.Below.RemovedComponents << " of "
         << report.Below.Components << " below components (" << report.Below.RemovedVoxels << " voxels); ";
  }
  text << report.ModifiedVoxels << " voxels modified, " << report.UnrepairableVoxels << " unrepairable. ";
  if (report.SurfacePiecesBefore || report.SurfacePiecesAfter)
  {
    text << (settings.Labels ? "Label surface pieces:" : "Isosurface pieces:");
    if (report.SurfacePiecesBefore)
    {
      text << " " << *report.SurfacePiecesBefore << " before";
    }
    if (report.SurfacePiecesAfter)
    {
      text << (report.SurfacePiecesBefore ? ", " : " ") << *report.SurfacePiecesAfter << " after";
    }
    if (report.RemovedSurfacePieces)
    {
      text << " (" << *report.RemovedSurfacePieces << " removed)";
    }
    text << ". ";
  }
  if (settings.Labels && (report.SurfacePiecesBefore || report.SurfacePiecesAfter))
  {
    text << "Surface pieces per label (before -> after):";
    const auto count = [](const std::optional<std::uint64_t> & pieces) {
      return pieces ? std::to_string(*pieces) : std::string("-");
    };
    for (const auto & [id, label] : report.Labels)
    {
      if (label.SurfacePiecesBefore || label.SurfacePiecesAfter)
      {
        text << " " << id << ": " << count(label.SurfacePiecesBefore) << " -> " << count(label.SurfacePiecesAfter)
             << ";";
      }
    }
    text << " ";
  }
  text << std::fixed << std::setprecision(3) << "Filter " << report.FilterSeconds << " s, total " << report.TotalSeconds
       << " s, " << report.Threads << (report.Threads == 1 ? " thread (" : " threads (") << report.WorkUnits
       << (report.WorkUnits == 1 ? " work unit)." : " work units).");
  const auto megabytes = [](std::uint64_t bytes) { return std::to_string((bytes + (1 << 19)) >> 20) + " MiB"; };
  if (report.Streaming)
  {
    text << " Streamed in slabs of " << report.SlabPlanes << (report.SlabPlanes == 1 ? " plane" : " planes")
         << " (reading " << report.ReadSeconds << " s, writing " << report.WriteSeconds << " s)";
    if (report.MemoryLimit > 0)
    {
      text << " under a memory limit of " << megabytes(report.MemoryLimit);
    }
    text << ".";
  }
  else if (report.SlabPlanes > 0)
  {
    text << " Swept in memory in slabs of " << report.SlabPlanes << (report.SlabPlanes == 1 ? " plane." : " planes.");
  }
  if (report.PeakResidentBytes > 0)
  {
    text << " Peak memory " << megabytes(report.PeakResidentBytes) << ".";
  }
  out << text.str() << std::endl;
}

void
WriteStatisticsJson(std::ostream &         out,
                    const std::string &    toolName,
                    const std::string &    version,
                    const FilterSettings & settings,
                    const FilterReport &   report)
{
  Json input = { { "path", settings.Input },
                 { "pixel_type", PixelTypeName(report.Input.ComponentType) },
                 { "dimension", report.Input.Dimension },
                 { "size", report.Input.Size },
                 { "spacing", report.Input.Spacing },
                 { "origin", report.Input.Origin },
                 { "voxel_volume", VoxelVolume(report.Input) } };

  Json outputs = { { "image", settings.Output },
                   { "removed_mask", settings.RemovedMask.empty() ? Json() : Json(settings.RemovedMask) },
                   { "stats", settings.Stats } };
  for (const auto & [key, path] : { std::make_pair("surface", &settings.Surface),
                                    std::make_pair("surface_before", &settings.SurfaceBefore),
                                    std::make_pair("render", &settings.Render) })
  {
    if (!path->empty())
    {
      outputs[key] = *path;
    }
  }

  Json parameters = settings.Labels ? Json{ { "labels", true } } : Json{ { "isovalue", settings.IsoValue } };
  parameters["max_size"] = settings.UsesVolume() ? Json() : Json(settings.MaximumSize);
  if (settings.MaximumVolume)
  {
    parameters["max_volume"] = *settings.MaximumVolume;
  }
  parameters["effective_max_size"] = report.EffectiveMaximumSize;
  if (settings.Labels)
  {
    AddLabelParameters(parameters, settings);
  }
  else
  {
    parameters["side"] = settings.Side;
  }
  parameters["connectivity"] = settings.FullyConnected ? "full" : "face";
  parameters["threads"] = report.Threads;
  parameters["work_units"] = report.WorkUnits;

  Json statistics = settings.Labels ? Json{ { "labels", LabelsJson(report) } }
                                    : Json{ { "above", SideJson(report.Above) }, { "below", SideJson(report.Below) } };
  statistics["modified_voxels"] = report.ModifiedVoxels;
  statistics["unrepairable_voxels"] = report.UnrepairableVoxels;
  statistics["seconds"] = report.FilterSeconds;
  statistics["total_seconds"] = report.TotalSeconds;
  // The scalar engine's memory figure; the label filter does not report one.
  if (!settings.Labels)
  {
    statistics["peak_extra_bytes"] = report.PeakExtraBytes;
  }
  statistics["mode"] = report.Streaming ? "streaming" : "in-memory";
  statistics["memory_limit_bytes"] = report.MemoryLimit > 0 ? Json(report.MemoryLimit) : Json();
  statistics["slab_planes"] = report.SlabPlanes;
  if (report.Streaming)
  {
    statistics["read_seconds"] = report.ReadSeconds;
    statistics["write_seconds"] = report.WriteSeconds;
  }
  statistics["peak_resident_bytes"] = report.PeakResidentBytes;
  for (const auto & [key, pieces] : { std::make_pair("surface_components_before", &report.SurfacePiecesBefore),
                                      std::make_pair("surface_components_after", &report.SurfacePiecesAfter),
                                      std::make_pair("removed_surface_components", &report.RemovedSurfacePieces) })
  {
    if (*pieces)
    {
      statistics[key] = **pieces;
    }
  }

  const Json document = { { "tool", toolName },
                          { "version", version },
                          { "input", std::move(input) },
                          { "outputs", std::move(outputs) },
                          { "parameters", std::move(parameters) },
                          { "statistics", std::move(statistics) } };
  // NaN and infinities become null; bytes of a path that are not UTF-8 become U+FFFD, so the
  // file stays valid JSON rather than the run failing after its work is done.
  out << document.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
}
} // namespace sic
