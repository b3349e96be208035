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
  /** The voxels' bytes as they are. */
  Raw,
  /** One or more zlib or gzip streams that inflate to the voxels. */
  Deflate,
  /** An encoding the tools do not check (NRRD's ascii, hex or bzip2): ITK's reader alone does. */
  Unchecked
};

/** One file's share of an image's voxels. */
struct ImageDataSegment
{
  std::filesystem::path File;
  ImageDataEncoding     Encoding{ ImageDataEncoding::Raw };
  /** Bytes of File before the data: the header, NRRD's line skip and (raw) byte skip. */
  std::uint64_t Offset{ 0 };
  /** The voxels are the last bytes of File (NRRD's byte skip -1, MetaImage's HeaderSize -1); for Deflate, of
   * the inflated data (NRRD's byte skip -1 of compressed data, which streaming refuses). Any negative byte skip is
   * taken as -1. */
  bool AtEnd{ false };
  /** Deflate only: bytes of the inflated data before the voxels (NIfTI's vox_offset in a .nii.gz, NRRD's byte
   * skip of compressed data). */
  std::uint64_t InflatedOffset{ 0 };
  /** Deflate, MetaImage only: its CompressedDataSize, the bytes ITK's reader takes from Offset on and inflates as
   * one stream; none when the header gives no whole number of bytes there. */
  std::optional<std::uint64_t> CompressedBytes;
};

/** The image file formats whose files the tools check themselves. */
enum class ImageFileFormat
{
  Nrrd,
  MetaImage,
  Nifti,
  Png,
  /** Any other format: ITK's reader and writer alone check it. */
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
  /** The size of the voxels in bytes, as the header describes them (sizes times bytes per voxel), when it says;
   * the largest 64-bit number when that product overflows. */
  std::optional<std::uint64_t> DataBytes;
  /** Whether the header has a fault that must be refused before ITK reads it: one its reader does not survive (a
   * MetaImage field name of 255 characters or more overflows MetaIO's buffer), misreads or reports without saying
   * what is wrong (sizes that are not whole numbers of at least 1). */
  bool UnsafeForItk{ false };
  /** Whether the header names its data files as a list or a numbered series (even a series of one file). */
  bool DataFileSeries{ false };
  /** A MetaImage list or numbered series: how many files its reader reads, each for the next slice (or slab) of
   * SeriesFileBytes bytes; 0 when the header does not say. */
  std::uint64_t SeriesFiles{ 0 };
  std::uint64_t SeriesFileBytes{ 0 };
  /** Whether the voxels' bytes are stored most significant first: NRRD's "endian: big", MetaImage's
   * BinaryDataByteOrderMSB or ElementByteOrderMSB True (whichever of them comes last). */
  bool BigEndian{ false };
  /** MetaImage's BinaryData False (on any of its lines): the voxels are written as text. */
  bool TextData{ false };
  /** With TextData: the number of values the header describes (sizes times channels), when it says. */
  std::optional<std::uint64_t> TextValues;
  /** NRRD's encoding field in lower case ("raw", "gzip", "ascii", ...); empty for the other formats. */
  std::string EncodingName;
};

/** The format of the image file \a path by its extension, as ITK knows it (case does not count). */
ImageFileFormat
ImageFileFormatOf(const std::filesystem::path & path);

/** Whether the file \a path begins with PNG's eight-byte signature. */
bool
StartsWithPngSignature(const std::filesystem::path & path);

/** The parts of the image file \a path, its format known by ImageFileFormatOf(), or PNG whatever its name when it
 * begins with PNG's signature (ITK's readers take such a file as PNG when the format its name gives declines it): for
 * NRRD (.nrrd, .nhdr), MetaImage (.mha, .mhd) and NIfTI (.nii, .nii.gz, .hdr + .img), read from its header (data files
 * are relative to the header's directory); for every other format the file alone, with no Data. Data files are named
 * whether or not they exist. Sets \a problem, saying why (e.g. "its header is cut short"), when the header of one of
 * those formats cannot be read. */
ImageFileParts
FindImageFileParts(const std::filesystem::path & path, std::string & problem);
} // namespace sic

#endif
