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

// Regression test: synthesises a noisy object with specks and bubbles, removes them, and
// writes the result for the test driver to --compare with a baseline. The baselines are
// written by this same function in "reference" mode, which runs the brute-force reference
// instead of the filter (see Baseline/README.md).

#include "itkImageFileWriter.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkSmallIsoComponentImageFilter.h"
#include "itkSmallIsoComponentReference.h"
#include "itkTestingMacros.h"
#include <cstring>
#include <random>

namespace
{
/** Raw std::mt19937 bits, mapped by hand: the same image with every standard library. */
class NoiseSource
{
public:
  explicit NoiseSource(uint32_t seed)
    : m_Engine(seed)
  {}
  /** An integer in [0, n). */
  int
  Below(int n)
  {
    return static_cast<int>(m_Engine() % static_cast<uint32_t>(n));
  }

private:
  std::mt19937 m_Engine;
};

/** Sets a voxel of a cube of edge \a edge at \a corner to \a value, and its centre voxel
 * to \a centre: a speck with a bubble, or a bubble with a speck. */
template <typename TImage>
void
PlantShell(TImage * image, const typename TImage::IndexType & corner, int edge, uint8_t value, uint8_t centre)
{
  typename TImage::SizeType size;
  size.Fill(static_cast<itk::SizeValueType>(edge));
  itk::ImageRegionIteratorWithIndex<TImage> it(image, typename TImage::RegionType(corner, size));
  for (; !it.IsAtEnd(); ++it)
  {
    bool isCentre = true;
    for (unsigned int a = 0; a < TImage::ImageDimension; ++a)
    {
      isCentre = isCentre && it.GetIndex()[a] == corner[a] + edge / 2;
    }
    it.Set(isCentre ? centre : value);
  }
}

/** An object (a ball in 3D, a ring in 2D) of values around 170 on a background around 60,
 * with noise of -30, -20, ..., 30 (few levels keep the baselines small), 3% salt noise (single-voxel specks and
 * bubbles), and planted shells: specks with a bubble inside, bubbles with a speck inside. */
template <unsigned int VDimension>
typename itk::Image<uint8_t, VDimension>::Pointer
SynthesizeInput()
{
  using ImageType = itk::Image<uint8_t, VDimension>;
  typename ImageType::SizeType size;
  size.Fill(VDimension == 3 ? 32 : 64);
  auto image = ImageType::New();
  image->SetRegions(size);
  image->Allocate();

  NoiseSource                                  noise(VDimension);
  itk::ImageRegionIteratorWithIndex<ImageType> it(image, image->GetBufferedRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    // Squared distance from the centre, in half voxels, so that all of it is integer.
    int distance2 = 0;
    for (unsigned int a = 0; a < VDimension; ++a)
    {
      const int d = 2 * static_cast<int>(it.GetIndex()[a]) - (static_cast<int>(size[a]) - 1);
      distance2 += d * d;
    }
    const bool object = VDimension == 3 ? distance2 <= 22 * 22 : distance2 >= 20 * 20 && distance2 <= 48 * 48;
    const bool salt = noise.Below(100) < 3;
    it.Set(static_cast<uint8_t>((object != salt ? 170 : 60) + 10 * noise.Below(7) - 30));
  }
  typename ImageType::IndexType corner;
  corner.Fill(2);
  PlantShell(image.GetPointer(), corner, 3, 200, 40); // a speck with a bubble, outside
  corner.Fill(13);
  corner[0] = VDimension == 3 ? 13 : 30;
  PlantShell(image.GetPointer(), corner, 3, 40, 200); // a bubble with a speck, in the object
  corner.Fill(VDimension == 3 ? 26 : 56);
  PlantShell(image.GetPointer(), corner, 5, 200, 40); // a speck bigger than K, outside
  return image;
}

template <unsigned int VDimension>
int
RemoveSmallComponents(bool fullyConnected, const char * engine, const char * outputFileName)
{
  using ImageType = itk::Image<uint8_t, VDimension>;
  using FilterType = itk::SmallIsoComponentImageFilter<ImageType>;
  using SideEnum = itk::SmallIsoComponentEnums::Side;

  const auto                                  input = SynthesizeInput<VDimension>();
  itk::SmallIsoComponentReference::Parameters parameters;
  parameters.IsoValue = VDimension == 3 ? 115.0 : 114.5;
  parameters.MaximumComponentSize = VDimension == 3 ? 8 : 6;
  parameters.Side = SideEnum::Both;
  parameters.FullyConnected = fullyConnected;
  const auto expected = itk::SmallIsoComponentReference::Run<uint8_t>(input.GetPointer(), parameters);

  auto output = ImageType::New();
  if (std::strcmp(engine, "reference") == 0)
  {
    output->SetRegions(input->GetLargestPossibleRegion());
    output->Allocate();
    std::copy(expected.Output.begin(), expected.Output.end(), output->GetBufferPointer());
  }
  else
  {
    auto filter = FilterType::New();
    ITK_EXERCISE_BASIC_OBJECT_METHODS(filter, SmallIsoComponentImageFilter, SmallIsoComponentImageFilterBase);
    ITK_TRY_EXPECT_EXCEPTION(filter->Update()); // no input yet

    filter->SetInput(input);
    filter->SetIsoValue(parameters.IsoValue);
    ITK_TEST_SET_GET_VALUE(parameters.IsoValue, filter->GetIsoValue());
    filter->SetMaximumComponentSize(parameters.MaximumComponentSize);
    ITK_TEST_SET_GET_VALUE(parameters.MaximumComponentSize, filter->GetMaximumComponentSize());
    filter->SetSide(parameters.Side);
    ITK_TEST_SET_GET_VALUE(parameters.Side, filter->GetSide());
    ITK_TEST_SET_GET_BOOLEAN(filter, FullyConnected, fullyConnected);
    ITK_TEST_SET_GET_BOOLEAN(filter, GenerateRemovedMask, false);
    filter->SetFullyConnected(fullyConnected);
    const int workUnits = std::atoi(engine);
    if (workUnits > 0)
    {
      filter->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(workUnits));
    }
    ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
    ITK_TRY_EXPECT_EXCEPTION(filter->GetNumberOfComponents(SideEnum::Both));

    // The statistics, which the baseline image cannot check.
    std::cout << "Work units: " << filter->GetNumberOfWorkUnits() << std::endl;
    const std::pair<SideEnum, const itk::SmallIsoComponentReference::SideStatistics *> sides[] = {
      { SideEnum::Above, &expected.Above }, { SideEnum::Below, &expected.Below }
    };
    for (const auto & side : sides)
    {
      std::cout << side.first << ": " << filter->GetNumberOfComponents(side.first) << " components, "
                << filter->GetNumberOfRemovedComponents(side.first) << " removed ("
                << filter->GetNumberOfRemovedVoxels(side.first) << " voxels)" << std::endl;
      ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfComponents(side.first), side.second->Components);
      ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfRemovedComponents(side.first), side.second->RemovedComponents);
      ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfRemovedVoxels(side.first), side.second->RemovedVoxels);
      ITK_TEST_EXPECT_TRUE(filter->GetComponentSizeHistogram(side.first) == side.second->Histogram);
    }
    ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfModifiedVoxels(), expected.ModifiedVoxels);
    ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfUnrepairableVoxels(), expected.UnrepairableVoxels);
    // The synthetic image is meant to exercise both passes.
    ITK_TEST_EXPECT_TRUE(expected.Above.RemovedComponents > 10 && expected.Below.RemovedComponents > 10);
    output = filter->GetOutput();
  }

  auto writer = itk::ImageFileWriter<ImageType>::New();
  writer->SetInput(output);
  writer->SetFileName(outputFileName);
  writer->UseCompressionOn();
  ITK_TRY_EXPECT_NO_EXCEPTION(writer->Update());
  return EXIT_SUCCESS;
}
} // namespace

int
itkSmallIsoComponentImageFilterTest(int argc, char * argv[])
{
  if (argc != 5)
  {
    std::cerr << "Missing parameters." << std::endl;
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv)
              << " ball3D|ring2D face|full <workUnits (0: the filter's default)>|reference output.mha" << std::endl;
    return EXIT_FAILURE;
  }
  const std::string kind = argv[1];
  const std::string connectivity = argv[2];
  if ((kind != "ball3D" && kind != "ring2D") || (connectivity != "face" && connectivity != "full"))
  {
    std::cerr << "Unknown input " << kind << " or connectivity " << connectivity << std::endl;
    return EXIT_FAILURE;
  }
  const bool fullyConnected = connectivity == "full";
  return kind == "ball3D" ? RemoveSmallComponents<3>(fullyConnected, argv[3], argv[4])
                          : RemoveSmallComponents<2>(fullyConnected, argv[3], argv[4]);
}
