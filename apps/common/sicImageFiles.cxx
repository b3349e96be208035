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
#include "sicImageFiles.h"
#include "sicImageDataCheck.h"
#include "sicImageFileParts.h"
#include "sicStrings.h"

#include "itkImageIOFactory.h"
#include "vnl/algo/vnl_determinant.h"
#include "vnl/vnl_matrix.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace sic
{
namespace
{
// The types sicScalarImageDispatch.h instantiates the tools for.
constexpr PixelTypeEntry SupportedTypes[] = {
  { itk::IOComponentEnum::UCHAR, "uint8", "MET_UCHAR", "uint8", 1 },
  { itk::IOComponentEnum::CHAR, "int8", "MET_CHAR", "int8", 1 },
  { itk::IOComponentEnum::USHORT, "uint16", "MET_USHORT", "uint16", 2 },
  { itk::IOComponentEnum::SHORT, "int16", "MET_SHORT", "int16", 2 },
  { itk::IOComponentEnum::UINT, "uint32", "MET_UINT", "uint32", 4 },
  { itk::IOComponentEnum::INT, "int32", "MET_INT", "int32", 4 },
  { itk::IOComponentEnum::FLOAT, "float32", "MET_FLOAT", "float", 4 },
  { itk::IOComponentEnum::DOUBLE, "float64", "MET_DOUBLE", "double", 8 },
};

// The types only label maps take besides those (sicScalarImageDispatch.h's DispatchLabelImage): ITK names an 8-byte
// integer LONG or LONGLONG, depending on the reader and on the platform's long.
constexpr bool           LongIs64 = sizeof(long) == 8;
constexpr PixelTypeEntry WideLabelTypes[] = {
  { itk::IOComponentEnum::ULONGLONG, "uint64", "MET_ULONG_LONG", "uint64", 8 },
  { itk::IOComponentEnum::LONGLONG, "int64", "MET_LONG_LONG", "int64", 8 },
  { itk::IOComponentEnum::ULONG, LongIs64 ? "uint64" : "uint32", "MET_ULONG", "uint64", sizeof(long) },
  { itk::IOComponentEnum::LONG, LongIs64 ? "int64" : "int32", "MET_LONG", "int64", sizeof(long) },
};

template <std::size_t VSize>
const PixelTypeEntry *
FindIn(const PixelTypeEntry (&types)[VSize], itk::IOComponentEnum componentType)
{
  const auto found = std::find_if(std::begin(types), std::end(types), [componentType](const PixelTypeEntry & entry) {
    return entry.ComponentType == componentType;
  });
  return found == std::end(types) ? nullptr : found;
}

template <std::size_t VSize>
std::string
Names(const PixelTypeEntry (&types)[VSize], std::string names)
{
  for (const PixelTypeEntry & entry : types)
  {
    // Several ITK types may share a name (LONG and LONGLONG): each name once.
    if ((", " + names + ", ").find(", " + std::string(entry.Name) + ", ") == std::string::npos)
    {
      names += (names.empty() ? "" : ", ") + std::string(entry.Name);
    }
  }
  return names;
}
} // namespace

const PixelTypeEntry *
FindPixelType(itk::IOComponentEnum componentType, bool labels)
{
  const PixelTypeEntry * entry = FindIn(SupportedTypes, componentType);
  return entry == nullptr && labels ? FindIn(WideLabelTypes, componentType) : entry;
}

std::string
PixelTypeName(itk::IOComponentEnum componentType)
{
  const PixelTypeEntry * entry = FindPixelType(componentType, true);
  return entry != nullptr ? entry->Name : itk::ImageIOBase::GetComponentTypeAsString(componentType);
}

std::string
SupportedPixelTypes()
{
  return Names(SupportedTypes, "");
}

std::string
SupportedLabelPixelTypes()
{
  return Names(WideLabelTypes, SupportedPixelTypes());
}

namespace
{
ScalarImageInfo
ReadImageInfo(const std::string & path, const std::string & what, bool labels)
{
  const std::string name = what + " " + Quoted(path);
  const auto        cannotRead = [&](const std::string & why) { throw ToolError("cannot read " + name + ": " + why); };
  std::error_code   error;
  const auto        status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status))
  {
    cannotRead("no such file; expected an existing image file");
  }
  if (std::filesystem::is_directory(status))
  {
    cannotRead("it is a directory; expected an image file");
  }
  if (!std::filesystem::is_regular_file(status))
  {
    cannotRead("it is not a regular file (a FIFO, device or socket); expected an image file");
  }
  const auto refuse = [&](const std::string & problem) {
    const bool saysExpected = problem.find("; expected") != std::string::npos;
    throw ToolError(name + " " + (problem.compare(0, 3, "is ") == 0 ? "" : "cannot be read: ") + problem +
                    (saysExpected ? "" : "; expected a complete, intact image file"));
  };
  // The data files are checked before ITK reads the header: its NRRD reader opens them, and would wait forever
  // for a FIFO. A header only this parser finds fault with is refused after ITK had its say.
  std::string          headerProblem;
  const ImageFileParts parts = FindImageFileParts(path, headerProblem);
  const std::string    dataProblem = headerProblem.empty() ? ImageFileProblem(parts) : "";
  if (parts.UnsafeForItk || !dataProblem.empty())
  {
    refuse(parts.UnsafeForItk ? headerProblem : dataProblem);
  }
  itk::ImageIOBase::Pointer io =
    itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode);
  if (!io && EndsWith(Lowercase(path), ".gz"))
  {
    // A small file's header is read through a gzip stream that is checked at its end, so a corrupt stream looks
    // like no image at all.
    std::string problem;
    Inflate(path, 0, true, problem);
    if (!problem.empty())
    {
      refuse(CompressedDataProblem("its compressed data", problem));
    }
  }
  if (!io)
  {
    cannotRead("not an image file ITK can read; expected e.g. NRRD (.nrrd, .nhdr), NIfTI (.nii, .nii.gz), "
               "MetaImage (.mha, .mhd) or PNG");
  }
  io->SetFileName(path);
  try
  {
    io->ReadImageInformation();
  }
  catch (const itk::ExceptionObject & exception)
  {
    cannotRead(ItkErrorText(exception.GetDescription()));
  }

  ScalarImageInfo info;
  info.ComponentType = io->GetComponentType();
  info.Dimension = io->GetNumberOfDimensions();
  if (io->GetNumberOfComponents() != 1)
  {
    throw ToolError(name + " has " + std::to_string(io->GetNumberOfComponents()) + " components per pixel (" +
                    itk::ImageIOBase::GetPixelTypeAsString(io->GetPixelType()) +
                    "); expected a scalar image, one value per voxel");
  }
  if (FindPixelType(info.ComponentType, labels) == nullptr)
  {
    throw ToolError(name + " has pixel type " + PixelTypeName(info.ComponentType) +
                    ", which is not supported; expected one of " +
                    (labels ? SupportedLabelPixelTypes() : SupportedPixelTypes()));
  }
  if (info.Dimension != 2 && info.Dimension != 3)
  {
    throw ToolError(name + " is " + std::to_string(info.Dimension) + "-D; expected a 2-D or 3-D image");
  }
  std::string size;
  for (unsigned int axis = 0; axis < info.Dimension; ++axis)
  {
    info.Size.push_back(io->GetDimensions(axis));
    info.Spacing.push_back(io->GetSpacing(axis));
    info.Origin.push_back(io->GetOrigin(axis));
    size += (axis == 0 ? "" : " x ") + std::to_string(info.Size.back());
  }
  if (std::find(info.Size.begin(), info.Size.end(), 0) != info.Size.end())
  {
    throw ToolError(name + " is empty: its size is " + size + " voxels; expected at least one voxel along every axis");
  }
  // ITK's reader refuses a spacing of 0, and a direction matrix of determinant (exactly) 0, only when it reads the
  // voxels, and the streaming reader reads none of it; the same tests as ITK's, so that both modes refuse the same
  // files.
  vnl_matrix<double> direction(info.Dimension, info.Dimension);
  for (unsigned int axis = 0; axis < info.Dimension; ++axis)
  {
    if (info.Spacing[axis] == 0.0 || !std::isfinite(info.Spacing[axis]))
    {
      std::ostringstream spacing;
      spacing << info.Spacing[axis];
      throw ToolError(name + " has a spacing of " + spacing.str() + " along axis " + std::to_string(axis) +
                      "; expected a nonzero, finite spacing along every axis");
    }
    direction.set_column(axis, io->GetDirection(axis).data());
  }
  if (vnl_determinant(direction) == 0.0)
  {
    throw ToolError(name + " has a direction matrix of determinant 0 (its axes do not span the space); expected axes "
                           "in independent directions");
  }
  if (!headerProblem.empty())
  {
    refuse(headerProblem);
  }
  info.Files = parts.Files;
  return info;
}
} // namespace

ScalarImageInfo
ReadScalarImageInfo(const std::string & path, const std::string & what)
{
  return ReadImageInfo(path, what, false);
}

ScalarImageInfo
ReadLabelImageInfo(const std::string & path, const std::string & what)
{
  return ReadImageInfo(path, what, true);
}


void
CheckPngFileName(const std::string & path, const std::string & what)
{
  if (std::filesystem::path(path).extension() != ".png")
  {
    throw ToolError("cannot write the " + what + " '" + path + "': expected a .png file (the " + what +
                    " is a PNG picture)");
  }
}

bool
CheckWrittenImageFile(const std::string & path, const std::string & finalPath, const std::string & what)
{
  std::string          problem;
  const ImageFileParts parts = FindImageFileParts(path, problem);
  if (parts.Format == ImageFileFormat::Other)
  {
    return false;
  }
  if (problem.empty())
  {
    problem = ImageFileProblem(parts);
  }
  if (!problem.empty())
  {
    // A header the tools cannot read back was cut short while it was written.
    throw ToolError("cannot write " + what + " '" + finalPath + "': the file written " +
                    (problem.compare(0, 3, "is ") == 0 ? "" : "is incomplete: ") +
                    ShowFinalPaths(problem, path, finalPath) + " (is the disk full?)");
  }
  return true;
}

void
CheckImageFileFormat(const std::string & path, const std::string & what, unsigned int dimension)
{
  const itk::ImageIOBase::Pointer io =
    itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::ImageIOFactory::IOFileModeEnum::WriteMode);
  const std::string extension = std::filesystem::path(path).extension().string();
  if (!io)
  {
    throw ToolError("cannot write " + what + " '" + path + "': no ITK image writer handles the extension '" +
                    extension + "'; expected e.g. .nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd or .png");
  }
  // These writers would silently keep only the first slice of a 3-D image.
  const std::string format = io->GetNameOfClass();
  const bool        twoDimensional = format == "PNGImageIO" || format == "BMPImageIO" || format == "JPEGImageIO";
  if (twoDimensional && dimension > 2)
  {
    throw ToolError("cannot write " + what + " '" + path + "': the " + extension +
                    " format stores 2-D images only and the image is " + std::to_string(dimension) +
                    "-D; expected e.g. .nrrd, .nii.gz or .mha");
  }
}
} // namespace sic
