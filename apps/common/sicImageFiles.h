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

#include "sicToolError.h"

#include "itkCommand.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageIOBase.h"

#include <cstdint>
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
};

/** Reads the header of the image file \a path (described to the user as \a what, e.g.
 * "input") and checks that the tools can process it: a scalar pixel of a supported type
 * (SupportedPixelTypes()) in 2 or 3 dimensions. Throws ToolError saying what is wrong. */
ScalarImageInfo
ReadScalarImageInfo(const std::string & path, const std::string & what);

/** "uint8", "int8", "uint16", "int16", "uint32", "int32", "float32" or "float64"; the ITK
 * name for any other type. */
std::string
PixelTypeName(itk::IOComponentEnum componentType);

/** The supported pixel types, for messages: "uint8, int8, ..., float64". */
std::string
SupportedPixelTypes();

/** Throws ToolError unless an ITK image writer handles \a path's extension and, as far as
 * known, can store an image of \a dimension dimensions (PNG, BMP and JPEG are 2-D only). */
void
CheckImageFileFormat(const std::string & path, const std::string & what, unsigned int dimension);

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
  try
  {
    reader->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw ToolError("cannot read " + what + " '" + path + "': " + OneLine(error.GetDescription()));
  }
  typename TImage::Pointer image = reader->GetOutput();
  image->DisconnectPipeline();
  return image;
}

/** Writes \a image to \a path, compressed where the format allows unless \a compress is false.
 * \a finalPath is the path the user asked for (the file may be written elsewhere first), for
 * messages. */
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
  try
  {
    writer->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    // The message names the file the user asked for, not where it was being written.
    std::string description = error.GetDescription();
    for (size_t at = description.find(path); at != std::string::npos;
         at = description.find(path, at + finalPath.size()))
    {
      description.replace(at, path.size(), finalPath);
    }
    throw ToolError("cannot write " + what + " '" + finalPath + "': " + OneLine(description));
  }
}
} // namespace sic

#endif
