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
#include "sicImageFileParts.h"
#include "sicStrings.h"

#include "NrrdIO.h"
#include "itk_zlib.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <utility>

namespace sic
{
namespace fs = std::filesystem;

namespace
{
constexpr std::uint64_t Saturated = std::numeric_limits<std::uint64_t>::max();
/** No header names more data files than this (a file per slice of a very large volume). */
constexpr std::uint64_t MaximumDataFiles = 1000000;

std::vector<std::string>
Words(const std::string & text)
{
  std::istringstream       stream(text);
  std::vector<std::string> words;
  for (std::string word; stream >> word;)
  {
    words.push_back(word);
  }
  return words;
}

std::optional<std::int64_t>
ParseInteger(const std::string & text)
{
  std::istringstream stream(text);
  std::int64_t       value = 0;
  if (!(stream >> value) || !(stream >> std::ws).eof())
  {
    return std::nullopt;
  }
  return value;
}

/** The whole number \a text starts with, as ITK's readers take the numbers that place the data (C's strtoll:
 * "7abc" and "7.9" are 7), or nothing when it starts with none or the number overflows. */
std::optional<std::int64_t>
ParseLeadingInteger(const std::string & text)
{
  // errno is kept as it was: ITK's messages name it.
  const int saved = errno;
  errno = 0;
  char *          end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  const bool      overflow = errno == ERANGE;
  errno = saved;
  if (end == text.c_str() || overflow)
  {
    return std::nullopt;
  }
  return static_cast<std::int64_t>(value);
}

std::uint64_t
SaturatingProduct(std::uint64_t a, std::uint64_t b)
{
  return a != 0 && b > Saturated / a ? Saturated : a * b;
}

/** \a factor times the sizes from \a first on. */
std::uint64_t
Product(const std::vector<std::uint64_t> & sizes, std::uint64_t factor, std::size_t first = 0)
{
  return std::accumulate(sizes.begin() + first, sizes.end(), factor, SaturatingProduct);
}

/** The sizes the header field \a field gives with \a words; when they are not whole numbers of voxels of at least 1
 * along each axis, sets \a problem saying why. ITK's NRRD reader refuses such sizes with a trace that does not say
 * which field is wrong, and its MetaImage reader takes a negative size as a huge one. */
std::vector<std::uint64_t>
WholeSizes(const std::string & field, const std::vector<std::string> & words, std::string & problem)
{
  std::vector<std::uint64_t> sizes;
  std::string                shown;
  std::string                value;
  for (const std::string & text : words)
  {
    const std::optional<std::int64_t> size = ParseInteger(text);
    if (size && *size >= 0)
    {
      sizes.push_back(static_cast<std::uint64_t>(*size));
    }
    shown += (shown.empty() ? "" : " x ") + text;
    value += " " + text;
  }
  if (sizes.empty() || sizes.size() != words.size())
  {
    problem =
      "its header gives '" + field + value + "'; expected a whole number of voxels, at least 1, along each axis";
  }
  else if (std::find(sizes.begin(), sizes.end(), 0) != sizes.end())
  {
    problem = "is empty: its size is " + shown + " voxels; expected at least one voxel along every axis";
  }
  return sizes;
}

/** The next line of \a stream without its line end ('\n' or "\r\n"); false at the end of the stream. */
bool
NextLine(std::istream & stream, std::string & line)
{
  if (!std::getline(stream, line))
  {
    return false;
  }
  if (!line.empty() && line.back() == '\r')
  {
    line.pop_back();
  }
  return true;
}

/** The offset after \a count lines of \a path from \a offset on (the file's size if it has fewer). */
std::uint64_t
SkipLines(const fs::path & path, std::uint64_t offset, std::uint64_t count)
{
  std::error_code error;
  if (count == 0 || !fs::is_regular_file(path, error))
  {
    return offset;
  }
  std::ifstream stream(path, std::ios::binary);
  stream.seekg(static_cast<std::streamoff>(offset));
  for (; count > 0 && stream.good(); --count)
  {
    stream.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    offset += static_cast<std::uint64_t>(stream.gcount());
  }
  return offset;
}

/** The names of a numbered series, "slice%03d.raw 1 10 1": a printf pattern with one integer conversion, then
 * the first and last numbers and the step. Nothing when \a words are not such a series. */
std::optional<std::vector<std::string>>
NumberedFiles(const std::vector<std::string> & words)
{
  if (words.size() < 4 || words[0].find('%') == std::string::npos)
  {
    return std::nullopt;
  }
  const std::string & pattern = words[0];
  const size_t        percent = pattern.find('%');
  size_t              end = percent + 1;
  while (end < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[end])))
  {
    ++end;
  }
  // A zero flag and a width of at most two digits, then d, i or u.
  if (end >= pattern.size() || end - percent - 1 > 2 ||
      (pattern[end] != 'd' && pattern[end] != 'i' && pattern[end] != 'u') ||
      pattern.find('%', end) != std::string::npos)
  {
    return std::nullopt;
  }
  const std::optional<std::int64_t> first = ParseInteger(words[1]);
  const std::optional<std::int64_t> last = ParseInteger(words[2]);
  const std::optional<std::int64_t> step = ParseInteger(words[3]);
  // Bounds that keep the arithmetic below far from overflowing.
  constexpr std::int64_t Bound = 1000000000000;
  const auto             bounded = [](std::optional<std::int64_t> v) { return v && *v >= -Bound && *v <= Bound; };
  if (!bounded(first) || !bounded(last) || !bounded(step) || *step == 0 || (*last - *first) / *step < 0 ||
      static_cast<std::uint64_t>((*last - *first) / *step) >= MaximumDataFiles)
  {
    return std::nullopt;
  }
  // The numbers are signed whatever the conversion, and may need 64 bits.
  const std::string        format = pattern.substr(0, end) + "lld" + pattern.substr(end + 1);
  std::vector<std::string> names;
  const std::int64_t       count = (*last - *first) / *step + 1;
  for (std::int64_t i = 0; i < count; ++i)
  {
    const long long number = *first + i * *step;
    std::string     name(static_cast<size_t>(std::snprintf(nullptr, 0, format.c_str(), number)), '\0');
    std::snprintf(name.data(), name.size() + 1, format.c_str(), number);
    names.push_back(name);
  }
  return names;
}

void
AddFile(ImageFileParts & parts, const fs::path & file)
{
  if (std::find(parts.Files.begin(), parts.Files.end(), file) == parts.Files.end())
  {
    parts.Files.push_back(file);
  }
}

/** The data files that a header's \a value names, relative to \a header, added to \a parts: LIST (the names on the
 * lines left in \a stream), a numbered series or one file. */
std::vector<fs::path>
DataFiles(const fs::path & header, const std::string & value, std::istream & stream, ImageFileParts & parts)
{
  const bool               listed = value.compare(0, 4, "LIST") == 0;
  const auto               numbered = NumberedFiles(Words(value));
  std::vector<std::string> names = numbered ? *numbered : std::vector<std::string>{ value };
  parts.DataFileSeries = listed || numbered;
  if (listed)
  {
    names.clear();
    for (std::string line; NextLine(stream, line);)
    {
      if (!Trim(line).empty())
      {
        names.push_back(Trim(line));
      }
    }
  }
  std::vector<fs::path> files;
  for (const std::string & name : names)
  {
    const fs::path file(name);
    files.push_back(file.is_absolute() ? file : header.parent_path() / file);
    AddFile(parts, files.back());
  }
  return files;
}

/** Bytes per value of a NRRD type name as NrrdIO knows it, 0 for an unknown one or "block"; a name not in lower
 * case is left to ITK's reader alone. */
std::uint64_t
NrrdTypeBytes(const std::string & type)
{
  return type == Lowercase(type) ? nrrdTypeSize[airEnumVal(nrrdType, type.c_str())] : 0;
}

/** A NRRD header: fields "name: value" up to the first empty line (after which attached data starts), key/value
 * pairs "key:=value" and comments skipped; a detached header's "data file" names one file, a numbered series or
 * LIST, whose names follow to the end of the header. */
void
ReadNrrd(const fs::path & path, ImageFileParts & parts, std::string & problem)
{
  std::ifstream stream(path, std::ios::binary);
  std::string   line;
  if (!NextLine(stream, line) || line.compare(0, 4, "NRRD") != 0)
  {
    problem = "it does not start with a NRRD header (NRRD000N)";
    return;
  }
  std::map<std::string, std::string> fields;
  bool                               ended = false;
  while (!ended && NextLine(stream, line))
  {
    ended = line.empty();
    const size_t colon = line.find(':');
    if (ended || line[0] == '#' || colon == std::string::npos || (colon + 1 < line.size() && line[colon + 1] == '='))
    {
      continue;
    }
    std::string name = line.substr(0, colon);
    name.erase(std::remove(name.begin(), name.end(), ' '), name.end());
    const std::string value = Trim(line.substr(colon + 1));
    fields[name] = value;
    if (name == "datafile" && value.compare(0, 4, "LIST") == 0)
    {
      break; // the data files' names follow to the end of the header
    }
  }
  const std::vector<std::uint64_t> sizes = WholeSizes("sizes:", Words(fields["sizes"]), problem);
  if (!problem.empty())
  {
    parts.UnsafeForItk = true;
    return;
  }

  const std::string encoding = Lowercase(fields["encoding"]);
  parts.EncodingName = encoding;
  parts.BigEndian = Lowercase(fields["endian"]) == "big";
  const bool raw = encoding == "raw";
  const bool deflate = encoding == "gzip" || encoding == "gz";
  // ITK's NRRD reader refuses any other encoding (bzip2 among them) with a chain of its library's messages.
  const bool readable = raw || deflate || encoding == "ascii" || encoding == "text" || encoding == "txt" ||
                        encoding == "hex" || fields.count("encoding") == 0;
  if (!readable)
  {
    problem = "its header gives 'encoding: " + fields["encoding"] +
              "', which ITK's NRRD reader cannot read; expected raw, gzip, ascii or hex";
    parts.UnsafeForItk = true;
    return;
  }
  const std::uint64_t typeBytes =
    fields["type"] == "block"
      ? static_cast<std::uint64_t>(std::max<std::int64_t>(ParseInteger(fields["blocksize"]).value_or(0), 0))
      : NrrdTypeBytes(fields["type"]);
  if (typeBytes > 0)
  {
    parts.DataBytes = Product(sizes, typeBytes);
  }
  const std::int64_t lineSkip = std::max<std::int64_t>(ParseLeadingInteger(fields["lineskip"]).value_or(0), 0);
  // A negative byte skip other than -1 is taken as -1.
  const std::int64_t      byteSkip = ParseLeadingInteger(fields["byteskip"]).value_or(0);
  const std::uint64_t     skip = static_cast<std::uint64_t>(std::max<std::int64_t>(byteSkip, 0));
  const ImageDataEncoding stored = raw       ? ImageDataEncoding::Raw
                                   : deflate ? ImageDataEncoding::Deflate
                                             : ImageDataEncoding::Unchecked;
  const auto              addSegment = [&](const fs::path & file, std::uint64_t offset) {
    offset = SkipLines(file, offset, static_cast<std::uint64_t>(lineSkip)) + (raw ? skip : 0);
    parts.Data.push_back({ file, stored, offset, (raw || deflate) && byteSkip < 0, deflate ? skip : 0, {} });
  };
  const auto dataFile = fields.find("datafile");
  if (dataFile != fields.end())
  {
    for (const fs::path & file : DataFiles(path, dataFile->second, stream, parts))
    {
      addSegment(file, 0);
    }
  }
  else if (!ended)
  {
    problem = "its header ends without the empty line after which the data starts";
  }
  else
  {
    stream.clear(); // a last line of "\r" alone leaves the stream at its end
    addSegment(path, static_cast<std::uint64_t>(stream.tellg()));
  }
}

/** Bytes per value of a MetaImage element type, 0 for one the tools do not know. */
std::uint64_t
MetaTypeBytes(const std::string & type)
{
  static const std::map<std::string, std::uint64_t> Sizes = {
    { "MET_CHAR", 1 }, { "MET_UCHAR", 1 }, { "MET_SHORT", 2 },  { "MET_USHORT", 2 },    { "MET_INT", 4 },
    { "MET_UINT", 4 }, { "MET_FLOAT", 4 }, { "MET_DOUBLE", 8 }, { "MET_LONG_LONG", 8 }, { "MET_ULONG_LONG", 8 },
  };
  const auto found = Sizes.find(type);
  return found == Sizes.end() ? 0 : found->second;
}

/** The size of MetaIO's buffer for a field name: ITK's MetaImage reader aborts on longer names. */
constexpr std::size_t MetaIOFieldNameLength = 255;

/** A MetaImage header: "Key = Value" lines up to ElementDataFile, the last field; LOCAL data follows it in the
 * same file, otherwise it names one file, a numbered series or LIST, whose names follow. HeaderSize, when given,
 * is where the data start in their file (-1: at its end). */
void
ReadMetaImage(const fs::path & path, ImageFileParts & parts, std::string & problem)
{
  std::ifstream                      stream(path, std::ios::binary);
  std::map<std::string, std::string> fields;
  std::string                        line;
  bool                               found = false;
  while (!found && NextLine(stream, line))
  {
    const size_t equals = line.find('=');
    if (equals == std::string::npos)
    {
      continue;
    }
    const std::string key = Trim(line.substr(0, equals));
    if (key.size() >= MetaIOFieldNameLength)
    {
      problem = "its header has a field name of " + std::to_string(key.size()) + " characters; MetaImage field names " +
                "have fewer than " + std::to_string(MetaIOFieldNameLength);
      parts.UnsafeForItk = true;
      return;
    }
    const std::string value = Trim(line.substr(equals + 1));
    fields[key] = value;
    found = key == "ElementDataFile";
    if (key == "BinaryDataByteOrderMSB" || key == "ElementByteOrderMSB")
    {
      parts.BigEndian = Lowercase(value) == "true";
    }
    parts.TextData = parts.TextData || (key == "BinaryData" && Lowercase(value) != "true");
  }
  if (!found)
  {
    problem = "its header ends before ElementDataFile, its last field";
    parts.UnsafeForItk = true;
    return;
  }
  // MetaIO refuses a header without these with a message that does not say why, and leaks on the way.
  for (const char * required : { "NDims", "DimSize", "ElementType" })
  {
    if (fields.count(required) == 0)
    {
      problem = std::string("its header has no ") + required +
                " field before ElementDataFile; MetaImage headers need NDims, DimSize and ElementType there";
      parts.UnsafeForItk = true;
      return;
    }
  }
  // MetaIO fails on these with lines that name another field, and ITK with "Reason: Success".
  for (const char * numeric : { "ElementSpacing",
                                "ElementSize",
                                "Offset",
                                "Position",
                                "Origin",
                                "TransformMatrix",
                                "Rotation",
                                "Orientation",
                                "CenterOfRotation" })
  {
    for (const std::string & word : fields.count(numeric) ? Words(fields[numeric]) : std::vector<std::string>{})
    {
      char *       end = nullptr;
      const double number = std::strtod(word.c_str(), &end);
      if (*end != '\0' || !std::isfinite(number))
      {
        problem = std::string("its header's '") + numeric + " = " + fields[numeric] +
                  "' holds a word that is not a finite number; expected finite numbers";
        parts.UnsafeForItk = true;
        return;
      }
    }
  }
  const bool ended = !stream.eof();

  const std::vector<std::string>    sizes = Words(fields["DimSize"]);
  const std::optional<std::int64_t> dimensions = ParseInteger(fields["NDims"]);
  const std::optional<std::int64_t> channels = fields.count("ElementNumberOfChannels")
                                                 ? ParseInteger(fields["ElementNumberOfChannels"])
                                                 : std::optional<std::int64_t>(1);
  const std::uint64_t               typeBytes = MetaTypeBytes(fields["ElementType"]);
  // MetaIO reads the first NDims sizes.
  const bool counted = dimensions && *dimensions >= 1 && static_cast<size_t>(*dimensions) <= sizes.size();
  if (dimensions && *dimensions >= 1 && !counted)
  {
    problem = "its header's 'DimSize = " + fields["DimSize"] + "' has " + std::to_string(sizes.size()) +
              " sizes for NDims = " + std::to_string(*dimensions) + "; expected one size per axis";
    parts.UnsafeForItk = true;
    return;
  }
  const std::vector<std::uint64_t> axes = WholeSizes(
    "DimSize =", std::vector<std::string>(sizes.begin(), counted ? sizes.begin() + *dimensions : sizes.end()), problem);
  if (!problem.empty())
  {
    parts.UnsafeForItk = true;
    return;
  }
  if (typeBytes > 0 && counted && channels && *channels >= 1)
  {
    parts.DataBytes = Product(axes, SaturatingProduct(typeBytes, static_cast<std::uint64_t>(*channels)));
  }
  if (parts.TextData && counted && channels && *channels >= 1)
  {
    parts.TextValues = Product(axes, static_cast<std::uint64_t>(*channels));
  }
  const bool         compressed = Lowercase(fields["CompressedData"]) == "true";
  const std::int64_t headerSize = ParseLeadingInteger(fields["HeaderSize"]).value_or(0);
  // MetaIO takes a CompressedDataSize of 0, or none, as the whole data file.
  const std::optional<std::int64_t>  compressedSize = ParseInteger(fields["CompressedDataSize"]);
  const std::optional<std::uint64_t> compressedBytes =
    compressed && compressedSize && *compressedSize > 0 ? std::optional<std::uint64_t>(*compressedSize) : std::nullopt;

  const auto addSegment = [&](const fs::path & file, std::uint64_t start) {
    const ImageDataEncoding encoding = compressed ? ImageDataEncoding::Deflate : ImageDataEncoding::Raw;
    const std::uint64_t     offset = headerSize > 0 ? static_cast<std::uint64_t>(headerSize) : start;
    parts.Data.push_back({ file, encoding, offset, !compressed && headerSize == -1, 0, compressedBytes });
  };
  const std::string value = fields["ElementDataFile"];
  // MetaIO takes these three spellings of LOCAL alone (any other is a data file's name) and any value that
  // starts with LIST as a list of files.
  if (value == "LOCAL" || value == "Local" || value == "local")
  {
    if (!ended)
    {
      problem = "its header ends without a line end after ElementDataFile = LOCAL";
      return;
    }
    // MetaIO honours HeaderSize here too: the voxels start there, or are the file's last bytes.
    addSegment(path, static_cast<std::uint64_t>(stream.tellg()));
    return;
  }
  for (const fs::path & file : DataFiles(path, value, stream, parts))
  {
    addSegment(file, 0);
  }
  // MetaIO reads any name with a % as a numbered series, whose first and last numbers and step may be left out.
  parts.DataFileSeries = parts.DataFileSeries || value.find('%') != std::string::npos;
  // Each file of a series holds the next slice of the last NDims - 1 axes, or of "LIST ND"'s N; MetaIO reads no
  // more from it, and leaves the voxels of a file it cannot read as they were.
  const bool    listed = value.compare(0, 4, "LIST") == 0;
  std::uint64_t fileAxes = axes.size() - 1;
  if (listed)
  {
    const std::optional<std::int64_t> given = ParseLeadingInteger(Trim(value.substr(4)));
    fileAxes = given && *given >= 1 && static_cast<std::uint64_t>(*given) <= axes.size() ? *given : fileAxes;
  }
  if (parts.DataFileSeries && !parts.TextData && (listed || Words(value).size() <= 4) && parts.DataBytes &&
      axes.size() >= 2)
  {
    parts.SeriesFiles = Product(axes, 1, fileAxes);
    parts.SeriesFileBytes = parts.SeriesFiles > 0 ? *parts.DataBytes / parts.SeriesFiles : 0;
  }
}

/** Reads the first \a count bytes of \a path, through gzip when it is compressed. */
std::vector<unsigned char>
ReadStart(const fs::path & path, size_t count)
{
  std::vector<unsigned char> bytes(count);
  gzFile                     file = gzopen(path.string().c_str(), "rb");
  if (file == nullptr)
  {
    return {};
  }
  const int got = gzread(file, bytes.data(), static_cast<unsigned int>(count));
  gzclose(file);
  bytes.resize(got > 0 ? static_cast<size_t>(got) : 0);
  return bytes;
}

/** A field of a NIfTI header, byte-swapped when the file's byte order is not the machine's. */
template <typename T>
T
FieldAt(const std::vector<unsigned char> & header, size_t offset, bool swapped)
{
  T value;
  std::memcpy(&value, header.data() + offset, sizeof(T));
  if (swapped)
  {
    std::reverse(reinterpret_cast<unsigned char *>(&value), reinterpret_cast<unsigned char *>(&value) + sizeof(T));
  }
  return value;
}

/** The largest magnitude a NIfTI sform number may have: ITK's NIfTI reader decomposes the sform in single
 * precision, and aborts on a number that is not finite or hangs when the matrix's norm overflows. Squares of
 * numbers this size, summed over the matrix, stay far below the largest float. */
constexpr double NiftiSformLimit = 1e18;

/** Why the sform of a NIfTI header at \a bytes cannot be handed to ITK, or "" when it can: ITK uses it only when
 * the magic says NIfTI and sform_code is positive, and then its 12 numbers must be finite and at most
 * NiftiSformLimit in magnitude. */
std::string
NiftiSformProblem(const std::vector<unsigned char> & bytes, bool nifti2, bool swapped)
{
  const size_t magicAt = nifti2 ? 4 : 344;
  const bool   isNifti = bytes[magicAt] == 'n' && (bytes[magicAt + 1] == 'i' || bytes[magicAt + 1] == '+') &&
                       bytes[magicAt + 2] >= '1' && bytes[magicAt + 2] <= '9' && bytes[magicAt + 3] == '\0';
  const std::int64_t sformCode =
    nifti2 ? FieldAt<std::int32_t>(bytes, 348, swapped) : FieldAt<std::int16_t>(bytes, 254, swapped);
  if (!isNifti || sformCode <= 0)
  {
    return {};
  }
  for (size_t i = 0; i < 12; ++i)
  {
    const double value =
      nifti2 ? FieldAt<double>(bytes, 400 + 8 * i, swapped) : FieldAt<float>(bytes, 280 + 4 * i, swapped);
    if (!(std::abs(value) <= NiftiSformLimit))
    {
      std::ostringstream text;
      text << "its sform (srow_"
           << "xyz"[i / 4] << "[" << i % 4 << "]) is " << value
           << ", and ITK's NIfTI reader takes only finite sform numbers of magnitude at most " << NiftiSformLimit;
      return text.str();
    }
  }
  return {};
}

/** A NIfTI-1 (or Analyze) or NIfTI-2 header, read through gzip for .nii.gz: the dimensions, the bits per voxel
 * and where the voxels start; .nii files hold their voxels, .hdr files name .img files that do. */
void
ReadNifti(const fs::path & path, ImageFileParts & parts, std::string & problem)
{
  const std::string name = Lowercase(path.filename().string());
  const bool        pair = EndsWith(name, ".hdr") || EndsWith(name, ".hdr.gz");
  // The other file of a .hdr/.img pair: the path with its extension (\a from, perhaps with .gz) replaced by \a to,
  // or by \a to and .gz when only that exists.
  const auto partner = [&](const std::string & from, const std::string & to) {
    std::string     other = path.string();
    std::error_code error;
    other.replace(other.size() - from.size() - (EndsWith(name, ".gz") ? 3 : 0), std::string::npos, to);
    return !fs::exists(other, error) && fs::exists(other + ".gz", error) ? fs::path(other + ".gz") : fs::path(other);
  };
  const fs::path data = pair ? partner(".hdr", ".img") : path;
  const fs::path header = EndsWith(name, ".img") || EndsWith(name, ".img.gz") ? partner(".img", ".hdr") : path;
  parts.Files = { header };
  AddFile(parts, data);

  const std::vector<unsigned char> bytes = ReadStart(header, 540);
  if (bytes.size() < 348)
  {
    problem = "its header is cut short (" + std::to_string(bytes.size()) + " of at least 348 bytes)";
    return;
  }
  const std::int32_t size = FieldAt<std::int32_t>(bytes, 0, false);
  const bool         swapped = size != 348 && size != 540;
  const std::int32_t headerBytes = FieldAt<std::int32_t>(bytes, 0, swapped);
  if (headerBytes != 348 && headerBytes != 540)
  {
    problem = "its header does not start with the size of a NIfTI header (348 or 540)";
    return;
  }
  if (headerBytes == 540 && bytes.size() < 540)
  {
    problem = "its NIfTI-2 header is cut short (" + std::to_string(bytes.size()) + " of 540 bytes)";
    return;
  }
  const bool nifti2 = headerBytes == 540;
  problem = NiftiSformProblem(bytes, nifti2, swapped);
  if (!problem.empty())
  {
    parts.UnsafeForItk = true;
    return;
  }
  const auto dimension = [&](int i) {
    return nifti2 ? FieldAt<std::int64_t>(bytes, 16 + 8 * i, swapped)
                  : FieldAt<std::int16_t>(bytes, 40 + 2 * i, swapped);
  };
  const std::int64_t bitsPerVoxel = FieldAt<std::int16_t>(bytes, nifti2 ? 14 : 72, swapped);
  const std::int64_t dimensions = dimension(0);
  if (dimensions >= 1 && dimensions <= 7)
  {
    std::vector<std::string> sizes;
    for (int i = 1; i <= dimensions; ++i)
    {
      sizes.push_back(std::to_string(dimension(i)));
    }
    // ITK's NIfTI reader takes a size below 1 as 1, and reads a part of the voxels as the whole image.
    const std::vector<std::uint64_t> whole = WholeSizes("dim[1..dim[0]] =", sizes, problem);
    if (!problem.empty())
    {
      parts.UnsafeForItk = true;
      return;
    }
    if (bitsPerVoxel > 0 && bitsPerVoxel % 8 == 0)
    {
      parts.DataBytes = Product(whole, static_cast<std::uint64_t>(bitsPerVoxel / 8));
    }
  }
  std::uint64_t voxelOffset = 0;
  if (nifti2)
  {
    voxelOffset = static_cast<std::uint64_t>(std::max<std::int64_t>(FieldAt<std::int64_t>(bytes, 168, swapped), 0));
  }
  else
  {
    const float offset = FieldAt<float>(bytes, 108, swapped);
    voxelOffset = std::isfinite(offset) && offset > 0.0f && offset < 1e15f ? static_cast<std::uint64_t>(offset) : 0;
  }
  // A single file's voxels start after its header and the 4 bytes that say whether extensions follow; ITK's
  // reader takes a smaller vox_offset as the header's size, and reads those 4 bytes as voxels.
  const std::uint64_t firstVoxel = static_cast<std::uint64_t>(headerBytes) + 4;
  if (!pair && header == data && voxelOffset < firstVoxel)
  {
    problem = "its vox_offset is " + std::to_string(voxelOffset) + "; expected " + std::to_string(firstVoxel) +
              " or more, where a single NIfTI file's voxels can start";
    parts.UnsafeForItk = true;
    return;
  }
  // The voxels of a .gz file start at that offset of its inflated data.
  const bool gzip = EndsWith(Lowercase(data.filename().string()), ".gz");
  const auto encoding = gzip ? ImageDataEncoding::Deflate : ImageDataEncoding::Raw;
  parts.Data.push_back({ data, encoding, gzip ? 0 : voxelOffset, false, gzip ? voxelOffset : 0, {} });
}
} // namespace

ImageFileFormat
ImageFileFormatOf(const fs::path & path)
{
  using F = ImageFileFormat;
  static const std::pair<const char *, F> extensions[] = {
    { ".nrrd", F::Nrrd }, { ".nhdr", F::Nrrd },    { ".mha", F::MetaImage }, { ".mhd", F::MetaImage },
    { ".nii", F::Nifti }, { ".nii.gz", F::Nifti }, { ".hdr", F::Nifti },     { ".hdr.gz", F::Nifti },
    { ".img", F::Nifti }, { ".img.gz", F::Nifti }, { ".png", F::Png },
  };
  const std::string name = Lowercase(path.filename().string());
  for (const auto & [extension, format] : extensions)
  {
    if (EndsWith(name, extension))
    {
      return format;
    }
  }
  return F::Other;
}

bool
StartsWithPngSignature(const fs::path & path)
{
  static constexpr char signature[] = { '\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n' };
  char                  start[sizeof(signature)] = {};
  std::ifstream         file(path, std::ios::binary);
  return file.read(start, sizeof(start)) && std::equal(start, start + sizeof(start), signature);
}

ImageFileParts
FindImageFileParts(const fs::path & path, std::string & problem)
{
  problem.clear();
  ImageFileParts parts;
  parts.Format = StartsWithPngSignature(path) ? ImageFileFormat::Png : ImageFileFormatOf(path);
  parts.Files = { path };
  switch (parts.Format)
  {
    case ImageFileFormat::Nrrd:
      ReadNrrd(path, parts, problem);
      break;
    case ImageFileFormat::MetaImage:
      ReadMetaImage(path, parts, problem);
      break;
    case ImageFileFormat::Nifti:
      ReadNifti(path, parts, problem);
      break;
    case ImageFileFormat::Png:
    case ImageFileFormat::Other:
      break;
  }
  return parts;
}
} // namespace sic
