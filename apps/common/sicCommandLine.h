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
#ifndef sicCommandLine_h
#define sicCommandLine_h

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace sic
{
/** How a parameter appears in a 3D Slicer Execution Model description (see
 * SlicerDescriptionXml()). An empty Tag leaves it out of the description. */
struct SlicerParameter
{
  /** double, integer, string-enumeration, boolean, file or image. */
  std::string Tag;
  /** An identifier (letters, digits, underscores) naming the parameter. */
  std::string Name;
  std::string Label;
  /** Label of the parameter group the parameter belongs to. */
  std::string Group;
  /** input or output, for images and files. */
  std::string Channel;
  /** The image's type attribute (scalar, label), for images. */
  std::string ImageType;
  /** The file's fileExtensions attribute, for files. */
  std::string FileExtensions;
  /** The default Slicer shows and passes; empty means the command line's default. */
  std::string              Default;
  std::vector<std::string> Elements;
  std::string              Minimum;
  std::string              Maximum;
  std::string              Step;
  bool                     Hidden{ false };
};

/** An option of a tool: a switch (no ValueName) or an option taking one value. */
struct Option
{
  /** The long flag, with hyphens: "--max-size". Underscores are accepted for hyphens
   * when parsing ("--max_size"), the spelling Slicer needs. */
  std::string Flag;
  /** The value's name in the help, e.g. "K"; empty for a switch. */
  std::string ValueName;
  /** What it does, with units; the help wraps it. */
  std::string Help;
  /** The default shown in the help; empty for none. */
  std::string     Default;
  SlicerParameter Slicer;
};

/** A positional argument. */
struct Positional
{
  std::string     Name;
  std::string     Help;
  SlicerParameter Slicer;
};

/** Everything a tool says about itself: it drives the parser, --help and --xml, so the three cannot disagree. */
struct ToolDescription
{
  std::string             Name;
  std::string             Usage;
  std::string             Description;
  std::vector<Positional> Positionals;
  std::vector<Option>     Options;
  /** Text after the options in --help: exit codes, examples. */
  std::string Epilogue;
  /** Options that may be given more than once (e.g. "--isovalue"); see
   * ParsedCommandLine::Values(). Any other option given twice is an error. */
  std::vector<std::string> RepeatableOptions;

  /** For the Slicer description. */
  std::string Category;
  std::string Title;
  std::string Version;
  std::string Contributor;
  std::string Acknowledgements;
  std::string License;
  std::string DocumentationUrl;
};

/** The arguments of one run, checked against a ToolDescription. */
class ParsedCommandLine
{
public:
  /** True when the option (spelled as in the description) was given. */
  bool
  Has(const std::string & flag) const;
  /** The option's value; empty for a switch or an option that was not given. */
  std::string
  Value(const std::string & flag) const;
  /** Every value of the option, in the order given; empty when it was not given. */
  std::vector<std::string>
  Values(const std::string & flag) const;
  const std::vector<std::string> &
  Positionals() const
  {
    return m_Positionals;
  }

private:
  friend ParsedCommandLine
  ParseCommandLine(const ToolDescription & tool, int argc, const char * const argv[]);

  /** Every value of each option given, none for a switch. */
  std::map<std::string, std::vector<std::string>> m_Options;
  std::vector<std::string>                        m_Positionals;
};

/** Parses argv[1..argc-1]: options in any order and anywhere ("--flag value" or "--flag=value"), "-h" for "--help", and
 * "--" ending the options. Throws ToolError for an unknown option, a missing value, a value given to a switch or an
 * option given twice. The number of positionals is not checked here; see CheckPositionals(). */
ParsedCommandLine
ParseCommandLine(const ToolDescription & tool, int argc, const char * const argv[]);

/** Throws ToolError unless exactly the tool's positionals were given. */
void
CheckPositionals(const ToolDescription & tool, const ParsedCommandLine & arguments);

/** The --help text. */
std::string
HelpText(const ToolDescription & tool);

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

/** A finite number (NaN and infinities are refused); throws ToolError naming the flag. */
double
ParseNumber(const std::string & flag, const std::string & text);

/** A non-negative integer; throws ToolError naming the flag. */
std::uint64_t
ParseCount(const std::string & flag, const std::string & text);

/** One of \a choices (case-insensitive, returned as spelled in \a choices). */
std::string
ParseChoice(const std::string & flag, const std::string & text, const std::vector<std::string> & choices);

/** The number of ITK work units --threads asks for, 0 to MaximumThreads(); 0 (ITK's
 * default) when it is not given. Throws ToolError naming the flag. */
std::uint64_t
ParseThreads(const ParsedCommandLine & arguments);

/** The most work units --threads takes: ITK's limit, ITK_MAX_THREADS (128 unless ITK was built otherwise). */
std::uint64_t
MaximumThreads();

/** Throws ToolError if one of \a flags, options that take a file path, was given an empty value. */
void
CheckPathsNotEmpty(const ParsedCommandLine & arguments, const std::vector<std::string> & flags);
} // namespace sic

#endif
