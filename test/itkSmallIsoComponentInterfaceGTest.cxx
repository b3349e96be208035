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

// The filter as an ITK object: parameters and their defaults, printing, errors,
// progress and abort; the streaming filter's share of the same interface, through their base
// class.

#include "itkCommand.h"
#include "itkSmallIsoComponentStreamingImageFilter.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>

namespace
{
using namespace itk::SmallIsoComponentTest;
using ImageType = itk::Image<uint8_t, 3>;
using FilterType = itk::SmallIsoComponentImageFilter<ImageType>;
using StreamingFilterType = itk::SmallIsoComponentStreamingImageFilter<ImageType>;
using BaseType = itk::SmallIsoComponentImageFilterBase<ImageType>;

/** 16 x 16 x \a depth voxels of uniform noise: with σ = 128 and K = 20, thousands of small
 * components. */
ImageType::Pointer
MakeSpeckledImage(itk::SizeValueType depth = 16, uint32_t seed = 12345)
{
  RandomSource         random(seed);
  std::vector<uint8_t> values(16 * 16 * depth);
  for (uint8_t & v : values)
  {
    v = static_cast<uint8_t>(random.Bits() >> 24);
  }
  return MakeImage<uint8_t, 3>({ 16, 16, depth }, values);
}

/** Records the progress of every progress event of \a filter in \a progress. */
void
RecordProgress(FilterType * filter, std::vector<float> & progress)
{
  auto observer = itk::CStyleCommand::New();
  observer->SetClientData(&progress);
  observer->SetCallback([](itk::Object * caller, const itk::EventObject &, void * clientData) {
    static_cast<std::vector<float> *>(clientData)->push_back(static_cast<FilterType *>(caller)->GetProgress());
  });
  filter->AddObserver(itk::ProgressEvent(), observer);
}

/** What Print() writes for \a filter, with the same parameters set through the base class. */
std::string
PrintedWithParameters(BaseType * filter)
{
  filter->SetIsoValue(12.25);
  filter->SetMaximumComponentVolume(7.5);
  filter->SetMaximumComponentSize(9);
  filter->SetSide(SideEnum::Below);
  filter->FullyConnectedOn();
  filter->GenerateRemovedMaskOn();
  std::ostringstream printed;
  filter->Print(printed);
  return printed.str();
}

/** Runs \a filter on the speckled image with parameters set through the base class and
 * GenerateRemovedMaskOn(). */
void
RunThroughTheBase(BaseType * filter, const ImageType * input)
{
  filter->SetInput(input);
  filter->SetIsoValue(128);
  filter->SetMaximumComponentVolume(6.0);
  filter->SetSide(SideEnum::Both);
  filter->FullyConnectedOff();
  filter->GenerateRemovedMaskOn();
  filter->Update();
}

/** The description of the exception \a call throws, or a note that it threw none. */
template <typename TCall>
std::string
ExceptionDescription(TCall call)
{
  try
  {
    call();
  }
  catch (const itk::ExceptionObject & e)
  {
    return e.GetDescription();
  }
  return "(no exception)";
}
} // namespace

TEST(SmallIsoComponentInterface, Defaults)
{
  auto                            inMemory = FilterType::New();
  auto                            streaming = StreamingFilterType::New();
  const std::array<BaseType *, 2> filters{ { inMemory.GetPointer(), streaming.GetPointer() } };
  for (BaseType * filter : filters)
  {
    EXPECT_EQ(filter->GetIsoValue(), 0.0);
    EXPECT_EQ(filter->GetMaximumComponentSize(), 20u);
    EXPECT_EQ(filter->GetMaximumComponentVolume(), 0.0);
    EXPECT_FALSE(filter->GetUseMaximumComponentVolume());
    EXPECT_EQ(filter->GetSide(), SideEnum::Both);
    EXPECT_FALSE(filter->GetFullyConnected());
    EXPECT_FALSE(filter->GetGenerateRemovedMask());
    EXPECT_FALSE(filter->GetInPlace());
    EXPECT_EQ(filter->GetNumberOfIndexedOutputs(), 2u);
    EXPECT_NE(filter->GetRemovedMask(), nullptr);
  }
  EXPECT_TRUE(inMemory->CanRunInPlace());
  EXPECT_EQ(inMemory->GetSlabThickness(), 0u);
  EXPECT_EQ(inMemory->GetSlabSweepMinimumSize(), itk::SizeValueType{ 1 } << 30);
  EXPECT_FALSE(inMemory->GetSweptInSlabs());
  EXPECT_STREQ(inMemory->GetNameOfClass(), "SmallIsoComponentImageFilter");
  EXPECT_FALSE(streaming->CanRunInPlace());
  EXPECT_EQ(streaming->GetSlabThickness(), 8u);
  EXPECT_STREQ(streaming->GetNameOfClass(), "SmallIsoComponentStreamingImageFilter");
}

TEST(SmallIsoComponentInterface, SetAndGetEveryParameter)
{
  auto filter = FilterType::New();
  for (const double iso : { -1.5, 0.0, 127.5, 1.0e9 })
  {
    filter->SetIsoValue(iso);
    EXPECT_EQ(filter->GetIsoValue(), iso);
  }
  for (const itk::SizeValueType size : { 0u, 1u, 20u, 1000000u })
  {
    filter->SetMaximumComponentSize(size);
    EXPECT_EQ(filter->GetMaximumComponentSize(), size);
    EXPECT_FALSE(filter->GetUseMaximumComponentVolume());
  }
  for (const double volume : { 0.0, 2.5, 28.0 })
  {
    filter->SetMaximumComponentVolume(volume);
    EXPECT_EQ(filter->GetMaximumComponentVolume(), volume);
    EXPECT_TRUE(filter->GetUseMaximumComponentVolume());
  }
  // Setting the size again (even to its old value) makes the size the threshold.
  filter->SetMaximumComponentSize(1000000u);
  EXPECT_FALSE(filter->GetUseMaximumComponentVolume());
  EXPECT_EQ(filter->GetMaximumComponentVolume(), 28.0);
  for (const SideEnum side : { SideEnum::Above, SideEnum::Below, SideEnum::Both })
  {
    filter->SetSide(side);
    EXPECT_EQ(filter->GetSide(), side);
  }
  filter->SetFullyConnected(true);
  EXPECT_TRUE(filter->GetFullyConnected());
  filter->FullyConnectedOff();
  EXPECT_FALSE(filter->GetFullyConnected());
  filter->FullyConnectedOn();
  EXPECT_TRUE(filter->GetFullyConnected());
}

TEST(SmallIsoComponentInterface, ChangingAParameterReruns)
{
  auto filter = FilterType::New();
  filter->SetInput(MakeSpeckledImage());
  filter->SetIsoValue(128);
  filter->Update();
  const itk::ModifiedTimeType before = filter->GetMTime();
  filter->SetIsoValue(128);
  EXPECT_EQ(filter->GetMTime(), before) << "setting the same value must not modify the filter";
  filter->SetMaximumComponentSize(0);
  EXPECT_GT(filter->GetMTime(), before);
  filter->Update();
  EXPECT_EQ(filter->GetNumberOfModifiedVoxels(), 0u);
  EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 0u);
}

TEST(SmallIsoComponentInterface, PrintSelfMentionsEveryParameter)
{
  auto streaming = StreamingFilterType::New();
  streaming->SetSlabThickness(3);
  for (const std::string & text : { PrintedWithParameters(FilterType::New()), PrintedWithParameters(streaming) })
  {
    for (const char * expected : { "IsoValue: 12.25",
                                   "MaximumComponentSize: 9",
                                   "MaximumComponentVolume: 7.5",
                                   "UseMaximumComponentVolume: Off",
                                   "Side: itk::SmallIsoComponentEnums::Side::Below",
                                   "FullyConnected: On",
                                   "GenerateRemovedMask: On",
                                   "EffectiveMaximumComponentSize: 0" })
    {
      EXPECT_NE(text.find(expected), std::string::npos) << "\"" << expected << "\" not in\n" << text;
    }
  }
  std::ostringstream printed;
  streaming->Print(printed);
  EXPECT_NE(printed.str().find("SlabThickness: 3"), std::string::npos) << printed.str();
}

TEST(SmallIsoComponentInterface, BothFiltersThroughTheBaseClass)
{
  const auto input = MakeSpeckledImage();
  auto       inMemory = FilterType::New();
  auto       streaming = StreamingFilterType::New();
  RunThroughTheBase(inMemory, input);
  RunThroughTheBase(streaming, input);
  const std::array<BaseType *, 2> filters{ { inMemory.GetPointer(), streaming.GetPointer() } };
  for (BaseType * filter : filters)
  {
    // A volume of 6 voxels of spacing 1.
    EXPECT_TRUE(filter->GetUseMaximumComponentVolume()) << filter->GetNameOfClass();
    EXPECT_EQ(filter->GetEffectiveMaximumComponentSize(), 6u) << filter->GetNameOfClass();
    for (const SideEnum side : { SideEnum::Above, SideEnum::Below })
    {
      EXPECT_EQ(filter->GetNumberOfComponents(side), inMemory->GetNumberOfComponents(side));
      EXPECT_EQ(filter->GetNumberOfRemovedComponents(side), inMemory->GetNumberOfRemovedComponents(side));
      EXPECT_EQ(filter->GetNumberOfRemovedVoxels(side), inMemory->GetNumberOfRemovedVoxels(side));
      EXPECT_THROW(filter->GetNumberOfComponents(SideEnum::Both), itk::ExceptionObject);
    }
    const auto * mask = filter->GetRemovedMask();
    ASSERT_EQ(mask->GetBufferedRegion(), input->GetLargestPossibleRegion()) << filter->GetNameOfClass();
    EXPECT_TRUE(std::equal(mask->GetBufferPointer(),
                           mask->GetBufferPointer() + input->GetLargestPossibleRegion().GetNumberOfPixels(),
                           inMemory->GetRemovedMask()->GetBufferPointer()))
      << filter->GetNameOfClass();
  }
  EXPECT_GT(inMemory->GetNumberOfRemovedComponents(SideEnum::Above), 0u);
  EXPECT_GT(inMemory->GetNumberOfRemovedComponents(SideEnum::Below), 0u);
  EXPECT_EQ(streaming->GetNumberOfModifiedVoxels(), inMemory->GetNumberOfModifiedVoxels());
  EXPECT_EQ(streaming->GetComponentSizeHistogram(SideEnum::Below),
            inMemory->GetComponentSizeHistogram(SideEnum::Below));
}

TEST(SmallIsoComponentInterface, StreamingFilterNeverRunsInPlace)
{
  const auto                 input = MakeSpeckledImage();
  const auto                 n = input->GetLargestPossibleRegion().GetNumberOfPixels();
  const std::vector<uint8_t> before(input->GetBufferPointer(), input->GetBufferPointer() + n);
  auto                       filter = StreamingFilterType::New();
  filter->SetInput(input);
  filter->SetIsoValue(128);
  filter->InPlaceOn();
  filter->Update();
  EXPECT_NE(filter->GetOutput()->GetBufferPointer(), input->GetBufferPointer());
  EXPECT_TRUE(std::equal(before.begin(), before.end(), input->GetBufferPointer())) << "the input was written";
  EXPECT_GT(filter->GetNumberOfModifiedVoxels(), 0u);
}

TEST(SmallIsoComponentInterface, StreamingFilterChecksItsParameters)
{
  auto filter = StreamingFilterType::New();
  EXPECT_NE(ExceptionDescription([&] { filter->GetNumberOfComponents(SideEnum::Above); }).find("has not run"),
            std::string::npos);
  filter->SetInput(MakeSpeckledImage());
  filter->SetIsoValue(std::nan(""));
  EXPECT_NE(ExceptionDescription([&] { filter->Update(); }).find("IsoValue"), std::string::npos);
  filter->SetIsoValue(100);
  filter->SetMaximumComponentVolume(-1.0);
  EXPECT_NE(ExceptionDescription([&] { filter->Update(); }).find("MaximumComponentVolume"), std::string::npos);
  filter->SetMaximumComponentSize(3);
  filter->SetSide(static_cast<SideEnum>(7));
  EXPECT_NE(ExceptionDescription([&] { filter->Update(); }).find("Side"), std::string::npos);
  filter->SetSide(SideEnum::Both);
  EXPECT_NO_THROW(filter->Update());
  EXPECT_NE(ExceptionDescription([&] { filter->GetNumberOfRemovedVoxels(SideEnum::Both); }).find("per side"),
            std::string::npos);
  EXPECT_THROW(filter->GetComponentSizeHistogram(SideEnum::Both), itk::ExceptionObject);
}

TEST(SmallIsoComponentInterface, SideEnumPrintsItsQualifiedName)
{
  const auto print = [](SideEnum side) {
    std::ostringstream out;
    out << side;
    return out.str();
  };
  EXPECT_EQ(print(SideEnum::Above), "itk::SmallIsoComponentEnums::Side::Above");
  EXPECT_EQ(print(SideEnum::Below), "itk::SmallIsoComponentEnums::Side::Below");
  EXPECT_EQ(print(SideEnum::Both), "itk::SmallIsoComponentEnums::Side::Both");
}

TEST(SmallIsoComponentInterface, PhaseEnumPrintsItsQualifiedName)
{
  using PhaseEnum = itk::SmallIsoComponentEnums::Phase;
  const std::array<const char *, itk::SmallIsoComponentEnums::NumberOfPhases> names{ "Encoding",  "Linking",  "Seams",
                                                                                     "Numbering", "Deciding", "Repair",
                                                                                     "Writes" };
  for (unsigned int phase = 0; phase < names.size(); ++phase)
  {
    std::ostringstream out;
    out << static_cast<PhaseEnum>(phase);
    EXPECT_EQ(out.str(), std::string("itk::SmallIsoComponentEnums::Phase::") + names[phase]);
  }
}

TEST(SmallIsoComponentInterface, PhaseTimesAddUpToTheUpdate)
{
  using PhaseEnum = itk::SmallIsoComponentEnums::Phase;
  const auto phaseSum = [](const FilterType * filter) {
    double sum = 0;
    for (unsigned int phase = 0; phase < itk::SmallIsoComponentEnums::NumberOfPhases; ++phase)
    {
      const double seconds = filter->GetPhaseSeconds(static_cast<PhaseEnum>(phase));
      EXPECT_GE(seconds, 0.0) << static_cast<PhaseEnum>(phase);
      sum += seconds;
    }
    return sum;
  };
  for (const unsigned int workUnits : { 1u, 2u })
  {
    auto filter = FilterType::New();
    filter->SetInput(MakeSpeckledImage(64, 99));
    filter->SetIsoValue(128);
    filter->SetMaximumComponentSize(20);
    filter->SetNumberOfWorkUnits(workUnits);
    const auto start = std::chrono::steady_clock::now();
    filter->Update();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_GT(filter->GetNumberOfRemovedComponents(SideEnum::Above), 0u);
    ASSERT_GT(filter->GetNumberOfRemovedComponents(SideEnum::Below), 0u);
    // Every phase ran, and the phases follow one another inside the update.
    for (unsigned int phase = 0; phase < itk::SmallIsoComponentEnums::NumberOfPhases; ++phase)
    {
      EXPECT_GT(filter->GetPhaseSeconds(static_cast<PhaseEnum>(phase)), 0.0) << static_cast<PhaseEnum>(phase);
    }
    EXPECT_LE(phaseSum(filter), wall);

    // Nothing to remove: no repair and no writes, and nothing left from the update before.
    filter->SetInput(MakeImage<uint8_t, 3>({ 16, 16, 16 }, std::vector<uint8_t>(16 * 16 * 16, 7)));
    filter->Update();
    EXPECT_EQ(filter->GetPhaseSeconds(PhaseEnum::Repair), 0.0);
    EXPECT_EQ(filter->GetPhaseSeconds(PhaseEnum::Writes), 0.0);
    EXPECT_GT(filter->GetPhaseSeconds(PhaseEnum::Encoding), 0.0);

    // A sweep in slabs has none of these phases.
    filter->SetInput(MakeSpeckledImage(64, 99));
    filter->SetSlabThickness(4);
    filter->Update();
    ASSERT_TRUE(filter->GetSweptInSlabs());
    EXPECT_EQ(phaseSum(filter), 0.0);
  }
}

TEST(SmallIsoComponentInterface, NaNIsoValueIsAnError)
{
  auto filter = FilterType::New();
  filter->SetInput(MakeSpeckledImage());
  filter->SetIsoValue(std::nan(""));
  EXPECT_THROW(filter->Update(), itk::ExceptionObject);
  EXPECT_NE(ExceptionDescription([&] { filter->Update(); }).find("IsoValue"), std::string::npos);
  filter->SetIsoValue(100);
  EXPECT_NO_THROW(filter->Update());
}

TEST(SmallIsoComponentInterface, NegativeMaximumComponentVolumeIsAnError)
{
  auto filter = FilterType::New();
  filter->SetInput(MakeSpeckledImage());
  filter->SetMaximumComponentVolume(-1.0);
  EXPECT_NE(ExceptionDescription([&] { filter->Update(); }).find("MaximumComponentVolume"), std::string::npos);
  // Taking the size as the threshold again makes the filter valid.
  filter->SetMaximumComponentSize(3);
  EXPECT_NO_THROW(filter->Update());
}

TEST(SmallIsoComponentInterface, InvalidSideIsAnError)
{
  auto filter = FilterType::New();
  filter->SetInput(MakeSpeckledImage());
  filter->SetSide(static_cast<SideEnum>(7));
  EXPECT_NE(ExceptionDescription([&] { filter->Update(); }).find("Side"), std::string::npos);
}

TEST(SmallIsoComponentInterface, StatisticsOfBothIsAnError)
{
  auto filter = FilterType::New();
  filter->SetInput(MakeSpeckledImage());
  filter->Update();
  EXPECT_THROW(filter->GetNumberOfComponents(SideEnum::Both), itk::ExceptionObject);
  EXPECT_THROW(filter->GetNumberOfRemovedComponents(SideEnum::Both), itk::ExceptionObject);
  EXPECT_THROW(filter->GetNumberOfRemovedVoxels(SideEnum::Both), itk::ExceptionObject);
  EXPECT_THROW(filter->GetComponentSizeHistogram(SideEnum::Both), itk::ExceptionObject);
  EXPECT_NO_THROW(filter->GetNumberOfComponents(SideEnum::Above));
  EXPECT_NO_THROW(filter->GetComponentSizeHistogram(SideEnum::Below));
}

TEST(SmallIsoComponentInterface, MissingInputIsAnError)
{
  auto filter = FilterType::New();
  EXPECT_THROW(filter->Update(), itk::ExceptionObject);
}

TEST(SmallIsoComponentInterface, ProgressReachesOne)
{
  // The whole image at once, and in slabs of 3 planes.
  for (const itk::SizeValueType slab : { 0u, 3u })
  {
    auto               filter = FilterType::New();
    std::vector<float> progress;
    RecordProgress(filter, progress);
    filter->SetInput(MakeSpeckledImage());
    filter->SetIsoValue(128);
    filter->SetSlabThickness(slab);
    filter->Update();
    EXPECT_EQ(filter->GetSweptInSlabs(), slab > 0);
    EXPECT_EQ(filter->GetSweptSlabThickness(), slab);
    ASSERT_GE(progress.size(), 3u);
    EXPECT_EQ(progress.back(), 1.0f);
    EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end())) << "progress went backwards";
  }
}

TEST(SmallIsoComponentInterface, AbortOnFirstProgressEvent)
{
  // The whole image at once, and in slabs of 3 planes with the labelling on a second thread.
  for (const itk::SizeValueType slab : { 0u, 3u })
  {
    auto filter = FilterType::New();
    auto observer = itk::CStyleCommand::New();
    observer->SetCallback([](itk::Object * caller, const itk::EventObject &, void *) {
      static_cast<FilterType *>(caller)->AbortGenerateDataOn();
    });
    const unsigned long tag = filter->AddObserver(itk::ProgressEvent(), observer);
    filter->SetInput(MakeSpeckledImage());
    filter->SetIsoValue(128);
    filter->SetSlabThickness(slab);
    filter->SetNumberOfWorkUnits(2);
    EXPECT_THROW(filter->Update(), itk::ProcessAborted);

    // Without the observer the next update runs to the end.
    filter->RemoveObserver(tag);
    filter->Modified();
    EXPECT_NO_THROW(filter->Update());
    EXPECT_EQ(filter->GetProgress(), 1.0f);
  }
}

namespace
{
FilterType::Pointer
RunOnTallImage(const ImageType * input, itk::SizeValueType minimumSize, itk::SizeValueType K, unsigned int workUnits)
{
  auto filter = FilterType::New();
  filter->SetInput(input);
  filter->SetIsoValue(128);
  filter->SetMaximumComponentSize(K);
  filter->SetSlabSweepMinimumSize(minimumSize);
  filter->SetNumberOfWorkUnits(workUnits);
  filter->GenerateRemovedMaskOn();
  filter->Update();
  return filter;
}
} // namespace

TEST(SmallIsoComponentInterface, SweepInSlabsOnlyForLargeImagesAndAThinWindow)
{
  // Deep enough for a sweep in slabs with small K.
  const auto input = MakeSpeckledImage(2000, 777);
  for (const unsigned int workUnits : { 1u, 2u })
  {
    const auto whole = RunOnTallImage(input, itk::NumericTraits<itk::SizeValueType>::max(), 3, workUnits);
    EXPECT_FALSE(whole->GetSweptInSlabs());
    EXPECT_EQ(whole->GetSweptSlabThickness(), 0u);
    // The default minimum is far above 512,000 voxels.
    EXPECT_FALSE(RunOnTallImage(input, FilterType::DefaultSlabSweepMinimumSize, 3, workUnits)->GetSweptInSlabs());
    // Above the minimum: slabs of a sixteenth of the depth (the plane is far below 2^24 voxels).
    const auto swept = RunOnTallImage(input, 1, 3, workUnits);
    EXPECT_TRUE(swept->GetSweptInSlabs());
    EXPECT_EQ(swept->GetSweptSlabThickness(), 125u);
    EXPECT_GT(swept->GetNumberOfRemovedComponents(SideEnum::Above), 1000u);
    const auto n = input->GetLargestPossibleRegion().GetNumberOfPixels();
    EXPECT_TRUE(std::equal(whole->GetOutput()->GetBufferPointer(),
                           whole->GetOutput()->GetBufferPointer() + n,
                           swept->GetOutput()->GetBufferPointer()));
    EXPECT_TRUE(std::equal(whole->GetRemovedMask()->GetBufferPointer(),
                           whole->GetRemovedMask()->GetBufferPointer() + n,
                           swept->GetRemovedMask()->GetBufferPointer()));
    for (const SideEnum side : { SideEnum::Above, SideEnum::Below })
    {
      EXPECT_EQ(swept->GetNumberOfComponents(side), whole->GetNumberOfComponents(side));
      EXPECT_EQ(swept->GetNumberOfRemovedComponents(side), whole->GetNumberOfRemovedComponents(side));
      EXPECT_EQ(swept->GetNumberOfRemovedVoxels(side), whole->GetNumberOfRemovedVoxels(side));
      EXPECT_EQ(swept->GetComponentSizeHistogram(side), whole->GetComponentSizeHistogram(side));
    }
    EXPECT_EQ(swept->GetNumberOfModifiedVoxels(), whole->GetNumberOfModifiedVoxels());
    EXPECT_EQ(swept->GetNumberOfUnrepairableVoxels(), whole->GetNumberOfUnrepairableVoxels());
    // The sweep holds a window of planes, not 8 bytes per run of the whole image.
    EXPECT_LT(swept->GetPeakExtraMemoryInBytes(), whole->GetPeakExtraMemoryInBytes());
    // A window of 2K + 4 + 3 slabs of planes deeper than half the image: the whole image.
    EXPECT_FALSE(RunOnTallImage(input, 1, 400, workUnits)->GetSweptInSlabs());
  }
}
