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
#include "sicJsonWriter.h"

#include <iomanip>
#include <sstream>

namespace sic
{
namespace
{
void
WriteSide(JsonWriter & json, const SideReport & side)
{
  json.BeginObject();
  json.Key("components").Number(side.Components);
  json.Key("removed_components").Number(side.RemovedComponents);
  json.Key("removed_voxels").Number(side.RemovedVoxels);
  json.Key("size_histogram").BeginArray();
  for (const auto & [size, count] : side.Histogram)
  {
    json.BeginArray().Number(size).Number(count).EndArray();
  }
  json.EndArray();
  json.EndObject();
}

template <typename T>
void
WriteArray(JsonWriter & json, const std::vector<T> & values)
{
  json.BeginArray();
  for (const T value : values)
  {
    json.Number(value);
  }
  json.EndArray();
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
  text << "Isovalue " << settings.IsoValue << ", K = " << report.EffectiveMaximumSize << " voxels";
  if (settings.UsesVolume())
  {
    text << " (from --max-volume " << *settings.MaximumVolume << " mm³, " << VoxelVolume(report.Input)
         << " mm³ per voxel)";
  }
  text << ", side " << settings.Side << ", " << (settings.FullyConnected ? "full" : "face") << " connectivity: ";
  text << "removed " << report.Above.RemovedComponents << " of " << report.Above.Components << " above components ("
       << report.Above.RemovedVoxels << " voxels) and " << report.Below.RemovedComponents << " of "
       << report.Below.Components << " below components (" << report.Below.RemovedVoxels << " voxels); "
       << report.ModifiedVoxels << " voxels modified, " << report.UnrepairableVoxels << " unrepairable. ";
  if (report.SurfacePiecesBefore || report.SurfacePiecesAfter)
  {
    text << "Isosurface pieces:";
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
  JsonWriter json(out);
  json.BeginObject();
  json.Key("tool").String(toolName);
  json.Key("version").String(version);

  json.Key("input").BeginObject();
  json.Key("path").String(settings.Input);
  json.Key("pixel_type").String(PixelTypeName(report.Input.ComponentType));
  json.Key("dimension").Number(static_cast<std::uint64_t>(report.Input.Dimension));
  json.Key("size");
  WriteArray(json, report.Input.Size);
  json.Key("spacing");
  WriteArray(json, report.Input.Spacing);
  json.Key("origin");
  WriteArray(json, report.Input.Origin);
  json.Key("voxel_volume").Number(VoxelVolume(report.Input));
  json.EndObject();

  json.Key("outputs").BeginObject();
  json.Key("image").String(settings.Output);
  json.Key("removed_mask");
  if (settings.RemovedMask.empty())
  {
    json.Null();
  }
  else
  {
    json.String(settings.RemovedMask);
  }
  json.Key("stats").String(settings.Stats);
  for (const auto & [key, path] : { std::make_pair("surface", &settings.Surface),
                                    std::make_pair("surface_before", &settings.SurfaceBefore),
                                    std::make_pair("render", &settings.Render) })
  {
    if (!path->empty())
    {
      json.Key(key).String(*path);
    }
  }
  json.EndObject();

  json.Key("parameters").BeginObject();
  json.Key("isovalue").Number(settings.IsoValue);
  json.Key("max_size");
  if (settings.UsesVolume())
  {
    json.Null();
  }
  else
  {
    json.Number(settings.MaximumSize);
  }
  if (settings.MaximumVolume)
  {
    json.Key("max_volume").Number(*settings.MaximumVolume);
  }
  json.Key("effective_max_size").Number(report.EffectiveMaximumSize);
  json.Key("side").String(settings.Side);
  json.Key("connectivity").String(settings.FullyConnected ? "full" : "face");
  json.Key("threads").Number(report.Threads);
  json.Key("work_units").Number(report.WorkUnits);
  json.EndObject();

  json.Key("statistics").BeginObject();
  json.Key("above");
  WriteSide(json, report.Above);
  json.Key("below");
  WriteSide(json, report.Below);
  json.Key("modified_voxels").Number(report.ModifiedVoxels);
  json.Key("unrepairable_voxels").Number(report.UnrepairableVoxels);
  json.Key("seconds").Number(report.FilterSeconds);
  json.Key("total_seconds").Number(report.TotalSeconds);
  json.Key("peak_extra_bytes").Number(report.PeakExtraBytes);
  json.Key("mode").String(report.Streaming ? "streaming" : "in-memory");
  json.Key("memory_limit_bytes");
  if (report.MemoryLimit > 0)
  {
    json.Number(report.MemoryLimit);
  }
  else
  {
    json.Null();
  }
  json.Key("slab_planes").Number(report.SlabPlanes);
  if (report.Streaming)
  {
    json.Key("read_seconds").Number(report.ReadSeconds);
    json.Key("write_seconds").Number(report.WriteSeconds);
  }
  json.Key("peak_resident_bytes").Number(report.PeakResidentBytes);
  for (const auto & [key, pieces] : { std::make_pair("surface_components_before", &report.SurfacePiecesBefore),
                                      std::make_pair("surface_components_after", &report.SurfacePiecesAfter),
                                      std::make_pair("removed_surface_components", &report.RemovedSurfacePieces) })
  {
    if (*pieces)
    {
      json.Key(key).Number(**pieces);
    }
  }
  json.EndObject();

  json.EndObject();
  json.Finish();
}
} // namespace sic
