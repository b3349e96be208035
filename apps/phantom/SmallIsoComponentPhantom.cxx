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
// SmallIsoComponentPhantom: writes a deterministic synthetic CT-like volume full of specks
// and bubbles, to try SmallIsoComponentFilter on without real data.

#include "sicCommandLine.h"
#include "sicImageFiles.h"
#include "sicPhantom.h"
#include "sicStagedOutputs.h"
#include "sicToolError.h"
#include "sicToolMain.h"

#include <filesystem>
#include <iostream>

namespace
{
const char * const ToolName = "SmallIsoComponentPhantom";
const char * const DefaultFileName = "phantom.nrrd";

sic::ToolDescription
DescribeTool()
{
  sic::ToolDescription tool;
  tool.Name = ToolName;
  tool.Usage = "SmallIsoComponentPhantom OUTPUT_DIR_OR_FILE [--size N] [--seed S] [--no-compression] [--help]";
  tool.Description =
    "Writes a synthetic CT-like volume (int16, Hounsfield-like units, spacing 0.8 x 0.8 x 1.0 mm): air (-1000) "
    "around an ellipsoidal body of soft tissue (40) holding a dense shell (700) with marrow (60) inside and a "
    "dense rod (1000) beside it, with noise of about 20 everywhere, small dense specks (300 to 1000) outside "
    "the dense parts and small bubbles (-200 to 100) inside them. At the suggested isovalue, 150, it has many "
    "small components on both sides for SmallIsoComponentFilter to remove. The same size and seed give the "
    "same file, bit for bit.";
  tool.Positionals = { { "OUTPUT_DIR_OR_FILE",
                         std::string("The file to write (NRRD by default; any format ITK writes, by its "
                                     "extension), or an existing directory to write ") +
                           DefaultFileName + " in.",
                         {} } };
  tool.Options = {
    { "--size", "N", "The volume has N x N x N voxels (8 to 1024).", "96", {} },
    { "--seed", "S", "Seed of the pseudo-random noise, specks and bubbles (a whole number).", "1", {} },
    { "--no-compression",
      "",
      "Write the volume uncompressed (faster for large sizes; .mhd and .nhdr then write .raw data files).",
      "compressed where the format allows",
      {} },
    { "--help", "", "Print this help and exit (also -h).", "", {} },
  };
  tool.Epilogue = "Exit status: 0 success; 1 the work failed (e.g. out of memory); 2 a wrong command line or an\n"
                  "output that cannot be written.\n"
                  "\n"
                  "Example:\n"
                  "  SmallIsoComponentPhantom /tmp/phantom.nrrd --size 128 --seed 7\n"
                  "  SmallIsoComponentFilter /tmp/phantom.nrrd /tmp/clean.nrrd --isovalue 150\n";
  return tool;
}

int
Run(const sic::ToolDescription & tool, const sic::ParsedCommandLine & arguments)
{
  sic::CheckPositionals(tool, arguments);
  std::uint64_t size = 96;
  if (arguments.Has("--size"))
  {
    size = sic::ParseCount("--size", arguments.Value("--size"));
    if (size < 8 || size > 1024)
    {
      throw sic::ToolError("--size " + arguments.Value("--size") + " is out of range; expected 8 to 1024 voxels");
    }
  }
  const std::uint64_t seed = arguments.Has("--seed") ? sic::ParseCount("--seed", arguments.Value("--seed")) : 1;

  std::string     path = arguments.Positionals()[0];
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
  {
    path = (std::filesystem::path(path) / DefaultFileName).string();
  }
  sic::StagedOutputs outputs;
  const std::string  staged = outputs.Stage(path, "phantom");
  sic::CheckImageFileFormat(path, "phantom", 3);

  const sic::PhantomImageType::Pointer phantom = sic::MakePhantom(static_cast<unsigned int>(size), seed);
  sic::WriteImage(phantom.GetPointer(), staged, path, "phantom", nullptr, !arguments.Has("--no-compression"));
  outputs.Commit();
  std::cout << "Wrote " << path << ": " << size << "x" << size << "x" << size << " int16 phantom, seed " << seed
            << "; suggested isovalue " << sic::PhantomSuggestedIsoValue << "." << std::endl;
  return sic::ExitSuccess;
}
} // namespace

int
main(int argc, char * argv[])
{
  const sic::ToolDescription tool = DescribeTool();
  return sic::ToolMain(
    tool, argc, argv, [&tool](const sic::ParsedCommandLine & arguments) { return Run(tool, arguments); });
}
