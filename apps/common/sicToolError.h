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
#ifndef sicToolError_h
#define sicToolError_h

#include <sstream>
#include <stdexcept>
#include <string>

namespace sic
{
/** Exit status of the command-line tools. */
enum ExitStatus : int
{
  ExitSuccess = 0,
  /** The work itself failed: out of memory, an internal error. */
  ExitFailure = 1,
  /** The request was wrong: command line, input file or output path. */
  ExitUsage = 2
};

/** An error the user can fix, reported as one line (what was wrong and what was expected)
 * and ending the tool with ExitUsage. */
class ToolError : public std::runtime_error
{
public:
  explicit ToolError(const std::string & message)
    : std::runtime_error(message)
  {}
};

/** \a text on one line: runs of whitespace, newlines included, become one space. */
inline std::string
OneLine(const std::string & text)
{
  std::istringstream words(text);
  std::string        word;
  std::string        line;
  while (words >> word)
  {
    line += (line.empty() ? "" : " ") + word;
  }
  return line;
}
/** The description of an ITK exception on one line, without the "ITK ERROR: Class(0x...): " prefixes ITK's
 * macros put in front (an object's address means nothing to the user). */
inline std::string
ItkErrorText(const std::string & description)
{
  std::string       text = OneLine(description);
  const std::string prefix = "ITK ERROR: ";
  for (size_t at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at))
  {
    size_t       end = at + prefix.size();
    const size_t open = text.find("(0x", end);
    const size_t close = open == std::string::npos ? open : text.find("): ", open);
    if (close != std::string::npos && text.find(' ', end) > open)
    {
      end = close + 3;
    }
    text.erase(at, end - at);
  }
  return text;
}
} // namespace sic

#endif
