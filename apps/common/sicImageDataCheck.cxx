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
#include "sicImageDataCheck.h"
#include "sicStrings.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <memory>
#include <new>
#include <vector>

namespace sic
{
namespace fs = std::filesystem;

namespace
{
std::string
ZlibProblem(int status, const char * message)
{
  const std::string text = message != nullptr ? message : "";
  if (status == Z_MEM_ERROR)
  {
    throw std::bad_alloc();
  }
  if (text == "incorrect data check")
  {
    return "fails its checksum (incorrect data check)";
  }
  if (text == "incorrect length check")
  {
    return "fails its length check (incorrect length check)";
  }
  return "is corrupt (" + (text.empty() ? "zlib status " + std::to_string(status) : text) + ")";
}

std::string
Bytes(std::uint64_t count)
{
  return std::to_string(count) + (count == 1 ? " byte" : " bytes");
}

std::uint32_t
BigEndian32(const unsigned char * bytes)
{
  return (std::uint32_t{ bytes[0] } << 24) | (std::uint32_t{ bytes[1] } << 16) | (std::uint32_t{ bytes[2] } << 8) |
         std::uint32_t{ bytes[3] };
}

bool
IsChunk(const unsigned char * type, const char * name)
{
  return std::equal(type, type + 4, name);
}

/** Why the IHDR chunk \a data of \a length bytes does not describe an image libpng reads, or empty. */
std::string
PngHeaderProblem(const unsigned char * data, std::uint64_t length)
{
  if (length != 13)
  {
    return "is corrupt: its IHDR chunk has " + std::to_string(length) + " bytes instead of 13";
  }
  // libpng refuses, by default, images wider or taller than a million pixels.
  constexpr std::uint32_t largest = 1000000;
  const std::uint32_t     width = BigEndian32(data);
  const std::uint32_t     height = BigEndian32(data + 4);
  if (width == 0 || height == 0 || width > largest || height > largest)
  {
    return "is corrupt or too large: its IHDR chunk gives " + std::to_string(width) + " x " + std::to_string(height) +
           " pixels (1 to " + std::to_string(largest) + " along each axis are read)";
  }
  const unsigned int depth = data[8];
  const unsigned int colour = data[9];
  // The bit depths PNG defines for each colour type (grey, none, RGB, palette, grey and alpha, none, RGBA), as
  // sets of powers of two.
  static constexpr unsigned int depths[] = { 1 | 2 | 4 | 8 | 16, 0, 8 | 16, 1 | 2 | 4 | 8, 8 | 16, 0, 8 | 16 };
  const bool valid = colour < 7 && depth > 0 && (depth & (depth - 1)) == 0 && (depths[colour] & depth) != 0;
  if (!valid)
  {
    return "is corrupt: its IHDR chunk gives colour type " + std::to_string(colour) + " with bit depth " +
           std::to_string(depth) + ", which PNG does not define";
  }
  if (data[10] != 0 || data[11] != 0 || data[12] > 1)
  {
    return "is corrupt: its IHDR chunk gives compression method " + std::to_string(data[10]) + ", filter method " +
           std::to_string(data[11]) + " and interlace method " + std::to_string(data[12]) +
           " (PNG defines 0, 0 and 0 or 1)";
  }
  return {};
}

/** The largest IDAT chunk libpng accepts for the image of the IHDR chunk \a header: the image's filtered bytes
 * and the most a zlib stream can add to them. */
std::uint64_t
LargestIdatChunk(const unsigned char * header)
{
  static constexpr unsigned int channels[] = { 1, 0, 3, 1, 2, 0, 4 };
  const std::uint64_t           width = BigEndian32(header);
  const std::uint64_t           height = BigEndian32(header + 4);
  const std::uint64_t rowBytes = width * channels[header[9]] * (header[8] > 8 ? 2 : 1) + 1 + (header[12] != 0 ? 6 : 0);
  constexpr std::uint64_t largest = std::numeric_limits<std::int32_t>::max();
  const std::uint64_t     image = height * rowBytes;
  return std::min(largest, image + 6 + 5 * (image / std::min<std::uint64_t>(rowBytes, 32566) + 1));
}

/** Why \a path is not a complete PNG file libpng reads without failing, or empty. Every chunk must be complete and pass
 * its CRC. The chunks before the image data are checked as libpng checks them (ITK's reader of a PNG's header cannot
 * recover from libpng's errors there): IHDR first and valid, chunk names of four letters, no critical chunk PNG does
 * not define, a palette of whole entries before the image data, no ancillary chunk larger than libpng allocates. */
std::string
PngProblem(const fs::path & path)
{
  if (!StartsWithPngSignature(path))
  {
    return "is not a PNG file (no PNG signature)";
  }
  constexpr std::uint64_t    signatureBytes = 8;
  std::ifstream              file(path, std::ios::binary);
  std::vector<unsigned char> chunk;
  file.ignore(signatureBytes);
  std::error_code               error;
  const std::uint64_t           size = fs::file_size(path, error);
  std::uint64_t                 position = signatureBytes;
  std::array<unsigned char, 13> header{};
  bool                          haveHeader = false;
  bool                          havePalette = false;
  bool                          haveData = false;
  while (true)
  {
    unsigned char head[8];
    if (!file.read(reinterpret_cast<char *>(head), sizeof(head)))
    {
      return "is cut short: it ends before its IEND chunk";
    }
    const unsigned char * type = head + 4;
    const std::uint64_t   length = BigEndian32(head);
    if (!std::all_of(type, type + 4, [](unsigned char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }))
    {
      return "is corrupt: it holds a chunk whose name is not four letters";
    }
    const bool isData = IsChunk(type, "IDAT");
    // libpng's limits: 2^31 - 1 bytes for any chunk, the image's size for the image data, 8,000,000 bytes for
    // the chunks it keeps in memory.
    if (length > std::numeric_limits<std::int32_t>::max() ||
        (haveHeader && isData && length > LargestIdatChunk(header.data())) ||
        (!isData && !IsChunk(type, "IEND") && length > 8000000))
    {
      return "is corrupt or unreadable: its " + std::string(type, type + 4) + " chunk claims " + Bytes(length) +
             ", more than PNG readers accept";
    }
    if (length > size - std::min(size, position + 12))
    {
      return "is cut short: a chunk goes beyond the end of the file";
    }
    chunk.assign(type, type + 4);
    chunk.resize(4 + length + 4);
    if (!file.read(reinterpret_cast<char *>(chunk.data() + 4), static_cast<std::streamsize>(length + 4)))
    {
      return "is cut short: a chunk goes beyond the end of the file";
    }
    if (crc32(crc32(0L, Z_NULL, 0), chunk.data(), static_cast<uInt>(4 + length)) !=
        BigEndian32(chunk.data() + 4 + length))
    {
      return "is corrupt: a chunk fails its CRC";
    }
    position += 12 + length;
    const unsigned char * data = chunk.data() + 4;
    const bool            critical = type[0] >= 'A' && type[0] <= 'Z';
    if (IsChunk(type, "IHDR"))
    {
      if (haveHeader)
      {
        return "is corrupt: it holds two IHDR chunks";
      }
      const std::string problem = PngHeaderProblem(data, length);
      if (!problem.empty())
      {
        return problem;
      }
      std::copy(data, data + 13, header.begin());
      haveHeader = true;
      continue;
    }
    if (!haveHeader)
    {
      return "is corrupt: its first chunk is " + std::string(type, type + 4) + " instead of IHDR";
    }
    if (IsChunk(type, "PLTE"))
    {
      if (havePalette || haveData || length == 0 || length % 3 != 0 || length > 3 * 256)
      {
        return "is corrupt: its PLTE chunk (the palette) is repeated, misplaced or not 1 to 256 whole entries";
      }
      havePalette = true;
    }
    else if (isData)
    {
      if (!haveData && header[9] == 3 && !havePalette)
      {
        return "is corrupt: its image data comes before the palette (PLTE) it needs";
      }
      haveData = true;
    }
    else if (IsChunk(type, "IEND"))
    {
      return haveData ? std::string() : "is corrupt: it ends (IEND) before any image data (IDAT)";
    }
    else if (critical && !haveData)
    {
      return "is corrupt: it holds the chunk " + std::string(type, type + 4) +
             ", which a PNG reader must understand and PNG does not define";
    }
  }
}

/** Why the CompressedDataSize of a MetaImage's \a segment is not \a compressedBytes, the bytes its stream takes;
 * empty when it is. ITK's reader inflates that many bytes alone, from the data file's first byte when the field is
 * missing, and leaves the voxels it did not get zero. */
std::string
CompressedSizeProblem(const ImageDataSegment & segment, std::uint64_t compressedBytes)
{
  const std::string expected = "; expected 'CompressedDataSize = " + std::to_string(compressedBytes) + "'";
  if (!segment.CompressedBytes && segment.Offset > 0)
  {
    return "its header gives no CompressedDataSize, which ITK needs for data that do not start their file" + expected;
  }
  if (segment.CompressedBytes && *segment.CompressedBytes != compressedBytes)
  {
    return "its header gives 'CompressedDataSize = " + std::to_string(*segment.CompressedBytes) +
           "' and its compressed data take " + Bytes(compressedBytes) + expected;
  }
  return {};
}

/** Why the text voxels of a MetaImage (BinaryData False), from \a offset of \a file on, are not \a count numbers;
 * empty when they are. ITK's reader takes a short or garbled text as it comes, leaving the voxels it did not get
 * with whatever they held. */
std::string
TextDataProblem(const fs::path & file, std::uint64_t offset, std::uint64_t count)
{
  std::ifstream stream(file, std::ios::binary);
  stream.seekg(static_cast<std::streamoff>(offset));
  std::uint64_t values = 0;
  std::string   word;
  while (values < count && stream >> word)
  {
    char * end = nullptr;
    std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0')
    {
      return "is corrupt: its text voxels hold " + Quoted(word) + " as value " + std::to_string(values + 1) +
             "; expected a number for each of the " + std::to_string(count) + " values its header describes";
    }
    ++values;
  }
  if (values < count)
  {
    return "is incomplete: its text voxels hold " + std::to_string(values) + " values and its header describes " +
           std::to_string(count);
  }
  return {};
}
} // namespace

InflateInput::InflateInput(std::FILE * file)
  : m_File(file)
  , m_Input(262144)
{}

InflateInput::~InflateInput()
{
  if (m_Started)
  {
    inflateEnd(&m_Stream);
  }
}

bool
InflateInput::Start()
{
  // 15 + 32: a zlib or a gzip header, whichever the stream has.
  m_Started = inflateInit2(&m_Stream, 15 + 32) == Z_OK;
  return m_Started;
}

bool
InflateInput::Fill()
{
  const size_t kept = m_Stream.avail_in;
  std::copy(m_Stream.next_in, m_Stream.next_in + kept, m_Input.begin());
  const size_t got = std::fread(m_Input.data() + kept, 1, m_Input.size() - kept, m_File);
  m_Read += got;
  m_Stream.next_in = m_Input.data();
  m_Stream.avail_in = static_cast<uInt>(kept + got);
  return m_Stream.avail_in > 0;
}

bool
InflateInput::NextMember()
{
  if (m_Stream.avail_in < 2)
  {
    Fill();
  }
  return m_Stream.avail_in >= 2 && m_Stream.next_in[0] == 0x1f && m_Stream.next_in[1] == 0x8b &&
         inflateReset(&m_Stream) == Z_OK;
}

InflatedData
Inflate(const fs::path & path, std::uint64_t offset, bool members, std::string & problem)
{
  problem.clear();
  const std::unique_ptr<std::FILE, int (*)(std::FILE *)> file(std::fopen(path.string().c_str(), "rb"), std::fclose);
  if (!file || fseeko(file.get(), static_cast<off_t>(offset), SEEK_SET) != 0)
  {
    problem = "is missing";
    return {};
  }
  InflateInput input(file.get());
  if (!input.Start())
  {
    throw std::bad_alloc();
  }
  z_stream &                 stream = input.Stream();
  std::vector<unsigned char> scratch(262144);
  InflatedData               inflated;
  bool                       started = false;
  while (true)
  {
    if (stream.avail_in == 0 && !input.Fill())
    {
      problem = started ? "is cut short" : "is missing";
      return inflated;
    }
    if (!started && members && stream.avail_in >= 2 && (stream.next_in[0] != 0x1f || stream.next_in[1] != 0x8b))
    {
      // NRRD's and NIfTI's readers (zlib's gzread) take data that are not gzip as uncompressed voxels.
      problem = "is not gzip data (which starts with the bytes 1f 8b)";
      return inflated;
    }
    started = true;
    int status = Z_OK;
    while (status == Z_OK && (stream.avail_in > 0 || stream.avail_out == 0))
    {
      stream.next_out = scratch.data();
      stream.avail_out = static_cast<uInt>(scratch.size());
      status = inflate(&stream, Z_NO_FLUSH);
      inflated.Bytes += scratch.size() - stream.avail_out;
    }
    // Z_BUF_ERROR with all input taken: no progress without more input, not an error yet.
    if (status == Z_OK || (status == Z_BUF_ERROR && stream.avail_in == 0))
    {
      continue;
    }
    if (status != Z_STREAM_END)
    {
      problem = ZlibProblem(status, stream.msg);
      return inflated;
    }
    // One stream ended, checksum and all: another gzip member may follow.
    inflated.CompressedBytes = input.Consumed();
    if (!members || !input.NextMember())
    {
      return inflated;
    }
  }
}

std::string
CompressedDataProblem(const std::string & data, const std::string & problem)
{
  const bool incomplete = problem == "is missing" || problem == "is cut short";
  return (incomplete ? "is incomplete: " : "is corrupt: ") + data + " " + problem;
}

std::string
ImageFileProblem(const ImageFileParts & parts)
{
  if (parts.Format == ImageFileFormat::Png)
  {
    return PngProblem(parts.Files.front());
  }
  if (parts.SeriesFiles > 0 && parts.Data.size() < parts.SeriesFiles)
  {
    return "is incomplete: its header describes " + std::to_string(parts.SeriesFiles) +
           " data files of a slice each and names " + std::to_string(parts.Data.size());
  }
  // A file of a series that holds less than its slice leaves the rest of the slice unread.
  const auto shortFile = [&](const ImageDataSegment & segment, std::uint64_t bytes) {
    return "is incomplete: its data file " + Quoted(segment.File) + " holds " + Bytes(bytes) +
           " of voxels and each file of its series holds a slice of " + Bytes(parts.SeriesFileBytes);
  };
  std::uint64_t available = 0;
  bool          checked = !parts.Data.empty();
  // Whether the data are compressed and should inflate to the voxels alone.
  bool exact = checked;
  for (const ImageDataSegment & segment : parts.Data)
  {
    std::error_code error;
    const auto      status = fs::status(segment.File, error);
    if (!fs::exists(status))
    {
      return "is incomplete: its data file " + Quoted(segment.File) + " does not exist";
    }
    if (!fs::is_regular_file(status))
    {
      return "is unreadable: its data file " + Quoted(segment.File) + " is not a regular file";
    }
    if (segment.Encoding == ImageDataEncoding::Unchecked)
    {
      checked = false;
      continue;
    }
    if (segment.Encoding == ImageDataEncoding::Raw && parts.TextValues && parts.Data.size() == 1 && !segment.AtEnd)
    {
      const std::string problem = TextDataProblem(segment.File, segment.Offset, *parts.TextValues);
      if (!problem.empty())
      {
        return problem;
      }
      checked = false;
      continue;
    }
    if (segment.Encoding == ImageDataEncoding::Raw)
    {
      exact = false;
      const std::uint64_t size = fs::file_size(segment.File, error);
      const std::uint64_t bytes = segment.AtEnd ? size : size - std::min(size, segment.Offset);
      if (bytes < parts.SeriesFileBytes)
      {
        return shortFile(segment, bytes);
      }
      available += bytes;
      continue;
    }
    const bool         metaImage = parts.Format == ImageFileFormat::MetaImage;
    std::string        problem;
    const InflatedData inflated = Inflate(segment.File, segment.Offset, !metaImage, problem);
    if (!problem.empty())
    {
      return CompressedDataProblem(segment.File == parts.Files.front()
                                     ? std::string("its compressed data")
                                     : "the compressed data of its data file " + Quoted(segment.File),
                                   problem);
    }
    if (metaImage && !parts.DataFileSeries)
    {
      problem = CompressedSizeProblem(segment, inflated.CompressedBytes);
      if (!problem.empty())
      {
        return problem;
      }
    }
    const std::uint64_t bytes = inflated.Bytes - std::min(inflated.Bytes, segment.InflatedOffset);
    if (bytes < parts.SeriesFileBytes)
    {
      return shortFile(segment, bytes);
    }
    available += bytes;
    exact = exact && !segment.AtEnd;
  }
  if (checked && parts.DataBytes && available < *parts.DataBytes)
  {
    const bool        own = parts.Data.size() == 1 && parts.Data.front().File == parts.Files.front();
    const std::string where = own                      ? std::string("it holds ")
                              : parts.Data.size() == 1 ? "its data file " + Quoted(parts.Data.front().File) + " holds "
                                                       : "its data files hold ";
    return "is incomplete: " + where + Bytes(available) + " of voxels and its header describes " +
           Bytes(*parts.DataBytes);
  }
  // More voxels than the header describes: its sizes or type are wrong, and no reader can tell which voxels are
  // meant. Raw data may be followed by other bytes.
  if (checked && exact && parts.DataBytes && available > *parts.DataBytes)
  {
    return "is inconsistent: its compressed data inflate to " + Bytes(available) +
           " of voxels and its header describes " + Bytes(*parts.DataBytes) + "; expected exactly as many";
  }
  return {};
}
} // namespace sic
