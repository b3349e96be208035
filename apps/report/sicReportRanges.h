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
#ifndef sicReportRanges_h
#define sicReportRanges_h

#include <cstdint>
#include <string>
#include <vector>

namespace sic
{
/** A comma-separated list of whole numbers >= 0 ("1,5,10,20,50"); throws ToolError
 * naming \a flag for an empty item, a negative number or anything that is not a number. */
std::vector<std::uint64_t>
ParseCountList(const std::string & flag, const std::string & text);

/** START:STOP:STEP as numbers: START, START + STEP, ... up to STOP, STOP included when it
 * is reached within rounding (1e-9 of a step). Throws ToolError for bad syntax, a STEP
 * <= 0, START > STOP or more than \a maximumCount values. */
std::vector<double>
ParseNumberRange(const std::string & flag, const std::string & text, std::uint64_t maximumCount);

/** START:STOP:STEP as whole numbers >= 0, STOP included when reached; STEP >= 1. */
std::vector<std::uint64_t>
ParseCountRange(const std::string & flag, const std::string & text, std::uint64_t maximumCount);
} // namespace sic

#endif
