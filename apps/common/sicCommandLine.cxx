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
#include "sicCommandLine.h"
#include "sicStrings.h"
#include "sicToolError.h"

#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace sic
{
namespace
{
/** \a flag with \a from replaced by \a to in its name: hyphens and underscores are the same to the parser, and a
 * Slicer longflag has no hyphens ("--max_size"). */
std::string
ReplaceInFlag(std::string flag, char from, char to)
{
  std::replace(flag.begin() + 2, flag.end(), from, to);
  return flag;
}

/** Appends \a text to \a out wrapped at 79 columns, each line indented by \a indent. */
void
Wrap(std::ostringstream & out, const std::string & text, size_t indent)
{
  std::istringstream words(text);
  std::string        word;
  size_t             column = 0;
  while (words >> word)
  {
    if (column > indent && column + 1 + word.size() > 79)
    {
      out << '\n';
      column = 0;
    }
    out << (column == 0 ? std::string(indent, ' ') : std::string(" ")) << word;
    column += (column == 0 ? indent : 1) + word.size();
  }
  out << '\n';
}

/** <tag>value</tag> on a line of its own after \a indent; nothing when there is no value. */
void
WriteOptionalElement(std::ostringstream & out, const char * indent, const std::string & tag, const std::string & value)
{
  if (!value.empty())
  {
    out << indent << '<' << tag << '>' << XmlEscaped(value) << "</" << tag << ">\n";
  }
}

/** One parameter; \a flag is empty for a positional, which gets \a index instead. */
void
WriteParameter(std::ostringstream &    out,
               const SlicerParameter & parameter,
               const std::string &     flag,
               int                     index,
               const std::string &     help,
               const std::string &     commandLineDefault)
{
  out << "    <" << parameter.Tag;
  if (!parameter.ImageType.empty())
  {
    out << " type=\"" << XmlEscaped(parameter.ImageType) << '"';
  }
  if (!parameter.FileExtensions.empty())
  {
    out << " fileExtensions=\"" << XmlEscaped(parameter.FileExtensions) << '"';
  }
  if (parameter.Hidden)
  {
    out << " hidden=\"true\"";
  }
  out << ">\n";
  out << "      <name>" << XmlEscaped(parameter.Name) << "</name>\n";
  if (flag.empty())
  {
    out << "      <index>" << index << "</index>\n";
  }
  else
  {
    out << "      <longflag>" << XmlEscaped(ReplaceInFlag(flag, '-', '_')) << "</longflag>\n";
  }
  out << "      <label>" << XmlEscaped(parameter.Label) << "</label>\n";
  out << "      <description>" << XmlEscaped(help) << "</description>\n";
  WriteOptionalElement(out, "      ", "channel", parameter.Channel);
  std::string defaultValue = parameter.Default.empty() ? commandLineDefault : parameter.Default;
  if (parameter.Tag == "boolean" && defaultValue.empty())
  {
    defaultValue = "false";
  }
  WriteOptionalElement(out, "      ", "default", defaultValue);
  for (const std::string & element : parameter.Elements)
  {
    out << "      <element>" << XmlEscaped(element) << "</element>\n";
  }
  if (!parameter.Minimum.empty() || !parameter.Maximum.empty() || !parameter.Step.empty())
  {
    out << "      <constraints>\n";
    WriteOptionalElement(out, "        ", "minimum", parameter.Minimum);
    WriteOptionalElement(out, "        ", "maximum", parameter.Maximum);
    WriteOptionalElement(out, "        ", "step", parameter.Step);
    out << "      </constraints>\n";
  }
  out << "    </" << parameter.Tag << ">\n";
}
} // namespace

bool
ParsedCommandLine::Has(const std::string & flag) const
{
  return m_Options.count(flag) != 0;
}

std::string
ParsedCommandLine::Value(const std::string & flag) const
{
  const std::vector<std::string> values = Values(flag);
  return values.empty() ? std::string() : values.back();
}

std::vector<std::string>
ParsedCommandLine::Values(const std::string & flag) const
{
  const auto found = m_Options.find(flag);
  return found == m_Options.end() ? std::vector<std::string>() : found->second;
}

// Our own loop rather than CLI11 or KWSys's CommandLineArguments: both accept what the tools refuse (CLI11 takes
// "--quiet=1", "-500" as a positional, and "--stats= FILE" as --stats FILE; KWSys needs each of "--flag value",
// "--flag=value" and the underscore spelling registered apart) and word every error their own way, so keeping the
// messages and their order would put this same loop in front of either.
ParsedCommandLine
ParseCommandLine(const ToolDescription & tool, int argc, const char * const argv[])
{
  ParsedCommandLine parsed;
  bool              optionsEnded = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string argument = argv[i];
    if (optionsEnded || argument.size() < 2 || argument[0] != '-')
    {
      parsed.m_Positionals.push_back(argument);
      continue;
    }
    if (argument == "--")
    {
      optionsEnded = true;
      continue;
    }
    if (argument == "-h")
    {
      parsed.m_Options["--help"];
      continue;
    }
    const size_t equals = argument.find('=');
    std::string  flag = argument.substr(0, equals);
    const auto   option = std::find_if(tool.Options.begin(), tool.Options.end(), [&flag](const Option & candidate) {
      return flag.compare(0, 2, "--") == 0 && candidate.Flag == ReplaceInFlag(flag, '_', '-');
    });
    if (option == tool.Options.end())
    {
      const bool numberLike = std::isdigit(static_cast<unsigned char>(argument[1])) || argument[1] == '.';
      throw ToolError(
        "unknown option " + Quoted(flag) + "; run '" + tool.Name + " --help' for the options" +
        (numberLike ? " (a value starting with '-' belongs after its option, e.g. --isovalue -500)" : ""));
    }
    flag = option->Flag;
    const bool repeatable =
      std::find(tool.RepeatableOptions.begin(), tool.RepeatableOptions.end(), flag) != tool.RepeatableOptions.end();
    if (parsed.Has(flag) && !repeatable)
    {
      throw ToolError(flag + " is given twice; give it once");
    }
    if (option->ValueName.empty())
    {
      if (equals != std::string::npos)
      {
        throw ToolError(flag + " takes no value, but was given " + Quoted(argument.substr(equals + 1)));
      }
      parsed.m_Options[flag];
    }
    else if (equals != std::string::npos || i + 1 < argc)
    {
      const std::string value = equals != std::string::npos ? argument.substr(equals + 1) : std::string(argv[++i]);
      parsed.m_Options[flag].push_back(value);
    }
    else
    {
      throw ToolError(flag + " needs a value (" + flag + " " + option->ValueName + ")");
    }
  }
  return parsed;
}

void
CheckPositionals(const ToolDescription & tool, const ParsedCommandLine & arguments)
{
  const auto & given = arguments.Positionals();
  if (given.size() < tool.Positionals.size())
  {
    throw ToolError("missing " + tool.Positionals[given.size()].Name + "; usage: " + tool.Usage);
  }
  if (given.size() > tool.Positionals.size())
  {
    throw ToolError("unexpected extra argument " + Quoted(given[tool.Positionals.size()]) + "; usage: " + tool.Usage);
  }
}

std::string
HelpText(const ToolDescription & tool)
{
  std::ostringstream out;
  out << "Usage: " << tool.Usage << "\n\n";
  Wrap(out, tool.Description, 0);
  out << "\nArguments:\n";
  for (const Positional & positional : tool.Positionals)
  {
    out << "  " << positional.Name << '\n';
    Wrap(out, positional.Help, 6);
  }
  out << "\nOptions (underscores may replace the hyphens in a flag):\n";
  for (const Option & option : tool.Options)
  {
    out << "  " << option.Flag;
    if (!option.ValueName.empty())
    {
      out << ' ' << option.ValueName;
    }
    out << '\n';
    Wrap(out, option.Help + (option.Default.empty() ? "" : " Default: " + option.Default + "."), 6);
  }
  if (!tool.Epilogue.empty())
  {
    out << '\n' << tool.Epilogue;
  }
  return out.str();
}

std::string
SlicerDescriptionXml(const ToolDescription & tool)
{
  std::vector<std::string> groups;
  const auto               addGroup = [&groups](const SlicerParameter & parameter) {
    if (!parameter.Tag.empty() && std::find(groups.begin(), groups.end(), parameter.Group) == groups.end())
    {
      groups.push_back(parameter.Group);
    }
  };
  for (const Positional & positional : tool.Positionals)
  {
    addGroup(positional.Slicer);
  }
  for (const Option & option : tool.Options)
  {
    addGroup(option.Slicer);
  }

  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<executable>\n";
  out << "  <category>" << XmlEscaped(tool.Category) << "</category>\n";
  out << "  <title>" << XmlEscaped(tool.Title) << "</title>\n";
  out << "  <description>" << XmlEscaped(tool.Description) << "</description>\n";
  out << "  <version>" << XmlEscaped(tool.Version) << "</version>\n";
  WriteOptionalElement(out, "  ", "documentation-url", tool.DocumentationUrl);
  out << "  <license>" << XmlEscaped(tool.License) << "</license>\n";
  out << "  <contributor>" << XmlEscaped(tool.Contributor) << "</contributor>\n";
  out << "  <acknowledgements>" << XmlEscaped(tool.Acknowledgements) << "</acknowledgements>\n";
  for (const std::string & group : groups)
  {
    out << "  <parameters" << (group == "Advanced" ? " advanced=\"true\"" : "") << ">\n";
    out << "    <label>" << XmlEscaped(group) << "</label>\n";
    out << "    <description>" << XmlEscaped(group) << "</description>\n";
    for (size_t i = 0; i < tool.Positionals.size(); ++i)
    {
      const Positional & positional = tool.Positionals[i];
      if (!positional.Slicer.Tag.empty() && positional.Slicer.Group == group)
      {
        WriteParameter(out, positional.Slicer, "", static_cast<int>(i), positional.Help, "");
      }
    }
    for (const Option & option : tool.Options)
    {
      if (!option.Slicer.Tag.empty() && option.Slicer.Group == group)
      {
        WriteParameter(out, option.Slicer, option.Flag, 0, option.Help, option.Default);
      }
    }
    out << "  </parameters>\n";
  }
  out << "</executable>\n";
  return out.str();
}

double
ParseNumber(const std::string & flag, const std::string & text)
{
  const char * begin = text.c_str();
  char *       end = nullptr;
  errno = 0;
  const double value = std::strtod(begin, &end);
  const bool   whole = end != begin && *end == '\0' && !std::isspace(static_cast<unsigned char>(text[0]));
  if (!whole || std::isnan(value))
  {
    throw ToolError(flag + " " + Quoted(text) + " is not a number; expected a finite number such as 150 or -0.5");
  }
  if (std::isinf(value) || (errno == ERANGE && std::fabs(value) > 1.0))
  {
    throw ToolError(flag + " " + Quoted(text) + " is not finite; expected a finite number");
  }
  return value;
}

std::uint64_t
ParseCount(const std::string & flag, const std::string & text)
{
  const bool digitsOnly = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c));
  });
  if (!digitsOnly)
  {
    const bool negative = !text.empty() && text[0] == '-';
    throw ToolError(flag + " " + Quoted(text) + (negative ? " is negative" : " is not a whole number") +
                    "; expected a whole number >= 0 such as 20");
  }
  errno = 0;
  const unsigned long long value = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE)
  {
    throw ToolError(flag + " " + Quoted(text) + " is too large; expected a whole number below 2^64");
  }
  return static_cast<std::uint64_t>(value);
}

std::string
ParseChoice(const std::string & flag, const std::string & text, const std::vector<std::string> & choices)
{
  const std::string lower = Lowercase(text);
  std::string       expected;
  for (const std::string & choice : choices)
  {
    if (lower == choice)
    {
      return choice;
    }
    expected += (expected.empty() ? "" : ", ") + choice;
  }
  throw ToolError(flag + " " + Quoted(text) + " is not a valid choice; expected one of " + expected);
}

std::uint64_t
ParseThreads(const ParsedCommandLine & arguments)
{
  if (!arguments.Has("--threads"))
  {
    return 0;
  }
  const std::uint64_t threads = ParseCount("--threads", arguments.Value("--threads"));
  if (threads > MaximumThreads())
  {
    throw ToolError("--threads " + arguments.Value("--threads") + " is too many; expected 0 to " +
                    std::to_string(MaximumThreads()));
  }
  return threads;
}

std::uint64_t
MaximumThreads()
{
  return ITK_MAX_THREADS;
}

void
CheckPathsNotEmpty(const ParsedCommandLine & arguments, const std::vector<std::string> & flags)
{
  for (const std::string & flag : flags)
  {
    if (arguments.Has(flag) && arguments.Value(flag).empty())
    {
      throw ToolError(flag + " is empty; expected a file path");
    }
  }
}
} // namespace sic
