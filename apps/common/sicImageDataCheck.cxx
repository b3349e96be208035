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

#include "itk_zlib.h"

#include <array>
#include <fstream>
#include <limits>
#include <new>
#include <vector>

namespace sic
{
namespace fs = std::filesystem;

namespace
{
/** Inflates into a scratch buffer, counting the bytes; owns the zlib stream. */
class Inflater
{
public:
  Inflater()
  {
    // 15 + 32: a zlib or a gzip header, whichever the stream has.
    if (inflateInit2(&m_Stream, 15 + 32) != Z_OK)
    {
      throw std::bad_alloc();
    }
  }
  Inflater(const Inflater &) = delete;
  Inflater &
  operator=(const Inflater &) = delete;
  ~Inflater() { inflateEnd(&m_Stream); }

  z_stream &
  Stream()
  {
    return m_Stream;
  }

  /** Inflates what is in the stream's input; returns zlib's status (Z_OK when more input is needed). */
  int
  Run(std::uint64_t & inflated)
  {
    int status = Z_OK;
    while (status == Z_OK && (m_Stream.avail_in > 0 || m_Stream.avail_out == 0))
    {
      m_Stream.next_out = m_Scratch.data();
      m_Stream.avail_out = static_cast<uInt>(m_Scratch.size());
      status = inflate(&m_Stream, Z_NO_FLUSH);
      inflated += m_Scratch.size() - m_Stream.avail_out;
      if (status == Z_BUF_ERROR && m_Stream.avail_in == 0)
      {
        // No progress without more input: not an error yet.
        status = Z_OK;
        break;
      }
    }
    return status;
  }

private:
  z_stream                          m_Stream{};
  std::array<unsigned char, 262144> m_Scratch;
};

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

/** Why \a path is not a complete PNG file, or empty. */
std::string
PngProblem(const fs::path & path)
{
  std::ifstream              file(path, std::ios::binary);
  const std::array<char, 8>  signature{ { '\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n' } };
  std::array<char, 8>        start{};
  std::vector<unsigned char> chunk;
  if (!file.read(start.data(), start.size()) || start != signature)
  {
    return "is not a PNG file (no PNG signature)";
  }
  std::error_code     error;
  const std::uint64_t size = fs::file_size(path, error);
  std::uint64_t       position = start.size();
  while (true)
  {
    unsigned char head[8];
    if (!file.read(reinterpret_cast<char *>(head), sizeof(head)))
    {
      return "is cut short: it ends before its IEND chunk";
    }
    const std::uint64_t length = (std::uint64_t{ head[0] } << 24) | (head[1] << 16) | (head[2] << 8) | head[3];
    if (length > size - std::min(size, position + 12))
    {
      return "is cut short: a chunk goes beyond the end of the file";
    }
    chunk.assign(head + 4, head + 8);
    chunk.resize(4 + length + 4);
    if (!file.read(reinterpret_cast<char *>(chunk.data() + 4), static_cast<std::streamsize>(length + 4)))
    {
      return "is cut short: a chunk goes beyond the end of the file";
    }
    const unsigned char * stored = chunk.data() + 4 + length;
    const std::uint32_t   expected =
      (std::uint32_t{ stored[0] } << 24) | (stored[1] << 16) | (stored[2] << 8) | stored[3];
    if (crc32(crc32(0L, Z_NULL, 0), chunk.data(), static_cast<uInt>(4 + length)) != expected)
    {
      return "is corrupt: a chunk fails its CRC";
    }
    position += 12 + length;
    if (chunk[0] == 'I' && chunk[1] == 'E' && chunk[2] == 'N' && chunk[3] == 'D')
    {
      return {};
    }
  }
}

std::string
Bytes(std::uint64_t count)
{
  return std::to_string(count) + (count == 1 ? " byte" : " bytes");
}
} // namespace

std::uint64_t
InflatedSize(const fs::path & path, std::uint64_t offset, std::string & problem)
{
  problem.clear();
  std::ifstream file(path, std::ios::binary);
  file.seekg(static_cast<std::streamoff>(offset));
  if (!file)
  {
    problem = "is missing";
    return 0;
  }
  std::vector<unsigned char> input(262144);
  Inflater                   inflater;
  z_stream &                 stream = inflater.Stream();
  std::uint64_t              inflated = 0;
  bool                       started = false;
  while (true)
  {
    if (stream.avail_in == 0)
    {
      file.read(reinterpret_cast<char *>(input.data()), static_cast<std::streamsize>(input.size()));
      stream.next_in = input.data();
      stream.avail_in = static_cast<uInt>(file.gcount());
      if (stream.avail_in == 0)
      {
        problem = started ? "is cut short" : "is missing";
        return inflated;
      }
    }
    started = true;
    const int status = inflater.Run(inflated);
    if (status == Z_OK)
    {
      continue;
    }
    if (status != Z_STREAM_END)
    {
      problem = ZlibProblem(status, stream.msg);
      return inflated;
    }
    // One stream ended, checksum and all: another gzip member may follow.
    if (stream.avail_in < 2)
    {
      const size_t kept = stream.avail_in;
      std::copy(stream.next_in, stream.next_in + kept, input.begin());
      file.read(reinterpret_cast<char *>(input.data() + kept), static_cast<std::streamsize>(input.size() - kept));
      stream.next_in = input.data();
      stream.avail_in = static_cast<uInt>(kept + static_cast<size_t>(file.gcount()));
    }
    if (stream.avail_in < 2 || stream.next_in[0] != 0x1f || stream.next_in[1] != 0x8b)
    {
      return inflated;
    }
    inflateReset(&stream);
  }
}

std::string
ImageFileProblem(const ImageFileParts & parts)
{
  if (parts.Format == ImageFileFormat::Png)
  {
    return PngProblem(parts.Files.front());
  }
  std::uint64_t available = 0;
  bool          checked = !parts.Data.empty();
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
    if (segment.Encoding == ImageDataEncoding::Raw)
    {
      const std::uint64_t size = fs::file_size(segment.File, error);
      available += segment.AtEnd ? size : size - std::min(size, segment.Offset);
      continue;
    }
    std::string         problem;
    const std::uint64_t inflated = InflatedSize(segment.File, segment.Offset, problem);
    if (!problem.empty())
    {
      const bool incomplete = problem == "is cut short" || problem == "is missing";
      return (incomplete ? "is incomplete: " : "is corrupt: ") +
             (segment.File == parts.Files.front() ? std::string("its compressed data")
                                                  : "the compressed data of its data file " + Quoted(segment.File)) +
             " " + problem;
    }
    available += inflated - std::min(inflated, segment.InflatedOffset);
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
  return {};
}
} // namespace sic
