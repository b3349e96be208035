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
#ifndef sicImageFiles_h
#define sicImageFiles_h

#include "sicImageFileParts.h"
#include "sicStagedOutputs.h"
#include "sicToolError.h"

#include "itkCommand.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageIOBase.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace sic
{
/** What an image file's header says, for a scalar image the tools can process. */
struct ScalarImageInfo
{
  itk::IOComponentEnum       ComponentType{ itk::IOComponentEnum::UNKNOWNCOMPONENTTYPE };
  unsigned int               Dimension{ 0 };
  std::vector<std::uint64_t> Size;
  std::vector<double>        Spacing;
  std::vector<double>        Origin;
  /** The files the image consists of: the file itself, then the data files its header names. */
  std::vector<std::filesystem::path> Files;
};

/** Reads the header of the image file \a path (described to the user as \a what, e.g. "input") and checks that the
 * tools can process it: a regular file (a FIFO would be read by each of ITK's format checks in turn), a scalar pixel of
 * a supported type (SupportedPixelTypes()) in 2 or 3 dimensions, at least one voxel along every axis, and its voxels
 * all there (ImageFileProblem(): data files of the size the header describes, compressed data complete and passing its
 * checksums), checked before anything is allocated. Throws ToolError saying what is wrong. */
ScalarImageInfo
ReadScalarImageInfo(const std::string & path, const std::string & what);

/** ReadScalarImageInfo() for a label map, which may also hold 64-bit integers (SupportedLabelPixelTypes()). */
ScalarImageInfo
ReadLabelImageInfo(const std::string & path, const std::string & what);

/** A pixel type the tools process, with its names: the tools' own, and in MetaImage and NRRD headers. */
struct PixelTypeEntry
{
  itk::IOComponentEnum ComponentType;
  const char *         Name;
  const char *         MetaImageName;
  const char *         NrrdName;
  unsigned int         Bytes;
};

/** The entry of \a componentType, or null when the tools do not process it (in a label map, with \a labels). */
const PixelTypeEntry *
FindPixelType(itk::IOComponentEnum componentType, bool labels = false);

/** "uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64", or for label maps "uint64" or "int64";
 * the ITK name for any other type. */
std::string
PixelTypeName(itk::IOComponentEnum componentType);

/** The supported pixel types, for messages: "uint8, int8, ..., float64". */
std::string
SupportedPixelTypes();

/** The pixel types of label maps, for messages: SupportedPixelTypes() and the 64-bit integers. */
std::string
SupportedLabelPixelTypes();

/** Throws ToolError unless an ITK image writer handles \a path's extension and, as far as
 * known, can store an image of \a dimension dimensions (PNG, BMP and JPEG are 2-D only). */
void
CheckImageFileFormat(const std::string & path, const std::string & what, unsigned int dimension);

/** Throws ToolError unless \a path, where the picture described as \a what is written, ends in
 * .png: the pictures are PNG files whatever their name says. */
void
CheckPngFileName(const std::string & path, const std::string & what);

/** Reads the whole image; \a observer (may be null) watches the reader's progress. */
template <typename TImage>
typename TImage::Pointer
ReadImage(const std::string & path, const std::string & what, itk::Command * observer)
{
  auto reader = itk::ImageFileReader<TImage>::New();
  reader->SetFileName(path);
  if (observer)
  {
    reader->AddObserver(itk::ProgressEvent(), observer);
  }
  // The readers' own prints are shown after a success; after a failure the one-line error says it all.
  StandardErrorCapture messages;
  try
  {
    reader->Update();
  }
  catch (const itk::MemoryAllocationError &)
  {
    // Not a fault of the file: out of memory is a failure of the run.
    throw;
  }
  catch (const itk::ExceptionObject & error)
  {
    // A PNG file's header and chunks were checked before: what fails now is its image data.
    const bool png = StartsWithPngSignature(path);
    throw ToolError("cannot read " + what + " '" + path +
                    "': " + (png ? "its image data (IDAT) do not decode to the image its header describes (" : "") +
                    ItkErrorText(error.GetDescription()) + (png ? "); expected a complete, intact PNG file" : ""));
  }
  messages.Replay();
  typename TImage::Pointer image = reader->GetOutput();
  image->DisconnectPipeline();
  return image;
}

/** Throws ToolError (naming \a finalPath, the path the user asked for) unless the image file ITK wrote at \a path is
 * complete (ImageFileProblem()): ITK's MetaImage and NIfTI writers only warn when a write fails, e.g. on a full disk.
 * Returns false, having checked nothing, for a format ImageFileProblem() does not check. */
bool
CheckWrittenImageFile(const std::string & path, const std::string & finalPath, const std::string & what);

/** Writes \a image to \a path, compressed where the format allows unless \a compress is false, and checks that the file
 * holds it: with CheckWrittenImageFile(), or for the other formats by reading it back and comparing every voxel.
 * \a finalPath is the path the user asked for (the file may be written elsewhere first), for messages. */
template <typename TImage>
void
WriteImage(const TImage *      image,
           const std::string & path,
           const std::string & finalPath,
           const std::string & what,
           itk::Command *      observer,
           bool                compress = true)
{
  auto writer = itk::ImageFileWriter<TImage>::New();
  writer->SetInput(image);
  writer->SetFileName(path);
  writer->SetUseCompression(compress);
  if (observer)
  {
    writer->AddObserver(itk::ProgressEvent(), observer);
  }
  // The MetaImage and NIfTI writers print a line where they fail: a failure gets one line of its own instead.
  StandardErrorCapture messages;
  try
  {
    writer->Update();
  }
  catch (const itk::MemoryAllocationError &)
  {
    throw;
  }
  catch (const itk::ExceptionObject & error)
  {
    // The message names the file the user asked for, not where it was being written.
    throw ToolError("cannot write " + what + " '" + finalPath +
                    "': " + ItkErrorText(ShowFinalPaths(error.GetDescription(), path, finalPath)));
  }
  if (CheckWrittenImageFile(path, finalPath, what))
  {
    messages.Replay();
    return;
  }
  typename TImage::Pointer written;
  try
  {
    written = ReadImage<TImage>(path, what, nullptr);
  }
  catch (const ToolError & error)
  {
    throw ToolError("cannot write " + what + " '" + finalPath + "': the file written cannot be read back (" +
                    ShowFinalPaths(error.what(), path, finalPath) + "); is the disk full?");
  }
  const auto & region = image->GetBufferedRegion();
  if (written->GetBufferedRegion().GetSize() != region.GetSize() ||
      std::memcmp(written->GetBufferPointer(),
                  image->GetBufferPointer(),
                  region.GetNumberOfPixels() * sizeof(typename TImage::PixelType)) != 0)
  {
    throw ToolError("cannot write " + what + " '" + finalPath +
                    "': the file written does not read back as the image (is the disk full, or can the format not "
                    "hold its voxels exactly?)");
  }
  messages.Replay();
}
} // namespace sic

#endif
