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
#ifndef sicSlicerDescription_h
#define sicSlicerDescription_h

#include "sicCommandLine.h"

#include <string>

namespace sic
{
/** The tool's 3D Slicer Execution Model description (the XML a Slicer CLI module prints for --xml), built from the same
 * ToolDescription as the parser.
 *
 * Slicer passes a parameter as "--" + its longflag, in the order of the description, followed by the parameters that
 * have an index (the positionals), in index order. A Slicer longflag may contain only letters, digits and underscores,
 * so the description spells each flag with underscores ("--max_size"), which the parser accepts. Parameters are grouped
 * by SlicerParameter::Group, in the order the groups first appear; a group named "Advanced" is marked advanced
 * (collapsed in Slicer's GUI). */
std::string
SlicerDescriptionXml(const ToolDescription & tool);
} // namespace sic

#endif
