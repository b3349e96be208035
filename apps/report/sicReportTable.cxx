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
#include "sicReportTable.h"

#include <charconv>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace sic
{
namespace
{
std::string
PercentText(std::uint64_t removed, std::uint64_t total)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", Percent(removed, total));
  return text;
}

/** A CSV field, quoted when it holds a comma, a quote or a line break. */
std::string
CsvField(const std::string & text)
{
  if (text.find_first_of(",\"\r\n") == std::string::npos)
  {
    return text;
  }
  std::string quoted = "\"";
  for (const char c : text)
  {
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  }
  return quoted + "\"";
}

nlohmann::ordered_json
SideJson(const SideRow & side, const std::vector<std::uint64_t> & maximumSizes)
{
  nlohmann::ordered_json bySize = nlohmann::ordered_json::array();
  for (size_t k = 0; k < maximumSizes.size(); ++k)
  {
    bySize.push_back({ { "max_size", maximumSizes[k] },
                       { "removed_components", side.RemovedComponents[k] },
                       { "modified_voxels", side.ModifiedVoxels[k] } });
  }
  return { { "components", side.Components }, { "by_size", std::move(bySize) } };
}

nlohmann::ordered_json
FilteredJson(const FilteredRow & filtered, const std::vector<std::uint64_t> & maximumSizes)
{
  nlohmann::ordered_json bySize = nlohmann::ordered_json::array();
  for (size_t k = 0; k < maximumSizes.size(); ++k)
  {
    bySize.push_back({ { "max_size", maximumSizes[k] },
                       { "removed_components", filtered.RemovedComponents[k] },
                       { "modified_voxels", filtered.ModifiedVoxels[k] },
                       { "surface_components_after", filtered.SurfacePiecesAfter[k] } });
  }
  return { { "side", "both" }, { "by_size", std::move(bySize) } };
}

/** "256 × 256 × 128 voxels (8388608)" for \a size. */
std::string
SizeText(const std::vector<std::uint64_t> & size)
{
  std::uint64_t voxels = 1;
  std::string   text;
  for (const std::uint64_t extent : size)
  {
    voxels *= extent;
    text += (text.empty() ? "" : " × ") + std::to_string(extent);
  }
  return text + " voxels (" + std::to_string(voxels) + ")";
}

bool
HasFiltered(const Report & report)
{
  return !report.Rows.empty() && report.Rows.front().Filtered.has_value();
}
} // namespace

SideRow
SummarizeSide(const SideHistogram & histogram, const std::vector<std::uint64_t> & maximumSizes)
{
  SideRow       row;
  std::uint64_t components = 0;
  std::uint64_t voxels = 0;
  std::uint64_t size = 0;
  row.Components = histogram.Components;
  for (const std::uint64_t k : maximumSizes)
  {
    for (; size <= k && size < histogram.CountOfSize.size(); ++size)
    {
      components += histogram.CountOfSize[size];
      voxels += size * histogram.CountOfSize[size];
    }
    row.RemovedComponents.push_back(components);
    row.ModifiedVoxels.push_back(voxels);
  }
  return row;
}

double
Percent(std::uint64_t removed, std::uint64_t total)
{
  return total == 0 ? 0.0 : 100.0 * static_cast<double>(removed) / static_cast<double>(total);
}

std::string
NumberText(double value)
{
  char       text[64];
  const auto result = std::to_chars(text, text + sizeof(text), value);
  return std::string(text, result.ptr);
}

void
WriteReportMarkdown(std::ostream & stream, const Report & report)
{
  stream << "# Small iso-components of " << report.Input << "\n\n"
         << SizeText(report.Size) << ", " << (report.FullyConnected ? "full connectivity" : "face connectivity")
         << ". For each isovalue S and maximum size K: the components of each side (above: >= S, below: < S) "
            "with at most K voxels, the percentage they are of all components (above + below), and the voxels "
            "in them. Active cubes are the grid cells with corners on both sides of S.";
  const bool filtered = HasFiltered(report);
  if (filtered)
  {
    stream << " The last three columns are what the filter does with side both (its below pass runs on the "
              "result of the above pass): the components it removes and the connected pieces of the "
              "isosurface at S before and after filtering.";
  }
  stream << "\n\n| isovalue | active cubes | components | above | below | K | above removed | above % | above voxels "
            "| below removed | below % | below voxels |"
         << (filtered ? " both removed | surface pieces before | surface pieces after |" : "") << "\n"
         << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|" << (filtered ? "---:|---:|---:|" : "")
         << "\n";
  for (const ReportRow & row : report.Rows)
  {
    const std::uint64_t total = row.TotalComponents();
    for (size_t k = 0; k < report.MaximumSizes.size(); ++k)
    {
      stream << "| " << NumberText(row.IsoValue) << " | " << row.ActiveCubes << " | " << total << " | "
             << row.Above.Components << " | " << row.Below.Components << " | " << report.MaximumSizes[k] << " | "
             << row.Above.RemovedComponents[k] << " | " << PercentText(row.Above.RemovedComponents[k], total) << " | "
             << row.Above.ModifiedVoxels[k] << " | " << row.Below.RemovedComponents[k] << " | "
             << PercentText(row.Below.RemovedComponents[k], total) << " | " << row.Below.ModifiedVoxels[k] << " |";
      if (row.Filtered)
      {
        stream << ' ' << row.Filtered->RemovedComponents[k] << " | " << row.Filtered->SurfacePiecesBefore << " | "
               << row.Filtered->SurfacePiecesAfter[k] << " |";
      }
      stream << '\n';
    }
  }
}

void
WriteReportCsv(std::ostream & stream, const Report & report)
{
  stream << "input,connectivity,isovalue,active_cubes,total_components,side,components,max_size,"
            "removed_components,removed_percent,modified_voxels"
         << (HasFiltered(report) ? ",surface_components_before,surface_components_after" : "") << '\n';
  const std::string prefix = CsvField(report.Input) + "," + (report.FullyConnected ? "full" : "face") + ",";
  for (const ReportRow & row : report.Rows)
  {
    const std::uint64_t total = row.TotalComponents();
    for (const auto & [name, side] : { std::make_pair("above", &row.Above), std::make_pair("below", &row.Below) })
    {
      for (size_t k = 0; k < report.MaximumSizes.size(); ++k)
      {
        stream << prefix << NumberText(row.IsoValue) << ',' << row.ActiveCubes << ',' << total << ',' << name << ','
               << side->Components << ',' << report.MaximumSizes[k] << ',' << side->RemovedComponents[k] << ','
               << NumberText(Percent(side->RemovedComponents[k], total)) << ',' << side->ModifiedVoxels[k];
        if (row.Filtered)
        {
          stream << ',' << row.Filtered->SurfacePiecesBefore << ',';
        }
        stream << '\n';
      }
    }
    if (row.Filtered)
    {
      // The filter's own result: its two passes do not split into per-side component counts.
      for (size_t k = 0; k < report.MaximumSizes.size(); ++k)
      {
        stream << prefix << NumberText(row.IsoValue) << ',' << row.ActiveCubes << ',' << total << ",both,,"
               << report.MaximumSizes[k] << ',' << row.Filtered->RemovedComponents[k] << ','
               << NumberText(Percent(row.Filtered->RemovedComponents[k], total)) << ','
               << row.Filtered->ModifiedVoxels[k] << ',' << row.Filtered->SurfacePiecesBefore << ','
               << row.Filtered->SurfacePiecesAfter[k] << '\n';
      }
    }
  }
}

void
WriteReportJson(std::ostream & stream, const Report & report)
{
  using Json = nlohmann::ordered_json;
  Json rows = Json::array();
  for (const ReportRow & row : report.Rows)
  {
    Json json = { { "isovalue", row.IsoValue },
                  { "active_cubes", row.ActiveCubes },
                  { "total_components", row.TotalComponents() },
                  { "above", SideJson(row.Above, report.MaximumSizes) },
                  { "below", SideJson(row.Below, report.MaximumSizes) } };
    if (row.Filtered)
    {
      json["surface_components_before"] = row.Filtered->SurfacePiecesBefore;
      json["filtered"] = FilteredJson(*row.Filtered, report.MaximumSizes);
    }
    rows.push_back(std::move(json));
  }
  const Json document = { { "input", report.Input },
                          { "size", report.Size },
                          { "connectivity", report.FullyConnected ? "full" : "face" },
                          { "rows", std::move(rows) } };
  // As the filter's statistics: null for NaN, U+FFFD for bytes of the input's path that are not UTF-8.
  stream << document.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
}

void
WriteReportMarkdown(std::ostream & stream, const LabelMapReport & report)
{
  stream << "# Small components of the label map " << report.Input << "\n\n"
         << SizeText(report.Size) << ", " << (report.FullyConnected ? "full connectivity" : "face connectivity")
         << ". For each label and maximum size K: the label's components with at most K voxels, the percentage "
            "they are of the label's components, and the voxels in them, which the label filter removes with K "
            "and every label selected.\n\n"
         << "| label | components | K | removed | removed % | removed voxels |\n"
         << "|---:|---:|---:|---:|---:|---:|\n";
  for (const auto & [label, row] : report.Labels)
  {
    for (size_t k = 0; k < report.MaximumSizes.size(); ++k)
    {
      stream << "| " << label << " | " << row.Components << " | " << report.MaximumSizes[k] << " | "
             << row.RemovedComponents[k] << " | " << PercentText(row.RemovedComponents[k], row.Components) << " | "
             << row.ModifiedVoxels[k] << " |\n";
    }
  }
}

void
WriteReportCsv(std::ostream & stream, const LabelMapReport & report)
{
  stream << "input,connectivity,label,components,max_size,removed_components,removed_percent,removed_voxels\n";
  const std::string prefix = CsvField(report.Input) + "," + (report.FullyConnected ? "full" : "face") + ",";
  for (const auto & [label, row] : report.Labels)
  {
    for (size_t k = 0; k < report.MaximumSizes.size(); ++k)
    {
      stream << prefix << label << ',' << row.Components << ',' << report.MaximumSizes[k] << ','
             << row.RemovedComponents[k] << ',' << NumberText(Percent(row.RemovedComponents[k], row.Components)) << ','
             << row.ModifiedVoxels[k] << '\n';
    }
  }
}

void
WriteReportJson(std::ostream & stream, const LabelMapReport & report)
{
  using Json = nlohmann::ordered_json;
  Json labels = Json::object();
  for (const auto & [label, row] : report.Labels)
  {
    Json bySize = Json::array();
    for (size_t k = 0; k < report.MaximumSizes.size(); ++k)
    {
      bySize.push_back({ { "max_size", report.MaximumSizes[k] },
                         { "removed_components", row.RemovedComponents[k] },
                         { "removed_voxels", row.ModifiedVoxels[k] } });
    }
    labels[label] = { { "components", row.Components }, { "by_size", std::move(bySize) } };
  }
  const Json document = { { "input", report.Input },
                          { "size", report.Size },
                          { "connectivity", report.FullyConnected ? "full" : "face" },
                          { "labels", std::move(labels) } };
  stream << document.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
}
} // namespace sic
