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
// Parses a CLI module's XML description (the file named on the command line) with 3D Slicer's own
// parser, SlicerExecutionModel's ModuleDescriptionParser, and prints what Slicer sees as JSON: the
// module's title and category, and every parameter of every group. Built only when a
// SlicerExecutionModel tree is available (see apps/test/CMakeLists.txt).

#include "ModuleDescription.h"
#include "ModuleDescriptionParser.h"

#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
std::string
Json(const std::string & text)
{
  std::string out = "\"";
  for (const char c : text)
  {
    switch (c)
    {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
        {
          char escaped[8];
          std::snprintf(escaped, sizeof(escaped), "\\u%04x", c);
          out += escaped;
        }
        else
        {
          out += c;
        }
    }
  }
  return out + "\"";
}
} // namespace

int
main(int argc, char * argv[])
{
  if (argc != 2)
  {
    std::cerr << "usage: SmallIsoComponentSlicerParserProbe DESCRIPTION.xml" << std::endl;
    return 2;
  }
  std::ifstream      file(argv[1]);
  std::ostringstream xml;
  xml << file.rdbuf();
  ModuleDescription       description;
  ModuleDescriptionParser parser;
  if (parser.Parse(xml.str(), description) != 0)
  {
    std::cerr << "ModuleDescriptionParser refused the description" << std::endl;
    return 1;
  }
  std::cout << "{\"title\": " << Json(description.GetTitle()) << ", \"category\": " << Json(description.GetCategory())
            << ", \"version\": " << Json(description.GetVersion()) << ", \"parameters\": [";
  bool first = true;
  for (const auto & group : description.GetParameterGroups())
  {
    for (const auto & parameter : group.GetParameters())
    {
      std::cout << (first ? "" : ", ") << "{\"group\": " << Json(group.GetLabel())
                << ", \"tag\": " << Json(parameter.GetTag()) << ", \"name\": " << Json(parameter.GetName())
                << ", \"flag\": " << Json(parameter.GetFlag()) << ", \"longflag\": " << Json(parameter.GetLongFlag())
                << ", \"label\": " << Json(parameter.GetLabel()) << ", \"default\": " << Json(parameter.GetDefault())
                << ", \"minimum\": " << Json(parameter.GetMinimum())
                << ", \"maximum\": " << Json(parameter.GetMaximum()) << ", \"step\": " << Json(parameter.GetStep())
                << ", \"channel\": " << Json(parameter.GetChannel()) << ", \"index\": " << Json(parameter.GetIndex())
                << ", \"hidden\": " << Json(parameter.GetHidden())
                << ", \"multiple\": " << Json(parameter.GetMultiple()) << ", \"elements\": [";
      bool firstElement = true;
      for (const auto & element : parameter.GetElements())
      {
        std::cout << (firstElement ? "" : ", ") << Json(element);
        firstElement = false;
      }
      std::cout << "]}";
      first = false;
    }
  }
  std::cout << "]}" << std::endl;
  return 0;
}
