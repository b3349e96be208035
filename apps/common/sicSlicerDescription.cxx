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

#include <algorithm>
#include <sstream>

namespace sic
{
namespace
{
std::string
Escaped(const std::string & text)
{
  std::string out;
  for (const char c : text)
  {
    switch (c)
    {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string
SlicerFlag(const std::string & flag)
{
  std::string spelled = flag;
  for (size_t i = 2; i < spelled.size(); ++i)
  {
    if (spelled[i] == '-')
    {
      spelled[i] = '_';
    }
  }
  return spelled;
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
    out << " type=\"" << Escaped(parameter.ImageType) << '"';
  }
  if (!parameter.FileExtensions.empty())
  {
    out << " fileExtensions=\"" << Escaped(parameter.FileExtensions) << '"';
  }
  if (parameter.Hidden)
  {
    out << " hidden=\"true\"";
  }
  out << ">\n";
  out << "      <name>" << Escaped(parameter.Name) << "</name>\n";
  if (flag.empty())
  {
    out << "      <index>" << index << "</index>\n";
  }
  else
  {
    out << "      <longflag>" << Escaped(SlicerFlag(flag)) << "</longflag>\n";
  }
  out << "      <label>" << Escaped(parameter.Label) << "</label>\n";
  out << "      <description>" << Escaped(help) << "</description>\n";
  if (!parameter.Channel.empty())
  {
    out << "      <channel>" << Escaped(parameter.Channel) << "</channel>\n";
  }
  std::string defaultValue = parameter.Default.empty() ? commandLineDefault : parameter.Default;
  if (parameter.Tag == "boolean" && defaultValue.empty())
  {
    defaultValue = "false";
  }
  if (!defaultValue.empty())
  {
    out << "      <default>" << Escaped(defaultValue) << "</default>\n";
  }
  for (const std::string & element : parameter.Elements)
  {
    out << "      <element>" << Escaped(element) << "</element>\n";
  }
  if (!parameter.Minimum.empty() || !parameter.Maximum.empty() || !parameter.Step.empty())
  {
    out << "      <constraints>\n";
    if (!parameter.Minimum.empty())
    {
      out << "        <minimum>" << Escaped(parameter.Minimum) << "</minimum>\n";
    }
    if (!parameter.Maximum.empty())
    {
      out << "        <maximum>" << Escaped(parameter.Maximum) << "</maximum>\n";
    }
    if (!parameter.Step.empty())
    {
      out << "        <step>" << Escaped(parameter.Step) << "</step>\n";
    }
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
  out << "  <category>" << Escaped(tool.Category) << "</category>\n";
  out << "  <title>" << Escaped(tool.Title) << "</title>\n";
  out << "  <description>" << Escaped(tool.Description) << "</description>\n";
  out << "  <version>" << Escaped(tool.Version) << "</version>\n";
  if (!tool.DocumentationUrl.empty())
  {
    out << "  <documentation-url>" << Escaped(tool.DocumentationUrl) << "</documentation-url>\n";
  }
  out << "  <license>" << Escaped(tool.License) << "</license>\n";
  out << "  <contributor>" << Escaped(tool.Contributor) << "</contributor>\n";
  out << "  <acknowledgements>" << Escaped(tool.Acknowledgements) << "</acknowledgements>\n";
  for (const std::string & group : groups)
  {
    out << "  <parameters" << (group == "Advanced" ? " advanced=\"true\"" : "") << ">\n";
    out << "    <label>" << Escaped(group) << "</label>\n";
    out << "    <description>" << Escaped(group) << "</description>\n";
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
