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
#ifndef sicStreamedImageFiles_h
#define sicStreamedImageFiles_h

#include "itkImageIOBase.h"

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace sic
{
/** The geometry and pixel type of an image read or written plane by plane (planes along the last
 * axis). Direction is row-major, Dimension × Dimension. */
struct VolumeGeometry
{
  unsigned int          Dimension{ 3 };
  std::vector<uint64_t> Size;
  std::vector<double>   Spacing;
  std::vector<double>   Origin;
  std::vector<double>   Direction;
  itk::IOComponentEnum  ComponentType{ itk::IOComponentEnum::UNKNOWNCOMPONENTTYPE };

  uint64_t
  PlaneVoxels() const;
  uint64_t
  Planes() const
  {
    return Size.back();
  }
  unsigned int
  PixelBytes() const;
};

/** The formats the tools read and write plane by plane: MetaImage (.mha, .mhd with its data
 * file) and NRRD (.nrrd, .nhdr with its data file), with raw, zlib or gzip data. */
bool
IsStreamableImageFile(const std::string & path);

/** The sentence saying which formats stream, for error messages. */
std::string
StreamableFormats();

/** Reads an image's voxels plane by plane, without holding more than the planes asked for: MetaImage and NRRD files
 * whose data are raw (either byte order), zlib-compressed (MetaImage) or gzip-compressed (NRRD). The geometry comes
 * from ITK's reader; where the voxels are and how they are stored from FindImageFileParts(), the header reader of the
 * tools' data checks. Every problem (another format, a data file that is too short, corrupt compressed data or a failed
 * checksum, data left over) is a ToolError with one line. */
class PlaneReader
{
public:
  /** Opens \a path (described to the user as \a what) and checks, before any voxel is read, that
   * its data file holds the voxels the header promises (for raw data). */
  PlaneReader(const std::string & path, const std::string & what);
  ~PlaneReader();
  PlaneReader(const PlaneReader &) = delete;
  PlaneReader &
  operator=(const PlaneReader &) = delete;

  const VolumeGeometry &
  GetGeometry() const
  {
    return m_Geometry;
  }

  /** Reads the next \a planes planes into \a buffer (native byte order). */
  void
  Read(void * buffer, uint64_t planes);
  /** After the last plane: checks that the data ended where the header said (compressed data:
   * the stream's end and checksum). */
  void
  Finish();

private:
  struct Data;
  std::string           m_Name;
  VolumeGeometry        m_Geometry;
  std::unique_ptr<Data> m_Data;
};

/** Writes an image plane by plane in the format its extension names (see StreamableFormats()), compressed unless asked
 * not to, checking every write: a full disk or any other failure is a ToolError, never a short file. The files are
 * written at \a path (a staged path) and name their data file relative to it. */
class PlaneWriter
{
public:
  PlaneWriter(const std::string &    path,
              const std::string &    finalPath,
              const std::string &    what,
              const VolumeGeometry & geometry,
              bool                   compress);
  ~PlaneWriter();
  PlaneWriter(const PlaneWriter &) = delete;
  PlaneWriter &
  operator=(const PlaneWriter &) = delete;

  /** Writes the next \a planes planes from \a buffer (native byte order). */
  void
  Write(const void * buffer, uint64_t planes);
  /** After the last plane: completes the header and closes the files. */
  void
  Finish();

private:
  struct Output;
  std::string             m_Path;
  std::string             m_Name;
  VolumeGeometry          m_Geometry;
  bool                    m_Compress;
  uint64_t                m_PlanesWritten{ 0 };
  std::unique_ptr<Output> m_Output;
};
} // namespace sic

#endif
