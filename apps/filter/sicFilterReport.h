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
#ifndef sicFilterReport_h
#define sicFilterReport_h

#include "sicImageFiles.h"

#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace sic
{
/** What SmallIsoComponentFilter was asked to do, from its command line. */
struct FilterSettings
{
  std::string Input;
  std::string Output;
  std::string RemovedMask;
  std::string Stats;
  /** Isosurface outputs (tools built with VTK only): the filtered image's, the input's, and
   * the four-panel picture. */
  std::string Surface;
  std::string SurfaceBefore;
  std::string Render;
  double      IsoValue{ 0.0 };
  /** The threshold in voxels; used unless MaximumVolume is set and positive. */
  std::uint64_t         MaximumSize{ 20 };
  bool                  MaximumSizeGiven{ false };
  std::optional<double> MaximumVolume;
  /** above, below or both. */
  std::string Side{ "both" };
  bool        FullyConnected{ false };
  /** 0: ITK's default. */
  std::uint64_t Threads{ 0 };
  bool          Quiet{ false };
  bool          ProgressXml{ false };
  /** --memory-limit in bytes (0: none given). */
  std::uint64_t MemoryLimit{ 0 };
  /** Whether the outputs are compressed where their format allows (--no-compression: not). */
  bool Compress{ true };

  /** A label map (--labels, or SmallIsoComponentLabelFilter), cleaned with the label filter; no isovalue nor side.
   * Label ids are kept as text in their canonical spelling (LabelId()), and become labels of the input's pixel type
   * once it is known. */
  bool Labels{ false };
  /** all, islands, holes, or listed (SelectedLabels). */
  std::string              Selection{ "all" };
  std::vector<std::string> SelectedLabels;
  std::string              Background{ "0" };
  /** --max-size-of: labels with their own K, in voxels. */
  std::vector<std::pair<std::string, std::uint64_t>> LabelMaximumSizes;
  /** --keep-largest N; 0: off. */
  std::uint64_t KeepLargest{ 0 };

  bool
  UsesVolume() const
  {
    return MaximumVolume && *MaximumVolume > 0.0;
  }
};

/** The statistics of one side of the isovalue. */
struct SideReport
{
  std::uint64_t Components{ 0 };
  std::uint64_t RemovedComponents{ 0 };
  std::uint64_t RemovedVoxels{ 0 };
  /** Component size (voxels) -> number of components of that size. */
  std::map<std::uint64_t, std::uint64_t> Histogram;
};

/** The statistics of one label of a label map. */
struct LabelReport : SideReport
{
  /** Removed voxels of other labels that took this one. */
  std::uint64_t GainedVoxels{ 0 };
  /** Connected pieces of the label's surface in the input and in the output, and the input's pieces filtering
   * removed, when they were extracted. */
  std::optional<std::uint64_t> SurfacePiecesBefore;
  std::optional<std::uint64_t> SurfacePiecesAfter;
  std::optional<std::uint64_t> RemovedSurfacePieces;
};

/** Where each output is written before it is moved into place. */
struct StagedPaths
{
  std::string Image;
  std::string RemovedMask;
  std::string Surface;
  std::string SurfaceBefore;
  std::string Render;
};

/** What one run of the filter found and did. */
struct FilterReport
{
  ScalarImageInfo Input;
  std::uint64_t   EffectiveMaximumSize{ 0 };
  /** ITK's number of threads, and the work units the filter split its work into. */
  std::uint64_t Threads{ 0 };
  std::uint64_t WorkUnits{ 0 };
  SideReport    Above;
  SideReport    Below;
  /** Label maps: each label of the input, in ascending order, with its id as text (LabelId()'s spelling). */
  std::vector<std::pair<std::string, LabelReport>> Labels;
  std::uint64_t                                    ModifiedVoxels{ 0 };
  std::uint64_t                                    UnrepairableVoxels{ 0 };
  std::uint64_t                                    PeakExtraBytes{ 0 };
  /** Connected pieces of the isosurface at the isovalue (of a label map: of all its labels' surfaces), when it was
   * extracted: of the input, of the output, and of the triangles filtering took away. */
  std::optional<std::uint64_t> SurfacePiecesBefore;
  std::optional<std::uint64_t> SurfacePiecesAfter;
  std::optional<std::uint64_t> RemovedSurfacePieces;
  /** Wall time of the filter itself, and of the whole run (reading and writing included). */
  double FilterSeconds{ 0.0 };
  double TotalSeconds{ 0.0 };
  /** Streamed plane by plane (--memory-limit, or an input too large for memory), in slabs of
   * SlabPlanes planes under MemoryLimit bytes; then the time spent reading and writing. In memory,
   * SlabPlanes is the thickness of the slabs a large image was swept in, 0 for the whole image at
   * once. */
  bool          Streaming{ false };
  std::uint64_t MemoryLimit{ 0 };
  std::uint64_t SlabPlanes{ 0 };
  double        ReadSeconds{ 0.0 };
  double        WriteSeconds{ 0.0 };
  /** The most memory the process held at once (0 where the system does not tell). */
  std::uint64_t PeakResidentBytes{ 0 };
};

/** A one-paragraph summary for a person. */
void
WriteSummary(std::ostream & out, const FilterSettings & settings, const FilterReport & report);

/** The input, the parameters and every statistic as one JSON document. */
void
WriteStatisticsJson(std::ostream &         out,
                    const std::string &    toolName,
                    const std::string &    version,
                    const FilterSettings & settings,
                    const FilterReport &   report);
} // namespace sic

#endif
