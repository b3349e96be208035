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
#ifndef sicFilterTool_h
#define sicFilterTool_h

namespace sic
{
/** The two executables of the filter tool: SmallIsoComponentFilter, for scalar images (label maps with --labels), and
 * SmallIsoComponentLabelFilter, for label maps only. Both run the same code; the second exists because 3D Slicer
 * shows one panel per executable, and a label map's panel takes and gives label volumes. */
enum class FilterTool
{
  Scalar,
  Labels
};

constexpr const char * ScalarToolName = "SmallIsoComponentFilter";
constexpr const char * LabelToolName = "SmallIsoComponentLabelFilter";

/** The tool's main: parses the command line, filters, and returns the exit status. */
int
FilterToolMain(FilterTool kind, int argc, char * argv[]);
} // namespace sic

#endif
