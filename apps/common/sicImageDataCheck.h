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
#ifndef sicImageDataCheck_h
#define sicImageDataCheck_h

// Whether an image file holds all it should, checked without ITK: ITK's MetaImage and NIfTI readers accept
// truncated files (with a warning or silently), its NRRD reader accepts gzip data that fails its checksum, and
// its MetaImage and NIfTI writers only warn when a write fails.

#include "sicImageFileParts.h"

#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace sic
{
/** Why the image file of \a parts does not hold all its voxels, as a phrase to follow the file's name (e.g. "is
 * incomplete: its data file 'x.raw' holds 10 bytes and its header describes 3400000000"); empty when it does, or for
 * ImageFileFormat::Other. Data files must be regular files; raw data as long as the header describes; compressed data
 * complete zlib or gzip streams that pass their checksums and inflate to exactly those bytes (and MetaImage's
 * CompressedDataSize what its stream takes); a PNG file's chunks complete, passing their CRCs, up to IEND. */
std::string
ImageFileProblem(const ImageFileParts & parts);

/** What Inflate() found: the bytes the data inflate to, and the compressed bytes that hold them. */
struct InflatedData
{
  std::uint64_t Bytes{ 0 };
  std::uint64_t CompressedBytes{ 0 };
};

/** Inflates the zlib or gzip stream at byte \a offset of \a file, checking its checksum, and with \a members the gzip
 * members that follow it, as NRRD's and NIfTI's readers do (then the first must be gzip; what follows the last is
 * ignored, as zlib's reader ignores it); MetaImage's reader takes the first stream alone. Sets \a problem ("is
 * missing", "is cut short", "fails its checksum (...)", "is corrupt (...)", "is not gzip data (...)") when the data
 * are not complete, intact zlib or gzip data. */
InflatedData
Inflate(const std::filesystem::path & file, std::uint64_t offset, bool members, std::string & problem);

/** The \a problem Inflate() found in \a data (e.g. "its compressed data") as a phrase to follow the file's name. */
std::string
CompressedDataProblem(const std::string & data, const std::string & problem);

/** Feeds zlib's stream with the zlib or gzip data of a file (not owned) from where it stands, gzip member after
 * member: what Inflate() and the streaming reader share. */
class InflateInput
{
public:
  explicit InflateInput(std::FILE * file);
  ~InflateInput();
  InflateInput(const InflateInput &) = delete;
  InflateInput &
  operator=(const InflateInput &) = delete;

  /** Starts zlib, taking a zlib or a gzip header; false when it cannot (out of memory). */
  bool
  Start();

  z_stream &
  Stream()
  {
    return m_Stream;
  }

  /** Reads more of the file after the input not inflated yet; false when no input is left. */
  bool
  Fill();

  /** After a stream ended: starts the gzip member that follows, if any (pigz, bgzip and concatenated files). */
  bool
  NextMember();

  /** The bytes of the file that zlib has taken. */
  std::uint64_t
  Consumed() const
  {
    return m_Read - m_Stream.avail_in;
  }

private:
  std::FILE *                m_File;
  z_stream                   m_Stream{};
  bool                       m_Started{ false };
  std::vector<unsigned char> m_Input;
  std::uint64_t              m_Read{ 0 };
};
} // namespace sic

#endif
