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
#include "sicReportRanges.h"

#include "sicCommandLine.h"
#include "sicToolError.h"

#include <algorithm>
#include <cmath>

namespace sic
{
namespace
{
/** The three parts of START:STOP:STEP. */
std::vector<std::string>
SplitRange(const std::string & flag, const std::string & text)
{
  std::vector<std::string> parts;
  size_t                   begin = 0;
  for (size_t colon = text.find(':'); colon != std::string::npos; colon = text.find(':', begin))
  {
    parts.push_back(text.substr(begin, colon - begin));
    begin = colon + 1;
  }
  parts.push_back(text.substr(begin));
  if (parts.size() != 3)
  {
    throw ToolError(flag + " '" + text + "' is not a range; expected START:STOP:STEP, e.g. 20.5:60.5:5");
  }
  return parts;
}

void
CheckCount(const std::string & flag, const std::string & text, double count, std::uint64_t maximumCount)
{
  if (count > static_cast<double>(maximumCount))
  {
    throw ToolError(flag + " '" + text + "' gives more than " + std::to_string(maximumCount) +
                    " values; expected a larger STEP or a shorter range");
  }
}
} // namespace

std::vector<std::uint64_t>
ParseCountList(const std::string & flag, const std::string & text)
{
  std::vector<std::uint64_t> values;
  size_t                     begin = 0;
  while (true)
  {
    const size_t      comma = text.find(',', begin);
    const std::string item = text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    if (item.empty())
    {
      throw ToolError(flag + " '" + text +
                      "' has an empty item; expected whole numbers >= 0 separated by commas, "
                      "e.g. 1,5,10,20,50");
    }
    values.push_back(ParseCount(flag, item));
    if (comma == std::string::npos)
    {
      return values;
    }
    begin = comma + 1;
  }
}

std::vector<double>
ParseNumberRange(const std::string & flag, const std::string & text, std::uint64_t maximumCount)
{
  const std::vector<std::string> parts = SplitRange(flag, text);
  const double                   start = ParseNumber(flag, parts[0]);
  const double                   stop = ParseNumber(flag, parts[1]);
  const double                   step = ParseNumber(flag, parts[2]);
  if (step <= 0.0)
  {
    throw ToolError(flag + " '" + text + "' has a STEP <= 0; expected a positive STEP");
  }
  if (start > stop)
  {
    throw ToolError(flag + " '" + text + "' has START > STOP; expected START <= STOP");
  }
  // Steps that land on STOP up to rounding count as landing on it.
  const double steps = std::floor((stop - start) / step + 1e-9);
  CheckCount(flag, text, steps + 1.0, maximumCount);
  std::vector<double> values;
  for (double i = 0.0; i <= steps; i += 1.0)
  {
    const double value = start + i * step;
    values.push_back(std::fabs(value - stop) <= 1e-9 * step ? stop : std::min(value, stop));
  }
  return values;
}

std::vector<std::uint64_t>
ParseCountRange(const std::string & flag, const std::string & text, std::uint64_t maximumCount)
{
  const std::vector<std::string> parts = SplitRange(flag, text);
  const std::uint64_t            start = ParseCount(flag, parts[0]);
  const std::uint64_t            stop = ParseCount(flag, parts[1]);
  const std::uint64_t            step = ParseCount(flag, parts[2]);
  if (step == 0)
  {
    throw ToolError(flag + " '" + text + "' has a STEP of 0; expected a STEP >= 1");
  }
  if (start > stop)
  {
    throw ToolError(flag + " '" + text + "' has START > STOP; expected START <= STOP");
  }
  CheckCount(flag, text, static_cast<double>((stop - start) / step) + 1.0, maximumCount);
  std::vector<std::uint64_t> values;
  for (std::uint64_t value = start;; value += step)
  {
    values.push_back(value);
    if (stop - value < step)
    {
      return values;
    }
  }
}
} // namespace sic
