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
#include "sicStreamedImageFiles.h"
#include "sicImageDataCheck.h"
#include "sicImageFileParts.h"
#include "sicImageFiles.h"
#include "sicStrings.h"
#include "sicToolError.h"

#include "itkByteSwapper.h"
#include "itkImageIOFactory.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <utility>

namespace sic
{
namespace
{
constexpr std::size_t CompressedChunk = std::size_t{ 256 } << 10;

std::string
Number(double value)
{
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

/** \a values, each after a space; numbers as precisely as Number() gives them. */
template <typename T>
std::string
Listed(const std::vector<T> & values)
{
  std::ostringstream out;
  out.precision(17);
  for (const T & value : values)
  {
    out << " " << value;
  }
  return out.str();
}

/** The parts of the MetaImage or NRRD file \a path, as its header says (FindImageFileParts, which has skipped
 * NRRD's lines and raw bytes to skip): one data segment; refuses what does not stream. */
ImageFileParts
StreamedParts(const std::string & path, const std::string & what)
{
  std::string          problem;
  const ImageFileParts parts = FindImageFileParts(path, problem);
  if (!problem.empty())
  {
    throw ToolError("cannot read " + what + " " + Quoted(path) + ": " + problem);
  }
  const auto refuse = [&](const std::string & reason) {
    throw ToolError("cannot stream " + what + " " + Quoted(path) + ": " + reason + "; " + StreamableFormats());
  };
  if (parts.Format != ImageFileFormat::MetaImage && parts.Format != ImageFileFormat::Nrrd)
  {
    refuse(parts.Format == ImageFileFormat::Png ? "it is a PNG file, whatever its name says"
                                                : "it is neither MetaImage nor NRRD");
  }
  if (parts.TextData)
  {
    refuse("its voxels are stored as text");
  }
  for (const ImageDataSegment & segment : parts.Data)
  {
    if (segment.Encoding == ImageDataEncoding::Unchecked)
    {
      refuse("its encoding is " + parts.EncodingName);
    }
    if (segment.Encoding == ImageDataEncoding::Deflate && (segment.AtEnd || segment.InflatedOffset > 0))
    {
      refuse("it skips bytes of gzip-compressed data");
    }
  }
  if (parts.DataFileSeries || parts.Data.size() != 1)
  {
    refuse("its voxels are spread over several files");
  }
  return parts;
}
} // namespace

uint64_t
VolumeGeometry::PlaneVoxels() const
{
  uint64_t voxels = 1;
  for (unsigned int a = 0; a + 1 < Dimension; ++a)
  {
    voxels *= Size[a];
  }
  return voxels;
}

unsigned int
VolumeGeometry::PixelBytes() const
{
  const PixelTypeEntry * type = FindPixelType(ComponentType, true);
  return type != nullptr ? type->Bytes : 0;
}

bool
IsStreamableImageFile(const std::string & path)
{
  const ImageFileFormat format = ImageFileFormatOf(path);
  return format == ImageFileFormat::MetaImage || format == ImageFileFormat::Nrrd;
}

std::string
StreamableFormats()
{
  return "streaming reads and writes MetaImage (.mha, .mhd) and NRRD (.nrrd, .nhdr) files with raw, "
         "zlib or gzip data";
}

struct PlaneReader::Data
{
  std::unique_ptr<std::FILE, int (*)(std::FILE *)> File{ nullptr, std::fclose };
  ImageDataSegment                                 Where;
  bool                                             BigEndian{ false };
  std::unique_ptr<InflateInput>                    Input;
  bool                                             StreamEnded{ false };
  uint64_t                                         BytesRead{ 0 };
  uint64_t                                         BytesTotal{ 0 };

  /** Inflates the next compressed bytes into the stream's output; throws \a cutShort (after the image's name)
   * when the data file holds no more, and says so when the data are corrupt. */
  int
  Inflate(const std::string & image, const std::string & cutShort)
  {
    z_stream & stream = Input->Stream();
    if (stream.avail_in == 0 && !Input->Fill())
    {
      throw ToolError(image + cutShort);
    }
    const int status = inflate(&stream, Z_NO_FLUSH);
    if (status != Z_OK && status != Z_STREAM_END && status != Z_BUF_ERROR)
    {
      throw ToolError(image + " is corrupt: its compressed data fail to decompress (" +
                      (stream.msg != nullptr ? stream.msg : "zlib error") + ")");
    }
    return status;
  }
};

PlaneReader::PlaneReader(const std::string & path, const std::string & what)
  : m_Name(what + " " + Quoted(path))
  , m_Data(std::make_unique<Data>())
{
  const auto cannotRead = [&](const std::string & why) { throw ToolError("cannot read " + m_Name + ": " + why); };
  itk::ImageIOBase::Pointer io =
    itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode);
  if (!io)
  {
    cannotRead("not a MetaImage or NRRD file ITK can read");
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
  const unsigned int n = io->GetNumberOfDimensions();
  m_Geometry.Dimension = n;
  m_Geometry.ComponentType = io->GetComponentType();
  m_Geometry.Direction.resize(n * n);
  for (unsigned int a = 0; a < n; ++a)
  {
    // As ITK's reader does for the in-memory mode: a negative spacing is made positive and its axis's direction
    // flipped, which places every voxel where it was (and gives --max-volume a positive voxel volume).
    const double sign = io->GetSpacing(a) < 0.0 ? -1.0 : 1.0;
    m_Geometry.Size.push_back(io->GetDimensions(a));
    m_Geometry.Spacing.push_back(sign * io->GetSpacing(a));
    m_Geometry.Origin.push_back(io->GetOrigin(a));
    for (unsigned int row = 0; row < n; ++row)
    {
      // No "-0" in the header written.
      m_Geometry.Direction[row * n + a] = io->GetDirection(a)[row] == 0.0 ? 0.0 : sign * io->GetDirection(a)[row];
    }
  }

  Data &               data = *m_Data;
  const ImageFileParts parts = StreamedParts(path, what);
  data.Where = parts.Data.front();
  data.BigEndian = parts.BigEndian;
  data.BytesTotal = m_Geometry.PlaneVoxels() * m_Geometry.Planes() * m_Geometry.PixelBytes();
  const bool      compressed = data.Where.Encoding == ImageDataEncoding::Deflate;
  const auto      dataFile = "its data file " + Quoted(data.Where.File);
  std::error_code error;
  const auto      fileSize = std::filesystem::file_size(data.Where.File, error);
  if (error)
  {
    cannotRead(dataFile + " cannot be opened (" + error.message() + ")");
  }
  if (!std::filesystem::is_regular_file(data.Where.File))
  {
    cannotRead(dataFile + " is not a regular file");
  }
  data.File.reset(std::fopen(data.Where.File.string().c_str(), "rb"));
  if (!data.File)
  {
    cannotRead("cannot open " + dataFile + " (" + std::strerror(errno) + ")");
  }
  uint64_t offset = data.Where.Offset;
  if (!compressed)
  {
    if (data.Where.AtEnd)
    {
      offset = fileSize >= data.BytesTotal ? fileSize - data.BytesTotal : 0;
    }
    if (fileSize < offset + data.BytesTotal)
    {
      throw ToolError(m_Name + " is truncated: its header promises " + std::to_string(data.BytesTotal) +
                      " bytes of voxels but " + dataFile + " holds " +
                      std::to_string(fileSize > offset ? fileSize - offset : 0));
    }
  }
  if (fseeko(data.File.get(), static_cast<off_t>(offset), SEEK_SET) != 0)
  {
    cannotRead("cannot seek in its data file");
  }
  if (compressed)
  {
    data.Input = std::make_unique<InflateInput>(data.File.get());
    if (!data.Input->Start())
    {
      cannotRead("the decompressor could not start");
    }
  }
}

PlaneReader::~PlaneReader() = default;

void
PlaneReader::Read(void * buffer, uint64_t planes)
{
  Data &         data = *m_Data;
  const uint64_t bytes = planes * m_Geometry.PlaneVoxels() * m_Geometry.PixelBytes();
  if (data.BytesRead + bytes > data.BytesTotal)
  {
    throw ToolError("cannot read " + m_Name + ": more planes asked for than it has");
  }
  if (!data.Input)
  {
    if (std::fread(buffer, 1, bytes, data.File.get()) != bytes)
    {
      throw ToolError("cannot read " + m_Name + ": its data file " + Quoted(data.Where.File) +
                      " ended early or could not be read");
    }
  }
  else
  {
    z_stream & stream = data.Input->Stream();
    stream.next_out = static_cast<Bytef *>(buffer);
    uint64_t left = bytes;
    while (left > 0)
    {
      if (data.StreamEnded && data.Input->NextMember())
      {
        data.StreamEnded = false;
      }
      const std::string held = std::to_string(data.BytesRead + (bytes - left)) + " of the " +
                               std::to_string(data.BytesTotal) + " bytes of voxels its header promises";
      if (data.StreamEnded)
      {
        throw ToolError(m_Name + " is truncated: its compressed data hold " + held);
      }
      const auto chunk = static_cast<uInt>(std::min<uint64_t>(left, uint64_t{ 1 } << 30));
      stream.avail_out = chunk;
      const int status = data.Inflate(m_Name, " is truncated: its compressed data end after " + held);
      left -= chunk - stream.avail_out;
      data.StreamEnded = status == Z_STREAM_END;
    }
  }
  data.BytesRead += bytes;
  if (m_Geometry.PixelBytes() > 1 && data.BigEndian != itk::ByteSwapper<std::uint16_t>::SystemIsBigEndian())
  {
    const unsigned int size = m_Geometry.PixelBytes();
    for (auto * pixel = static_cast<uint8_t *>(buffer); pixel < static_cast<uint8_t *>(buffer) + bytes; pixel += size)
    {
      std::reverse(pixel, pixel + size);
    }
  }
}

void
PlaneReader::Finish()
{
  Data & data = *m_Data;
  if (data.BytesRead != data.BytesTotal || !data.Input)
  {
    return;
  }
  // The stream must end here, and its checksum match; so must any gzip members that follow, holding nothing.
  uint8_t scratch[64];
  while (!data.StreamEnded || data.Input->NextMember())
  {
    data.Input->Stream().next_out = scratch;
    data.Input->Stream().avail_out = sizeof(scratch);
    data.StreamEnded = data.Inflate(m_Name, " is truncated: its compressed data stop before their end") == Z_STREAM_END;
    if (data.Input->Stream().avail_out != sizeof(scratch))
    {
      throw ToolError(m_Name + " is inconsistent: its compressed data inflate to more than the " +
                      std::to_string(data.BytesTotal) +
                      " bytes of voxels its header describes; expected exactly as many");
    }
  }
}

struct PlaneWriter::Output
{
  ImageFileFormat Kind{ ImageFileFormat::Other };
  bool            Detached{ false };
  std::string     DataName;
  /** A detached header; an attached one is written to File. */
  std::FILE *          Header{ nullptr };
  std::FILE *          File{ nullptr };
  long                 SizeFieldAt{ -1 };
  z_stream             Stream{};
  bool                 Deflating{ false };
  std::vector<uint8_t> Out;
  uint64_t             CompressedBytes{ 0 };

  ~Output()
  {
    if (Deflating)
    {
      deflateEnd(&Stream);
    }
    for (std::FILE * file : { File, Header })
    {
      if (file != nullptr)
      {
        std::fclose(file);
      }
    }
  }

  /** Deflates the stream's input (\a flush as zlib takes it) into the data file; false when writing fails. */
  bool
  Deflate(int flush, int & status)
  {
    Stream.next_out = Out.data();
    Stream.avail_out = static_cast<uInt>(Out.size());
    status = deflate(&Stream, flush);
    const std::size_t produced = Out.size() - Stream.avail_out;
    CompressedBytes += produced;
    return produced == 0 || std::fwrite(Out.data(), 1, produced, File) == produced;
  }
};

namespace
{
/** The header text; MetaImage's CompressedDataSize is \a compressedSize. */
std::string
MetaImageHeader(const VolumeGeometry & geometry,
                bool                   compress,
                const std::string &    dataFile,
                const std::string &    compressedSize)
{
  std::ostringstream header;
  const unsigned int n = geometry.Dimension;
  header << "ObjectType = Image\nNDims = " << n << "\nBinaryData = True\nBinaryDataByteOrderMSB = False\n";
  header << "CompressedData = " << (compress ? "True" : "False") << "\n";
  if (compress)
  {
    header << "CompressedDataSize = " << compressedSize << "\n";
  }
  // MetaImage lists each axis's direction in turn.
  header << "TransformMatrix =";
  for (unsigned int column = 0; column < n; ++column)
  {
    for (unsigned int row = 0; row < n; ++row)
    {
      header << " " << Number(geometry.Direction[row * n + column]);
    }
  }
  header << "\nOffset =" << Listed(geometry.Origin) << "\nCenterOfRotation =" << Listed(std::vector<int>(n, 0))
         << "\nElementSpacing =" << Listed(geometry.Spacing) << "\nDimSize =" << Listed(geometry.Size);
  header << "\nElementType = " << FindPixelType(geometry.ComponentType, true)->MetaImageName
         << "\nElementDataFile = " << dataFile << "\n";
  return header.str();
}

std::string
NrrdHeader(const VolumeGeometry & geometry, bool compress, const std::string & dataFile)
{
  std::ostringstream header;
  const unsigned int n = geometry.Dimension;
  header << "NRRD0004\ntype: " << FindPixelType(geometry.ComponentType, true)->NrrdName << "\ndimension: " << n << "\n";
  if (n == 3)
  {
    header << "space: left-posterior-superior\n";
  }
  else
  {
    header << "space dimension: " << n << "\n";
  }
  header << "sizes:" << Listed(geometry.Size) << "\nspace directions:";
  for (unsigned int column = 0; column < n; ++column)
  {
    header << " (";
    for (unsigned int row = 0; row < n; ++row)
    {
      header << (row ? "," : "") << Number(geometry.Direction[row * n + column] * geometry.Spacing[column]);
    }
    header << ")";
  }
  header << "\nkinds:" << Listed(std::vector<std::string>(n, "domain"));
  header << "\nendian: " << (itk::ByteSwapper<std::uint16_t>::SystemIsBigEndian() ? "big" : "little")
         << "\nencoding: " << (compress ? "gzip" : "raw") << "\nspace origin: (";
  for (unsigned int a = 0; a < n; ++a)
  {
    header << (a ? "," : "") << Number(geometry.Origin[a]);
  }
  header << ")\n" << (dataFile.empty() ? "" : "data file: " + dataFile) << "\n";
  return header.str();
}

bool
WriteAll(std::FILE * file, const std::string & text)
{
  return std::fwrite(text.data(), 1, text.size(), file) == text.size();
}

/** Flushes and closes \a file, which is null afterwards; false when that fails. */
bool
Closed(std::FILE *& file)
{
  std::FILE * closing = std::exchange(file, nullptr);
  const bool  flushed = std::fflush(closing) == 0 && !std::ferror(closing);
  return std::fclose(closing) == 0 && flushed;
}

/** The error of a write that failed, e.g. on a full disk. */
ToolError
WriteFailed(const std::string & name)
{
  return ToolError("cannot write " + name + ": " + std::strerror(errno) + " (is the disk full?)");
}
} // namespace

PlaneWriter::PlaneWriter(const std::string &    path,
                         const std::string &    finalPath,
                         const std::string &    what,
                         const VolumeGeometry & geometry,
                         bool                   compress)
  : m_Path(path)
  , m_Name(what + " " + Quoted(finalPath))
  , m_Geometry(geometry)
  , m_Compress(compress)
  , m_Output(std::make_unique<Output>())
{
  Output &          out = *m_Output;
  const std::string name = Lowercase(finalPath);
  out.Kind = ImageFileFormatOf(finalPath);
  if (!IsStreamableImageFile(finalPath) || FindPixelType(geometry.ComponentType, true) == nullptr)
  {
    throw ToolError("cannot stream " + m_Name + ": " + StreamableFormats());
  }
  out.Detached = EndsWith(name, ".mhd") || EndsWith(name, ".nhdr");
  const auto fail = [&](const std::string & file) {
    throw ToolError("cannot write " + m_Name + ": cannot create " + file + " (" + std::strerror(errno) + ")");
  };
  if (out.Detached)
  {
    const std::string stem = std::filesystem::path(finalPath).stem().string();
    out.DataName =
      stem + (out.Kind == ImageFileFormat::MetaImage ? (compress ? ".zraw" : ".raw") : (compress ? ".raw.gz" : ".raw"));
    out.File = std::fopen((std::filesystem::path(path).parent_path() / out.DataName).string().c_str(), "wb");
    if (out.File == nullptr)
    {
      fail("its data file");
    }
    if (out.Kind == ImageFileFormat::Nrrd)
    {
      // A NRRD header names no size: write it now.
      out.Header = std::fopen(path.c_str(), "wb");
      if (out.Header == nullptr || !WriteAll(out.Header, NrrdHeader(geometry, compress, out.DataName)))
      {
        fail("its header");
      }
    }
  }
  else
  {
    out.File = std::fopen(path.c_str(), "wb");
    if (out.File == nullptr)
    {
      fail("the file");
    }
    // MetaImage's CompressedDataSize is filled in when it is known.
    const std::string header = out.Kind == ImageFileFormat::MetaImage
                                 ? MetaImageHeader(geometry, compress, "LOCAL", std::string(20, '0'))
                                 : NrrdHeader(geometry, compress, "");
    if (out.Kind == ImageFileFormat::MetaImage && compress)
    {
      const std::string field = "CompressedDataSize = ";
      out.SizeFieldAt = static_cast<long>(header.find(field) + field.size());
    }
    if (!WriteAll(out.File, header))
    {
      throw ToolError("cannot write " + m_Name + ": " + std::strerror(errno));
    }
  }
  if (compress)
  {
    // Level 1: for volumes this large, the fastest compression is most of the gain.
    const int windowBits = out.Kind == ImageFileFormat::Nrrd ? 15 + 16 : 15;
    if (deflateInit2(&out.Stream, 1, Z_DEFLATED, windowBits, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    {
      throw ToolError("cannot write " + m_Name + ": the compressor could not start");
    }
    out.Deflating = true;
    out.Out.resize(CompressedChunk);
  }
}

PlaneWriter::~PlaneWriter() = default;

void
PlaneWriter::Write(const void * buffer, uint64_t planes)
{
  Output &       out = *m_Output;
  const uint64_t bytes = planes * m_Geometry.PlaneVoxels() * m_Geometry.PixelBytes();
  if (m_PlanesWritten + planes > m_Geometry.Planes())
  {
    throw ToolError("cannot write " + m_Name + ": more planes than the image has");
  }
  if (!m_Compress)
  {
    if (std::fwrite(buffer, 1, bytes, out.File) != bytes)
    {
      throw WriteFailed(m_Name);
    }
  }
  else
  {
    out.Stream.next_in = static_cast<Bytef *>(const_cast<void *>(buffer));
    uint64_t left = bytes;
    while (left > 0 || out.Stream.avail_in > 0)
    {
      if (out.Stream.avail_in == 0)
      {
        const auto chunk = static_cast<uInt>(std::min<uint64_t>(left, uint64_t{ 1 } << 30));
        out.Stream.avail_in = chunk;
        left -= chunk;
      }
      int status = Z_OK;
      if (!out.Deflate(Z_NO_FLUSH, status))
      {
        throw WriteFailed(m_Name);
      }
    }
  }
  m_PlanesWritten += planes;
}

void
PlaneWriter::Finish()
{
  Output & out = *m_Output;
  if (m_PlanesWritten != m_Geometry.Planes())
  {
    throw ToolError("cannot write " + m_Name + ": only " + std::to_string(m_PlanesWritten) + " of its " +
                    std::to_string(m_Geometry.Planes()) + " planes were written");
  }
  if (m_Compress)
  {
    for (int status = Z_OK; status != Z_STREAM_END;)
    {
      if (!out.Deflate(Z_FINISH, status))
      {
        throw WriteFailed(m_Name);
      }
    }
    deflateEnd(&out.Stream);
    out.Deflating = false;
  }
  if (out.SizeFieldAt >= 0)
  {
    // Fill in the compressed size, zero-padded to the placeholder's width.
    std::string size = std::to_string(out.CompressedBytes);
    size.insert(0, 20 - size.size(), '0');
    if (fseeko(out.File, out.SizeFieldAt, SEEK_SET) != 0 || !WriteAll(out.File, size))
    {
      throw WriteFailed(m_Name);
    }
  }
  if (!Closed(out.File))
  {
    throw WriteFailed(m_Name);
  }
  if (out.Detached && out.Kind == ImageFileFormat::MetaImage)
  {
    out.Header = std::fopen(m_Path.c_str(), "wb");
    if (out.Header == nullptr ||
        !WriteAll(out.Header,
                  MetaImageHeader(m_Geometry, m_Compress, out.DataName, std::to_string(out.CompressedBytes))))
    {
      throw WriteFailed(m_Name);
    }
  }
  if (out.Header != nullptr && !Closed(out.Header))
  {
    throw WriteFailed(m_Name);
  }
}
} // namespace sic
