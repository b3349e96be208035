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
// Plane-by-plane reading and writing against ITK's own readers and writers: every format and
// encoding both ways, geometry included, and the damaged files that must be refused.

#include "sicStreamedImageFiles.h"
#include "sicToolError.h"

#include "itkImage.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageRegionIterator.h"

#include "gtest/gtest.h"

#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <random>

namespace
{
using ImageType = itk::Image<int16_t, 3>;

/** A file of this test's own (ctest runs the tests of this file at the same time). */
std::filesystem::path
Scratch(const std::string & name)
{
  const auto directory = std::filesystem::temp_directory_path() / "sicStreamedImageFilesTest" /
                         ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::filesystem::create_directories(directory);
  return directory / name;
}

ImageType::Pointer
MakeImage()
{
  auto                image = ImageType::New();
  ImageType::SizeType size = { { 13, 7, 11 } };
  image->SetRegions(size);
  image->Allocate();
  const double spacing[3] = { 0.5, 0.75, 2.0 };
  const double origin[3] = { -10.25, 3.5, 100.0 };
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  ImageType::DirectionType direction;
  direction.Fill(0.0);
  direction[0][1] = 1.0; // axis 1 points along x
  direction[1][0] = -1.0;
  direction[2][2] = 1.0;
  image->SetDirection(direction);
  std::mt19937 random(7);
  for (itk::ImageRegionIterator<ImageType> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    it.Set(static_cast<int16_t>(static_cast<int>(random() % 4000) - 2000));
  }
  return image;
}

sic::VolumeGeometry
GeometryOf(const ImageType * image)
{
  sic::VolumeGeometry geometry;
  geometry.Dimension = 3;
  geometry.ComponentType = itk::IOComponentEnum::SHORT;
  for (unsigned int a = 0; a < 3; ++a)
  {
    geometry.Size.push_back(image->GetLargestPossibleRegion().GetSize()[a]);
    geometry.Spacing.push_back(image->GetSpacing()[a]);
    geometry.Origin.push_back(image->GetOrigin()[a]);
  }
  for (unsigned int row = 0; row < 3; ++row)
  {
    for (unsigned int column = 0; column < 3; ++column)
    {
      geometry.Direction.push_back(image->GetDirection()[row][column]);
    }
  }
  return geometry;
}

void
ExpectSameImage(const ImageType * a, const ImageType * b)
{
  ASSERT_EQ(a->GetLargestPossibleRegion(), b->GetLargestPossibleRegion());
  EXPECT_EQ(a->GetSpacing(), b->GetSpacing());
  EXPECT_EQ(a->GetOrigin(), b->GetOrigin());
  EXPECT_EQ(a->GetDirection(), b->GetDirection());
  const auto voxels = a->GetLargestPossibleRegion().GetNumberOfPixels();
  EXPECT_TRUE(std::equal(a->GetBufferPointer(), a->GetBufferPointer() + voxels, b->GetBufferPointer()));
}

ImageType::Pointer
ReadWithPlaneReader(const std::string & path)
{
  sic::PlaneReader    reader(path, "input");
  const auto &        geometry = reader.GetGeometry();
  auto                image = ImageType::New();
  ImageType::SizeType size = { { geometry.Size[0], geometry.Size[1], geometry.Size[2] } };
  image->SetRegions(size);
  image->Allocate();
  ImageType::SpacingType   spacing;
  ImageType::PointType     origin;
  ImageType::DirectionType direction;
  for (unsigned int a = 0; a < 3; ++a)
  {
    spacing[a] = geometry.Spacing[a];
    origin[a] = geometry.Origin[a];
    for (unsigned int b = 0; b < 3; ++b)
    {
      direction[a][b] = geometry.Direction[a * 3 + b];
    }
  }
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(direction);
  // Planes in uneven pieces.
  for (uint64_t z = 0; z < geometry.Size[2];)
  {
    const uint64_t planes = std::min<uint64_t>(geometry.Size[2] - z, 1 + z % 3);
    reader.Read(image->GetBufferPointer() + z * geometry.PlaneVoxels(), planes);
    z += planes;
  }
  reader.Finish();
  return image;
}

const char * const Names[] = { "a.mha", "a.mhd", "a.nrrd", "a.nhdr" };
} // namespace

TEST(StreamedImageFiles, PlaneWriterFilesReadBackWithITK)
{
  const auto image = MakeImage();
  for (const bool compress : { false, true })
  {
    for (const char * name : Names)
    {
      const std::string path = Scratch(std::string(compress ? "c-" : "r-") + name).string();
      sic::PlaneWriter  writer(path, path, "output", GeometryOf(image), compress);
      const uint64_t    planeVoxels = 13 * 7;
      for (uint64_t z = 0; z < 11; z += 2)
      {
        writer.Write(image->GetBufferPointer() + z * planeVoxels, std::min<uint64_t>(2, 11 - z));
      }
      writer.Finish();
      auto reader = itk::ImageFileReader<ImageType>::New();
      reader->SetFileName(path);
      reader->Update();
      SCOPED_TRACE(path);
      ExpectSameImage(image, reader->GetOutput());
      ExpectSameImage(image, ReadWithPlaneReader(path));
    }
  }
}

TEST(StreamedImageFiles, PlaneReaderReadsWhatITKWrites)
{
  const auto image = MakeImage();
  for (const bool compress : { false, true })
  {
    for (const char * name : Names)
    {
      const std::string path = Scratch(std::string(compress ? "itk-c-" : "itk-r-") + name).string();
      auto              writer = itk::ImageFileWriter<ImageType>::New();
      writer->SetInput(image);
      writer->SetFileName(path);
      writer->SetUseCompression(compress);
      writer->Update();
      SCOPED_TRACE(path);
      ExpectSameImage(image, ReadWithPlaneReader(path));
    }
  }
}

TEST(StreamedImageFiles, PlaneReaderReadsGzipDataInSeveralMembers)
{
  // What pigz, bgzip (its last member empty) and concatenated gzip files hold.
  const auto        image = MakeImage();
  const std::string path = Scratch("members.nrrd").string();
  {
    std::ofstream header(path, std::ios::binary);
    header << "NRRD0004\ntype: short\ndimension: 3\nsizes: 13 7 11\nendian: little\nencoding: gzip\n\n";
  }
  const auto * const voxels = reinterpret_cast<const char *>(image->GetBufferPointer());
  const unsigned int bytes = 13 * 7 * 11 * sizeof(int16_t);
  for (const auto & [start, count] :
       { std::pair<unsigned int, unsigned int>{ 0, 501 }, { 501, bytes - 501 }, { 0, 0 } })
  {
    // Each gzopen in append mode writes a member of its own.
    gzFile member = gzopen(path.c_str(), "ab");
    ASSERT_NE(member, nullptr);
    EXPECT_EQ(gzwrite(member, voxels + start, count), static_cast<int>(count));
    EXPECT_EQ(gzclose(member), Z_OK);
  }
  const auto read = ReadWithPlaneReader(path);
  EXPECT_TRUE(std::equal(voxels, voxels + bytes, reinterpret_cast<const char *>(read->GetBufferPointer())));
}

TEST(StreamedImageFiles, DamagedFilesAreRefused)
{
  const auto image = MakeImage();
  const auto write = [&](const std::string & name, bool compress) {
    const std::string path = Scratch(name).string();
    auto              writer = itk::ImageFileWriter<ImageType>::New();
    writer->SetInput(image);
    writer->SetFileName(path);
    writer->SetUseCompression(compress);
    writer->Update();
    return path;
  };
  const auto readFails = [](const std::string & path, const std::string & expected) {
    try
    {
      ReadWithPlaneReader(path);
      ADD_FAILURE() << path << " was read without an error";
    }
    catch (const sic::ToolError & error)
    {
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
    }
  };
  // Raw data cut short: refused before reading, saying how much is missing.
  const std::string raw = write("cut.mha", false);
  std::filesystem::resize_file(raw, std::filesystem::file_size(raw) - 100);
  readFails(raw, "truncated");
  const std::string detached = write("cut.nhdr", false);
  std::filesystem::resize_file(Scratch("cut.raw"), 500);
  readFails(detached, "truncated");
  // Compressed data cut short, or damaged (the checksum or the stream fails).
  const std::string gz = write("cut.nrrd", true);
  std::filesystem::resize_file(gz, std::filesystem::file_size(gz) - 40);
  readFails(gz, "truncated");
  const std::string damaged = write("damaged.nrrd", true);
  {
    std::fstream file(damaged, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(-30, std::ios::end);
    const char garbage[8] = { 1, 2, 3, 4, 5, 6, 7, 8 };
    file.write(garbage, sizeof(garbage));
  }
  readFails(damaged, "corrupt");
  // Another format.
  EXPECT_THROW(sic::PlaneReader(Scratch("x.nii").string(), "input"), sic::ToolError);
}
