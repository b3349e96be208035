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
#ifndef sicLabelFilter_h
#define sicLabelFilter_h

#include "sicFilterReport.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sic
{
class ParsedCommandLine;
class ProgressReporter;

/** A label id as the command line gives it, a whole number, spelled canonically as the statistics key labels: no
 * '+', no leading zeros, "0" for "-0". Throws ToolError naming \a flag. */
std::string
LabelId(const std::string & flag, const std::string & text);

/** Reads the options of label maps into \a settings; throws ToolError for an option that has no meaning for them. */
void
ReadLabelSettings(const ParsedCommandLine & arguments, FilterSettings & settings);

/** Throws ToolError for an option of label maps given without --labels. */
void
RefuseLabelOptions(const ParsedCommandLine & arguments);

/** Reads the label map \a info describes, cleans it with SmallIsoComponentLabelImageFilter in memory, and writes the
 * output, the mask, the labels' surfaces and the picture the settings ask for to their \a staged paths. The label ids
 * of the settings are checked against the input's pixel type before any voxel is read. */
FilterReport
FilterLabelMap(const FilterSettings &  settings,
               const ScalarImageInfo & info,
               const StagedPaths &     staged,
               ProgressReporter &      progress);

/** FilterLabelMap() plane by plane along the last axis, within about \a limit bytes of memory, for MetaImage and NRRD
 * files: slabs of planes, each read with the planes around it that the filter asks for (twice the largest K on each
 * side), so the output and mask are those of the in-memory run. Of the statistics, each label's removed and gained
 * voxels, the modified and the unrepairable voxels are known; its components and their sizes are not (a component may
 * span the whole depth). Throws ToolError when the limit is too small, or was passed before the last plane. */
FilterReport
FilterLabelMapStreamed(const FilterSettings &  settings,
                       const ScalarImageInfo & info,
                       const StagedPaths &     staged,
                       std::uint64_t           limit,
                       ProgressReporter &      progress);

/** Every label of the label map \a info describes (settings.Input), in ascending order, as the statistics key it,
 * with its components and their sizes: SmallIsoComponentLabelImageFilter run with K = 0, which removes nothing, with
 * the connectivity and threads of \a settings. */
std::vector<std::pair<std::string, LabelReport>>
CountLabelComponents(const FilterSettings & settings, const ScalarImageInfo & info);
} // namespace sic

#endif
