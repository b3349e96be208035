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

// libFuzzer target: the tools' reading path on arbitrary bytes. The first byte picks the file's format (NRRD,
// MetaImage or NIfTI), the next three the filter's parameters; the rest is the file. It is checked and read as
// SmallIsoComponentFilter reads its input (ReadScalarImageInfo, then ReadImage, here always as float32), filtered, and
// written back in the same format, checked as the tool checks its outputs. A refusal (ToolError) is a correct outcome;
// anything else that escapes, or a sanitizer's report, is a finding.

#include "sicImageFiles.h"

#include "itkMetaImageIOFactory.h"
#include "itkNiftiImageIOFactory.h"
#include "itkNrrdImageIOFactory.h"
#include "itkSmallIsoComponentImageFilter.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace
{
namespace fs = std::filesystem;

/** Larger images are refused before reading: the fuzzer looks for faults, not for the memory a header can ask. */
constexpr std::uint64_t MaximumVoxels = 1 << 20;

struct FilterChoices
{
  double                            IsoValue{ 0.0 };
  itk::SizeValueType                MaximumSize{ 0 };
  itk::SmallIsoComponentEnums::Side Side{ itk::SmallIsoComponentEnums::Side::Both };
  bool                              FullyConnected{ false };
};

/** A directory of this process's own for the fuzzed file and the outputs. */
const fs::path &
ScratchDirectory()
{
  static const fs::path directory = [] {
    const fs::path path = fs::temp_directory_path() / ("sic-fuzz-read-" + std::to_string(getpid()));
    fs::create_directories(path);
    return path;
  }();
  return directory;
}

void
RegisterImageFormats()
{
  static const bool registered = [] {
    itk::NrrdImageIOFactory::RegisterOneFactory();
    itk::MetaImageIOFactory::RegisterOneFactory();
    itk::NiftiImageIOFactory::RegisterOneFactory();
    return true;
  }();
  (void)registered;
}

template <typename TImage>
void
FilterAndWrite(const std::string & input, const std::string & output, const FilterChoices & choices)
{
  typename TImage::Pointer image = sic::ReadImage<TImage>(input, "input", nullptr);
  auto                     filter = itk::SmallIsoComponentImageFilter<TImage>::New();
  filter->SetInput(image);
  filter->SetIsoValue(choices.IsoValue);
  filter->SetMaximumComponentSize(choices.MaximumSize);
  filter->SetSide(choices.Side);
  filter->SetFullyConnected(choices.FullyConnected);
  filter->SetNumberOfWorkUnits(2);
  filter->GenerateRemovedMaskOn();
  filter->Update();
  sic::WriteImage(filter->GetOutput(), output, output, "output image", nullptr);
  const std::string mask = output + ".mask" + fs::path(output).extension().string();
  sic::WriteImage(filter->GetRemovedMask(), mask, mask, "removed-voxel mask", nullptr);
}

void
CheckReadFilterWrite(const std::string & input, const std::string & output, const FilterChoices & choices)
{
  const sic::ScalarImageInfo info = sic::ReadScalarImageInfo(input, "input");
  std::uint64_t              voxels = 1;
  for (const std::uint64_t extent : info.Size)
  {
    voxels *= extent;
    if (voxels > MaximumVoxels)
    {
      return;
    }
  }
  // Read as float32 whatever the file holds (ITK's reader converts every pixel type): one instantiation per
  // dimension keeps the target quick to build; the tool's own dispatch adds no reading of its own.
  if (info.Dimension == 2)
  {
    FilterAndWrite<itk::Image<float, 2>>(input, output, choices);
  }
  else
  {
    FilterAndWrite<itk::Image<float, 3>>(input, output, choices);
  }
}
} // namespace

extern "C" int
LLVMFuzzerTestOneInput(const std::uint8_t * data, size_t size)
{
  if (size < 4)
  {
    return 0;
  }
  RegisterImageFormats();
  static const char * const Extensions[] = { ".nrrd", ".mha", ".nii" };
  const std::string         extension = Extensions[data[0] % 3];
  FilterChoices             choices;
  choices.IsoValue = static_cast<std::int8_t>(data[1]) * 4.0 + 0.5;
  choices.MaximumSize = data[2] % 64;
  choices.Side = static_cast<itk::SmallIsoComponentEnums::Side>(data[3] % 3);
  choices.FullyConnected = (data[3] & 4) != 0;

  const fs::path directory = ScratchDirectory();
  const fs::path input = directory / ("input" + extension);
  {
    std::ofstream file(input, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char *>(data + 4), static_cast<std::streamsize>(size - 4));
  }
  try
  {
    CheckReadFilterWrite(input.string(), (directory / ("output" + extension)).string(), choices);
  }
  catch (const sic::ToolError &)
  {
    // A refusal with a message is what bad input should get.
  }
  // Nothing a fuzzed header names outside the directory is touched: only what is inside is removed.
  for (const auto & entry : fs::directory_iterator(directory))
  {
    std::error_code ignored;
    fs::remove_all(entry.path(), ignored);
  }
  return 0;
}
