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
#ifndef sicStrings_h
#define sicStrings_h

// The small text helpers the tools share: case, ends, surrounding white space, quoting and escaping.

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace sic
{
/** \a text in lower case (ASCII letters only). */
inline std::string
Lowercase(std::string text)
{
  std::transform(
    text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

/** Whether \a text ends with \a suffix (case counts). */
inline bool
EndsWith(const std::string & text, const std::string & suffix)
{
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/** \a text without the spaces, tabs and line ends around it. */
inline std::string
Trim(const std::string & text)
{
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos)
  {
    return {};
  }
  return text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
}

/** \a text with XML's special characters escaped, for element text and attribute values alike. */
inline std::string
XmlEscaped(const std::string & text)
{
  std::string out;
  for (const char c : text)
  {
    out += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '"' ? "&quot;" : std::string(1, c);
  }
  return out;
}

/** \a text in single quotes, as the tools' messages name files and values: 'x.nrrd'. */
inline std::string
Quoted(const std::string & text)
{
  return "'" + text + "'";
}

/** A path in single quotes, as it is given. */
inline std::string
Quoted(const std::filesystem::path & path)
{
  return Quoted(path.string());
}
} // namespace sic

#endif
