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
#ifndef sicImageFileParts_h
#define sicImageFileParts_h

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sic
{
/** How a stretch of an image file's voxels is stored. */
enum class ImageDataEncoding
{
  Raw,
  /** One or more zlib or gzip streams. */
  Deflate,
  /** NRRD's ascii, hex or bzip2: ITK's reader alone checks these. */
  Unchecked
};

/** One file's share of an image's voxels. */
struct ImageDataSegment
{
  std::filesystem::path File;
  ImageDataEncoding     Encoding{ ImageDataEncoding::Raw };
  /** Bytes of File before the data: the header, NRRD's line skip and (raw) byte skip. */
  std::uint64_t Offset{ 0 };
  /** The voxels are the last bytes of File, or of the inflated data (a negative NRRD byte skip, MetaImage's
   * HeaderSize -1). */
  bool AtEnd{ false };
  /** Deflate only: bytes of the inflated data before the voxels (a .nii.gz's vox_offset, NRRD's byte skip). */
  std::uint64_t InflatedOffset{ 0 };
  /** Deflate, MetaImage only: its CompressedDataSize, the bytes ITK's reader inflates as one stream, when whole. */
  std::optional<std::uint64_t> CompressedBytes;
};

/** The image file formats whose files the tools check themselves; ITK alone checks the Other ones. */
enum class ImageFileFormat
{
  Nrrd,
  MetaImage,
  Nifti,
  Png,
  Other
};

/** The files an image consists of, where its voxels are and how they are stored, as its header says. */
struct ImageFileParts
{
  ImageFileFormat Format{ ImageFileFormat::Other };
  /** The header file first, then every other file it names, each once. */
  std::vector<std::filesystem::path> Files;
  /** Where the voxels are, in order; empty for a format whose header the tools do not read. */
  std::vector<ImageDataSegment> Data;
  /** The voxels' bytes as the header describes them, when it says (the largest 64-bit number on overflow). */
  std::optional<std::uint64_t> DataBytes;
  /** The header has a fault that must be refused before ITK reads it: one its reader does not survive (a MetaImage
   * field name of 255 characters or more overflows MetaIO's buffer), misreads or reports without saying what is
   * wrong (sizes that are not whole numbers of at least 1). */
  bool UnsafeForItk{ false };
  /** The header names its data files as a list or a numbered series (even of one file). */
  bool DataFileSeries{ false };
  /** A MetaImage series: how many files its reader reads, each for a slice (or slab) of SeriesFileBytes bytes; 0 when
   * the header does not say. */
  std::uint64_t SeriesFiles{ 0 };
  std::uint64_t SeriesFileBytes{ 0 };
  /** NRRD's "endian: big", MetaImage's BinaryDataByteOrderMSB or ElementByteOrderMSB True (the last of them). */
  bool BigEndian{ false };
  /** MetaImage's BinaryData False (on any of its lines): the voxels are text, TextValues numbers when it says. */
  bool                         TextData{ false };
  std::optional<std::uint64_t> TextValues;
  /** NRRD's encoding field in lower case ("raw", "gzip", "ascii", ...). */
  std::string EncodingName;
};

/** The format of the image file \a path by its extension, as ITK knows it (case does not count). */
ImageFileFormat
ImageFileFormatOf(const std::filesystem::path & path);

/** Whether the file \a path begins with PNG's eight-byte signature. */
bool
StartsWithPngSignature(const std::filesystem::path & path);

/** The parts of the image file \a path by ImageFileFormatOf(), or PNG whatever its name when it has PNG's signature
 * (ITK's readers take it as PNG when the format its name gives declines it): NRRD, MetaImage and NIfTI from their
 * headers (data files relative to the header's directory, named whether or not they exist), any other the file alone
 * with no Data. Sets \a problem, saying why (e.g. "its header is cut short"), when such a header cannot be read. */
ImageFileParts
FindImageFileParts(const std::filesystem::path & path, std::string & problem);
} // namespace sic

#endif
