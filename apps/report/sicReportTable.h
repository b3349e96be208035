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
#ifndef sicReportTable_h
#define sicReportTable_h

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace sic
{
/** The components of one side of an isovalue, as a labelling gives them. */
struct SideHistogram
{
  std::uint64_t Components{ 0 };
  /** CountOfSize[s]: the number of components of exactly s voxels, for s up to the largest
   * size the report asks about (larger components only count in Components). */
  std::vector<std::uint64_t> CountOfSize;
};

/** One side's numbers in a row of the report, for every maximum size K. */
struct SideRow
{
  std::uint64_t Components{ 0 };
  /** Per K: the components of <= K voxels, and their voxels. */
  std::vector<std::uint64_t> RemovedComponents;
  std::vector<std::uint64_t> ModifiedVoxels;
};

/** What the filter itself does with side Both at every K, and the isosurface it leaves
 * (reports built with VTK, 3-D images). */
struct FilteredRow
{
  std::uint64_t SurfacePiecesBefore{ 0 };
  /** Per K: components the filter removed (above and below pass), voxels it modified, and
   * the connected pieces of the isosurface of its output. */
  std::vector<std::uint64_t> RemovedComponents;
  std::vector<std::uint64_t> ModifiedVoxels;
  std::vector<std::uint64_t> SurfacePiecesAfter;
};

struct ReportRow
{
  double                     IsoValue{ 0.0 };
  std::uint64_t              ActiveCubes{ 0 };
  SideRow                    Above;
  SideRow                    Below;
  std::optional<FilteredRow> Filtered;

  std::uint64_t
  TotalComponents() const
  {
    return Above.Components + Below.Components;
  }
};

/** What SmallIsoComponentReport reports about one image. */
struct Report
{
  std::string                Input;
  std::vector<std::uint64_t> Size;
  bool                       FullyConnected{ false };
  /** The maximum sizes K, ascending. */
  std::vector<std::uint64_t> MaximumSizes;
  /** One row per isovalue, ascending. */
  std::vector<ReportRow> Rows;
};

/** What removing small components would do to a label map: for every label, its components and, for every K, those of
 * at most K voxels and the voxels in them, which SmallIsoComponentLabelImageFilter removes with K and every label
 * selected. */
struct LabelMapReport
{
  std::string                Input;
  std::vector<std::uint64_t> Size;
  bool                       FullyConnected{ false };
  /** The maximum sizes K, ascending. */
  std::vector<std::uint64_t> MaximumSizes;
  /** Each label, as the filter's statistics key it, and its row, in ascending order of the labels. */
  std::vector<std::pair<std::string, SideRow>> Labels;
};

/** The removal counts for every K of \a maximumSizes (ascending) from a side's histogram. */
SideRow
SummarizeSide(const SideHistogram & histogram, const std::vector<std::uint64_t> & maximumSizes);

/** removed as a percentage of total (0 when total is 0). */
double
Percent(std::uint64_t removed, std::uint64_t total);

/** The shortest decimal text that reads back as \a value. */
std::string
NumberText(double value);

/** A heading, a sentence on the image, then one table row per isovalue and K (with the
 * filter's Both result and the isosurface's pieces when the rows have them). */
void
WriteReportMarkdown(std::ostream & stream, const Report & report);

/** One line per isovalue, side and K, under a header line; side "both" lines give the
 * filter's own result and the isosurface's pieces when the rows have them. */
void
WriteReportCsv(std::ostream & stream, const Report & report);

void
WriteReportJson(std::ostream & stream, const Report & report);

/** The label map's report: a heading, a sentence on the map, then one table row per label and K. */
void
WriteReportMarkdown(std::ostream & stream, const LabelMapReport & report);

/** One line per label and K, under a header line. */
void
WriteReportCsv(std::ostream & stream, const LabelMapReport & report);

/** The labels keyed by their ids, each with its components and one entry per K. */
void
WriteReportJson(std::ostream & stream, const LabelMapReport & report);
} // namespace sic

#endif
