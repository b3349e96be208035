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
// The streaming filter in ITK pipelines that stream: a reader asked for pieces of a MetaImage
// file, pieces pulled by StreamingImageFilter or a streaming writer, against the in-memory filter.

#include "itkSmallIsoComponentStreamingImageFilter.h"
#include "itkSmallIsoComponentTestUtilities.h"

#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkMetaImageIOFactory.h"
#include "itkStreamingImageFilter.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <filesystem>

namespace
{
using namespace itk;
using namespace itk::SmallIsoComponentTest;

/** Registers ITK's MetaImage IO unless it is registered already. A build against an installed ITK
 * registers ITK's IO factories for every test (UseITK); a build as an ITK module, external or in
 * ITK's source tree, registers none for a GoogleTest driver. */
bool
RegisterMetaImageIO()
{
  for (const auto & factory : ObjectFactoryBase::GetRegisteredFactories())
  {
    if (dynamic_cast<MetaImageIOFactory *>(factory) != nullptr)
    {
      return false;
    }
  }
  MetaImageIOFactory::RegisterOneFactory();
  return true;
}
const bool MetaImageIORegisteredHere = RegisterMetaImageIO();

/** A file of this test's own (ctest runs the tests of this file at the same time). */
std::string
ScratchFile(const std::string & name)
{
  const auto * test = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto   directory =
    std::filesystem::temp_directory_path() / "SmallIsoComponentStreamingImageFilterGTest" / test->name();
  std::filesystem::create_directories(directory);
  return (directory / name).string();
}

/** A pass-through filter that records the largest region it was asked for. */
template <typename TImage>
class RegionRecorder : public ImageToImageFilter<TImage, TImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(RegionRecorder);
  using Self = RegionRecorder;
  using Superclass = ImageToImageFilter<TImage, TImage>;
  using Pointer = SmartPointer<Self>;
  itkNewMacro(Self);

  SizeValueType LargestRequest{ 0 };
  unsigned int  Requests{ 0 };

protected:
  RegionRecorder() = default;
  void
  GenerateData() override
  {
    this->AllocateOutputs();
    const auto & region = this->GetOutput()->GetRequestedRegion();
    LargestRequest = std::max<SizeValueType>(LargestRequest, region.GetNumberOfPixels());
    ++Requests;
    ImageAlgorithm::Copy(this->GetInput(), this->GetOutput(), region, region);
  }
};

template <typename TPixel, unsigned int VDimension>
void
ExpectStreamingMatchesInMemory(const RandomCase<TPixel, VDimension> & c, unsigned int divisions, SizeValueType slab)
{
  using ImageType = Image<TPixel, VDimension>;
  const std::string path = ScratchFile("input.mha");
  auto              writer = ImageFileWriter<ImageType>::New();
  writer->SetInput(c.Input);
  writer->SetFileName(path);
  writer->Update();

  const auto expected = RunFilter<ImageType>(c.Input, c.Settings, 1);

  auto reader = ImageFileReader<ImageType>::New();
  reader->SetFileName(path);
  reader->SetUseStreaming(true);
  auto recorder = RegionRecorder<ImageType>::New();
  recorder->SetInput(reader->GetOutput());
  auto filter = SmallIsoComponentStreamingImageFilter<ImageType>::New();
  filter->SetInput(recorder->GetOutput());
  filter->SetIsoValue(c.Settings.IsoValue);
  filter->SetMaximumComponentSize(c.Settings.MaximumComponentSize);
  filter->SetSide(c.Settings.Side);
  filter->SetFullyConnected(c.Settings.FullyConnected);
  filter->SetSlabThickness(slab);
  auto streamer = StreamingImageFilter<ImageType, ImageType>::New();
  streamer->SetInput(filter->GetOutput());
  streamer->SetNumberOfStreamDivisions(divisions);
  streamer->Update();

  EXPECT_EQ(CountDifferentVoxels(streamer->GetOutput(), expected->GetOutput()), 0u) << c.Description;
  EXPECT_TRUE(filter->GetComplete());
  // Without GenerateRemovedMaskOn() no piece of the mask was made.
  EXPECT_EQ(filter->GetRemovedMask()->GetBufferedRegion().GetNumberOfPixels(), 0u) << c.Description;
  EXPECT_EQ(filter->GetRemovedMask()->GetPixelContainer()->Capacity(), 0u) << c.Description;
  using Side = SmallIsoComponentEnums::Side;
  for (const Side side : { Side::Above, Side::Below })
  {
    EXPECT_EQ(filter->GetNumberOfComponents(side), expected->GetNumberOfComponents(side)) << c.Description;
    EXPECT_EQ(filter->GetNumberOfRemovedComponents(side), expected->GetNumberOfRemovedComponents(side));
    EXPECT_EQ(filter->GetNumberOfRemovedVoxels(side), expected->GetNumberOfRemovedVoxels(side));
    EXPECT_EQ(filter->GetComponentSizeHistogram(side), expected->GetComponentSizeHistogram(side));
  }
  EXPECT_EQ(filter->GetNumberOfModifiedVoxels(), expected->GetNumberOfModifiedVoxels());
  EXPECT_EQ(filter->GetNumberOfUnrepairableVoxels(), expected->GetNumberOfUnrepairableVoxels());
  // The reader was never asked for the whole image when the pieces were thin enough.
  const SizeValueType voxels = c.Input->GetLargestPossibleRegion().GetNumberOfPixels();
  const SizeValueType depth = c.Size[VDimension - 1];
  const SizeValueType reach = SmallIsoComponentDetail::StreamingSweep<TPixel>::WindowPlanes(
    c.Settings.MaximumComponentSize, slab, filter->GetNumberOfWorkUnits());
  if ((depth + divisions - 1) / divisions + reach < depth)
  {
    EXPECT_LT(recorder->LargestRequest, voxels) << c.Description;
  }
  EXPECT_GT(recorder->Requests, 0u);
}

/** The mask pulled in pieces (output 1 streamed on its own) against the in-memory filter's;
 * returns the number of removed voxels the mask marks. */
template <typename TPixel, unsigned int VDimension>
SizeValueType
ExpectStreamedMaskMatchesInMemory(const RandomCase<TPixel, VDimension> & c, unsigned int divisions, SizeValueType slab)
{
  using ImageType = Image<TPixel, VDimension>;
  using FilterType = SmallIsoComponentStreamingImageFilter<ImageType>;
  using MaskImageType = typename FilterType::MaskImageType;
  const auto expected = RunFilter<ImageType>(c.Input, c.Settings, 1);

  auto filter = FilterType::New();
  filter->SetInput(c.Input);
  filter->SetIsoValue(c.Settings.IsoValue);
  filter->SetMaximumComponentSize(c.Settings.MaximumComponentSize);
  filter->SetSide(c.Settings.Side);
  filter->SetFullyConnected(c.Settings.FullyConnected);
  filter->SetSlabThickness(slab);
  filter->GenerateRemovedMaskOn();
  auto streamer = StreamingImageFilter<MaskImageType, MaskImageType>::New();
  streamer->SetInput(filter->GetRemovedMask());
  streamer->SetNumberOfStreamDivisions(divisions);
  streamer->Update();

  const MaskImageType * mask = streamer->GetOutput();
  EXPECT_EQ(mask->GetBufferedRegion(), expected->GetRemovedMask()->GetBufferedRegion()) << c.Description;
  if (mask->GetBufferedRegion() != expected->GetRemovedMask()->GetBufferedRegion())
  {
    return 0;
  }
  EXPECT_EQ(CountDifferentVoxels(mask, expected->GetRemovedMask()), 0u) << c.Description;
  EXPECT_TRUE(filter->GetComplete());
  EXPECT_EQ(filter->GetNumberOfModifiedVoxels(), expected->GetNumberOfModifiedVoxels()) << c.Description;
  // The last piece of the mask is in the filter's output 1, as large as that piece of output 0.
  EXPECT_EQ(filter->GetRemovedMask()->GetBufferedRegion(), filter->GetOutput()->GetBufferedRegion());
  const SizeValueType n = mask->GetBufferedRegion().GetNumberOfPixels();
  return static_cast<SizeValueType>(
    std::count_if(mask->GetBufferPointer(), mask->GetBufferPointer() + n, [](uint8_t m) { return m != 0; }));
}
} // namespace

TEST(SmallIsoComponentStreamingImageFilter, PiecesMatchTheInMemoryFilter)
{
  for (uint32_t seed = 1; seed <= 60; ++seed)
  {
    const auto c = MakeRandomCase<uint8_t, uint8_t, 3>(seed, seed % 3 == 0);
    ExpectStreamingMatchesInMemory(c, 1 + seed % 7, 1 + seed % 4);
  }
}

TEST(SmallIsoComponentStreamingImageFilter, PiecesOf2DImagesMatchTheInMemoryFilter)
{
  for (uint32_t seed = 101; seed <= 160; ++seed)
  {
    const auto c = MakeRandomCase<float, float, 2>(seed);
    ExpectStreamingMatchesInMemory(c, 1 + seed % 5, 1 + seed % 3);
  }
}

TEST(SmallIsoComponentStreamingImageFilter, TallVolumeIsReadInPieces)
{
  // A tall noisy volume with small K: the reader must only be asked for slabs.
  RandomSource           random(5);
  RandomCase<int16_t, 3> c;
  c.Size = { 24, 20, 200 };
  for (SizeValueType v = 0; v < 24 * 20 * 200; ++v)
  {
    c.Values.push_back(static_cast<int16_t>(random.Chance(0.45) ? 1000 : -1000));
  }
  c.Input = MakeImage<int16_t, 3>(c.Size, c.Values);
  c.Settings.IsoValue = 0.5;
  c.Settings.MaximumComponentSize = 3;
  c.Settings.Side = SmallIsoComponentEnums::Side::Both;
  ExpectStreamingMatchesInMemory(c, 20, 4);
}

TEST(SmallIsoComponentStreamingImageFilter, MaskPiecesMatchTheInMemoryMask)
{
  SizeValueType marked3D = 0;
  for (uint32_t seed = 201; seed <= 230; ++seed)
  {
    const auto c = MakeRandomCase<uint8_t, uint8_t, 3>(seed, seed % 3 == 0);
    marked3D += ExpectStreamedMaskMatchesInMemory(c, 1 + seed % 7, 1 + seed % 4);
  }
  SizeValueType marked2D = 0;
  for (uint32_t seed = 301; seed <= 330; ++seed)
  {
    const auto c = MakeRandomCase<float, float, 2>(seed);
    marked2D += ExpectStreamedMaskMatchesInMemory(c, 1 + seed % 5, 1 + seed % 3);
  }
  // The cases remove voxels, so the masks compared are not all zero.
  EXPECT_GT(marked3D, 0u);
  EXPECT_GT(marked2D, 0u);
}

TEST(SmallIsoComponentStreamingImageFilter, AStreamingWriterWritesTheInMemoryResult)
{
  const auto c = MakeRandomCase<int16_t, int16_t, 3>(77, true);
  using ImageType = Image<int16_t, 3>;
  const auto expected = RunFilter<ImageType>(c.Input, c.Settings, 2);
  auto       filter = SmallIsoComponentStreamingImageFilter<ImageType>::New();
  filter->SetInput(c.Input);
  filter->SetIsoValue(c.Settings.IsoValue);
  filter->SetMaximumComponentSize(c.Settings.MaximumComponentSize);
  filter->SetSide(c.Settings.Side);
  filter->SetFullyConnected(c.Settings.FullyConnected);
  const std::string path = ScratchFile("streamed.mha");
  auto              writer = ImageFileWriter<ImageType>::New();
  writer->SetInput(filter->GetOutput());
  writer->SetFileName(path);
  writer->SetNumberOfStreamDivisions(7);
  writer->Update();
  auto reader = ImageFileReader<ImageType>::New();
  reader->SetFileName(path);
  reader->Update();
  EXPECT_EQ(CountDifferentVoxels(reader->GetOutput(), expected->GetOutput()), 0u) << c.Description;
  // A second run after a change starts the sweep again.
  filter->SetMaximumComponentSize(c.Settings.MaximumComponentSize + 3);
  auto settings = c.Settings;
  settings.MaximumComponentSize += 3;
  const auto again = RunFilter<ImageType>(c.Input, settings, 2);
  writer->Update();
  reader->Modified();
  reader->Update();
  EXPECT_EQ(CountDifferentVoxels(reader->GetOutput(), again->GetOutput()), 0u) << c.Description;
  EXPECT_EQ(filter->GetNumberOfModifiedVoxels(), again->GetNumberOfModifiedVoxels());
}
