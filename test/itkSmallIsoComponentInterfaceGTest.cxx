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
// progress and abort.

#include "itkCommand.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"
#include <cmath>
#include <sstream>

namespace
{
using namespace itk::SmallIsoComponentTest;
using ImageType = itk::Image<uint8_t, 3>;
using FilterType = itk::SmallIsoComponentImageFilter<ImageType>;

/** 16^3 voxels of uniform noise: with σ = 128 and K = 20, thousands of small components. */
ImageType::Pointer
MakeSpeckledImage()
{
  RandomSource         random(12345);
  std::vector<uint8_t> values(16 * 16 * 16);
  for (uint8_t & v : values)
  {
    v = static_cast<uint8_t>(random.Bits() >> 24);
  }
  return MakeImage<uint8_t, 3>({ 16, 16, 16 }, values);
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
  auto filter = FilterType::New();
  EXPECT_EQ(filter->GetIsoValue(), 0.0);
  EXPECT_EQ(filter->GetMaximumComponentSize(), 20u);
  EXPECT_EQ(filter->GetMaximumComponentVolume(), 0.0);
  EXPECT_FALSE(filter->GetUseMaximumComponentVolume());
  EXPECT_EQ(filter->GetSide(), SideEnum::Both);
  EXPECT_FALSE(filter->GetFullyConnected());
  EXPECT_FALSE(filter->GetInPlace());
  EXPECT_EQ(filter->GetNumberOfIndexedOutputs(), 2u);
  EXPECT_NE(filter->GetRemovedMask(), nullptr);
  EXPECT_STREQ(filter->GetNameOfClass(), "SmallIsoComponentImageFilter");
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
  auto filter = FilterType::New();
  filter->SetIsoValue(12.25);
  filter->SetMaximumComponentVolume(7.5);
  filter->SetMaximumComponentSize(9);
  filter->SetSide(SideEnum::Below);
  filter->FullyConnectedOn();
  std::ostringstream printed;
  filter->Print(printed);
  const std::string text = printed.str();
  for (const char * expected : { "IsoValue: 12.25",
                                 "MaximumComponentSize: 9",
                                 "MaximumComponentVolume: 7.5",
                                 "UseMaximumComponentVolume: Off",
                                 "Side: itk::SmallIsoComponentEnums::Side::Below",
                                 "FullyConnected: On" })
  {
    EXPECT_NE(text.find(expected), std::string::npos) << "\"" << expected << "\" not in\n" << text;
  }
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
  auto               filter = FilterType::New();
  std::vector<float> progress;
  auto               observer = itk::CStyleCommand::New();
  observer->SetClientData(&progress);
  observer->SetCallback([](itk::Object * caller, const itk::EventObject &, void * clientData) {
    static_cast<std::vector<float> *>(clientData)->push_back(static_cast<FilterType *>(caller)->GetProgress());
  });
  filter->AddObserver(itk::ProgressEvent(), observer);
  filter->SetInput(MakeSpeckledImage());
  filter->SetIsoValue(128);
  filter->Update();
  ASSERT_GE(progress.size(), 3u);
  EXPECT_EQ(progress.back(), 1.0f);
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end())) << "progress went backwards";
}

TEST(SmallIsoComponentInterface, AbortOnFirstProgressEvent)
{
  auto filter = FilterType::New();
  auto observer = itk::CStyleCommand::New();
  observer->SetCallback([](itk::Object * caller, const itk::EventObject &, void *) {
    static_cast<FilterType *>(caller)->AbortGenerateDataOn();
  });
  const unsigned long tag = filter->AddObserver(itk::ProgressEvent(), observer);
  filter->SetInput(MakeSpeckledImage());
  filter->SetIsoValue(128);
  EXPECT_THROW(filter->Update(), itk::ProcessAborted);

  // Without the observer the next update runs to the end.
  filter->RemoveObserver(tag);
  filter->Modified();
  EXPECT_NO_THROW(filter->Update());
  EXPECT_EQ(filter->GetProgress(), 1.0f);
}
