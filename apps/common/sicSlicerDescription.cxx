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
#include "sicSlicerDescription.h"
#include "sicStrings.h"

#include <algorithm>
#include <sstream>

namespace sic
{
namespace
{
/** A Slicer longflag has no hyphens: "--max-size" is spelled "--max_size", which the parser takes too. */
std::string
SlicerFlag(std::string flag)
{
  std::replace(flag.begin() + 2, flag.end(), '-', '_');
  return flag;
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
    out << "      <longflag>" << XmlEscaped(SlicerFlag(flag)) << "</longflag>\n";
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
} // namespace sic
