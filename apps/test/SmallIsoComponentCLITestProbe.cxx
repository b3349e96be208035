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
// SmallIsoComponentCLITestProbe: the test suite's C++ helper. It makes small test images of
// every pixel type, reads headers and voxels back, and runs the filter directly (not through
// the tool) so that the tool's statistics can be checked against it.
//
//   make FILE TYPE DIMENSION   a test image (isovalue 50 gives specks and bubbles);
//                              TYPE uint8 ... float64, or rgb for a 3-component image
//   info FILE                  header as JSON: pixel_type, dimension, size, spacing, origin
//   count-nonzero FILE         number of nonzero voxels
//   equal FILE1 FILE2          exit 0 if the grids and all voxel values are the same
//   json-sample                awkward values written as the tools write JSON (NaN,
//                              infinities, doubles that need 17 digits, 64-bit integers,
//                              escapes, bytes that are not UTF-8)
//   reference FILE ISOVALUE K SIDE CONNECTIVITY
//                              the filter's statistics as JSON, K in voxels,
//                              SIDE above|below|both, CONNECTIVITY face|full
//   make-labels FILE TYPE DIMENSION SEED [SIZE...]
//                              a random label map (blocks of five labels, one of them
//                              TYPE's own, with noise); TYPE as for make, or uint64, int64;
//                              a SIZE per axis, or 23 x 19 x 13 (46 x 38 in 2-D)
//   label-reference FILE OUTPUT MASK SELECT BACKGROUND K KEEP CONNECTIVITY SIZES
//                              SmallIsoComponentLabelImageFilter run directly: writes its output
//                              and mask, prints its statistics as JSON; SELECT all|islands|
//                              holes|L,..., KEEP the N of keep-largest, SIZES L=K,... or -

#include "itkSmallIsoComponentImageFilter.h"
#include "itkSmallIsoComponentLabelImageFilter.h"
#include "sicImageFiles.h"
#include "sicScalarImageDispatch.h"
#include "sicSplitMix64.h"

#include "itkImageRegionConstIterator.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkRGBPixel.h"

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <vector>
#include <nlohmann/json.hpp>
#include <string>

namespace
{
using Json = nlohmann::ordered_json;

/** Prints \a document as the tools write their JSON. */
void
Print(const Json & document)
{
  std::cout << document.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
}

/** Background 10 with specks of 100 (1 to 3 voxels), a box of 100 with bubbles of 10. */
template <typename TImage>
void
MakeImage(const std::string & path)
{
  constexpr unsigned int       Dimension = TImage::ImageDimension;
  auto                         image = TImage::New();
  typename TImage::SizeType    size;
  typename TImage::SpacingType spacing;
  typename TImage::PointType   origin;
  const unsigned int           sizes[3] = { 24, 20, 16 };
  const double                 spacings[3] = { 0.5, 0.75, 2.0 };
  for (unsigned int axis = 0; axis < Dimension; ++axis)
  {
    size[axis] = sizes[axis];
    spacing[axis] = spacings[axis];
    origin[axis] = -3.0 + axis;
  }
  image->SetRegions(size);
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->Allocate();
  image->FillBuffer(10);
  itk::ImageRegionIteratorWithIndex<TImage> it(image, image->GetLargestPossibleRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    const auto & index = it.GetIndex();
    bool         inBox = true;
    for (unsigned int axis = 0; axis < Dimension; ++axis)
    {
      inBox = inBox && index[axis] >= 4 && index[axis] < static_cast<itk::IndexValueType>(sizes[axis]) - 4;
    }
    const itk::IndexValueType x = index[0];
    const itk::IndexValueType y = index[1];
    const bool                z = Dimension < 3 || index[Dimension - 1] % 4 == 2;
    if (inBox)
    {
      // Bubbles: single voxels and pairs inside the box.
      const bool bubble = z && ((x % 5 == 1 && y % 4 == 1) || (x % 5 == 2 && y % 4 == 1 && x < 12));
      it.Set(bubble ? 10 : 100);
    }
    else if (z && ((x == 1 && y % 3 == 0) || (x == 2 && y % 6 == 0)))
    {
      // Specks: single voxels and pairs along the border.
      it.Set(100);
    }
  }
  sic::WriteImage(image.GetPointer(), path, path, "test image", nullptr);
}

void
MakeRgbImage(const std::string & path)
{
  using ImageType = itk::Image<itk::RGBPixel<unsigned char>, 2>;
  auto image = ImageType::New();
  image->SetRegions(ImageType::SizeType{ { 8, 8 } });
  image->Allocate();
  itk::RGBPixel<unsigned char> gray;
  gray.Fill(100);
  image->FillBuffer(gray);
  sic::WriteImage(image.GetPointer(), path, path, "test image", nullptr);
}

template <typename TImage>
int
CountNonzero(const std::string & path)
{
  const auto    image = sic::ReadImage<TImage>(path, "image", nullptr);
  std::uint64_t count = 0;
  for (itk::ImageRegionConstIterator<TImage> it(image, image->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    count += it.Get() != 0;
  }
  std::cout << count << std::endl;
  return 0;
}

template <typename TImage>
int
Equal(const std::string & first, const std::string & second)
{
  const auto a = sic::ReadImage<TImage>(first, "image", nullptr);
  const auto b = sic::ReadImage<TImage>(second, "image", nullptr);
  if (a->GetLargestPossibleRegion() != b->GetLargestPossibleRegion() || a->GetSpacing() != b->GetSpacing() ||
      a->GetOrigin() != b->GetOrigin())
  {
    std::cout << "different grids" << std::endl;
    return 1;
  }
  // The index of a difference is reported, so the first image's iterator keeps it.
  itk::ImageRegionConstIteratorWithIndex<TImage> itA(a, a->GetLargestPossibleRegion());
  itk::ImageRegionConstIterator<TImage>          itB(b, b->GetLargestPossibleRegion());
  for (; !itA.IsAtEnd(); ++itA, ++itB)
  {
    const double va = static_cast<double>(itA.Get());
    const double vb = static_cast<double>(itB.Get());
    if (va != vb && !(std::isnan(va) && std::isnan(vb)))
    {
      std::cout << "different at " << itA.GetIndex() << ": " << va << " vs " << vb << std::endl;
      return 1;
    }
  }
  std::cout << "equal" << std::endl;
  return 0;
}

template <typename TImage>
int
Reference(const std::string & path, double isoValue, itk::SizeValueType k, const std::string & side, bool full)
{
  using FilterType = itk::SmallIsoComponentImageFilter<TImage>;
  using SideEnum = itk::SmallIsoComponentEnums::Side;
  auto filter = FilterType::New();
  filter->SetInput(sic::ReadImage<TImage>(path, "image", nullptr));
  filter->SetIsoValue(isoValue);
  filter->SetMaximumComponentSize(k);
  filter->SetSide(side == "above" ? SideEnum::Above : side == "below" ? SideEnum::Below : SideEnum::Both);
  filter->SetFullyConnected(full);
  filter->Update();

  Json document;
  for (const SideEnum s : { SideEnum::Above, SideEnum::Below })
  {
    Json histogram = Json::array();
    for (const auto & [size, count] : filter->GetComponentSizeHistogram(s))
    {
      histogram.push_back({ static_cast<std::uint64_t>(size), static_cast<std::uint64_t>(count) });
    }
    document[s == SideEnum::Above ? "above" : "below"] = {
      { "components", static_cast<std::uint64_t>(filter->GetNumberOfComponents(s)) },
      { "removed_components", static_cast<std::uint64_t>(filter->GetNumberOfRemovedComponents(s)) },
      { "removed_voxels", static_cast<std::uint64_t>(filter->GetNumberOfRemovedVoxels(s)) },
      { "size_histogram", std::move(histogram) }
    };
  }
  document["modified_voxels"] = static_cast<std::uint64_t>(filter->GetNumberOfModifiedVoxels());
  document["unrepairable_voxels"] = static_cast<std::uint64_t>(filter->GetNumberOfUnrepairableVoxels());
  document["effective_max_size"] = static_cast<std::uint64_t>(filter->GetEffectiveMaximumComponentSize());
  Print(document);
  return 0;
}

/** A label of the probe's command line. */
template <typename TLabel>
TLabel
LabelNamed(const std::string & text)
{
  if constexpr (std::is_floating_point_v<TLabel>)
  {
    return static_cast<TLabel>(std::stod(text));
  }
  else if constexpr (std::is_signed_v<TLabel>)
  {
    return static_cast<TLabel>(std::stoll(text));
  }
  else
  {
    return static_cast<TLabel>(std::stoull(text));
  }
}

/** Blocks of 3 voxels along each axis of five labels (0, 1, 2, 5 and one only TLabel holds), then one voxel in six set
 * to a random label: components of every size, islands and holes. \a extent gives the size, or is empty for 23 x 19 x
 * 13 voxels (46 x 38 in 2-D). */
template <typename TImage>
void
MakeLabels(const std::string & path, std::uint64_t seed, const std::vector<std::uint64_t> & extent)
{
  using LabelType = typename TImage::PixelType;
  constexpr unsigned int Dimension = TImage::ImageDimension;
  std::vector<LabelType> labels = { 0, 1, 2, 5 };
  if constexpr (std::is_floating_point_v<LabelType>)
  {
    labels.push_back(-12);
  }
  else if constexpr (std::is_signed_v<LabelType>)
  {
    labels.push_back(static_cast<LabelType>(sizeof(LabelType) == 1   ? -100
                                            : sizeof(LabelType) == 2 ? -3000
                                            : sizeof(LabelType) == 4 ? -70000
                                                                     : -1099511627776LL));
  }
  else
  {
    labels.push_back(std::numeric_limits<LabelType>::max());
  }
  auto                      image = TImage::New();
  typename TImage::SizeType size;
  const unsigned int        sizes[3] = { 23, 19, 13 };
  for (unsigned int axis = 0; axis < Dimension; ++axis)
  {
    size[axis] = !extent.empty() ? extent[axis] : Dimension == 2 ? 2 * sizes[axis] : sizes[axis];
  }
  image->SetRegions(size);
  image->Allocate();
  sic::SplitMix64                    random(seed);
  std::map<std::uint64_t, LabelType> blocks;
  for (itk::ImageRegionIteratorWithIndex<TImage> it(image, image->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    std::uint64_t block = 0;
    for (unsigned int axis = 0; axis < Dimension; ++axis)
    {
      block = block * 4096 + static_cast<std::uint64_t>(it.GetIndex()[axis] / 3);
    }
    if (blocks.count(block) == 0)
    {
      blocks[block] = labels[random.Next() % labels.size()];
    }
    it.Set(random.Next() % 6 == 0 ? labels[random.Next() % labels.size()] : blocks[block]);
  }
  sic::WriteImage(image.GetPointer(), path, path, "test image", nullptr);
}

template <typename TImage>
int
LabelReference(char * argv[])
{
  using FilterType = itk::SmallIsoComponentLabelImageFilter<TImage>;
  using LabelType = typename TImage::PixelType;
  using Selection = itk::SmallIsoComponentLabelEnums::Selection;
  auto              filter = FilterType::New();
  const std::string select = argv[5];
  filter->SetSelection(select == "all"       ? Selection::All
                       : select == "islands" ? Selection::Islands
                       : select == "holes"   ? Selection::Holes
                                             : Selection::Listed);
  std::vector<LabelType> listed;
  std::istringstream     items(select);
  for (std::string item; filter->GetSelection() == Selection::Listed && std::getline(items, item, ',');)
  {
    listed.push_back(LabelNamed<LabelType>(item));
  }
  filter->SetSelectedLabels(listed);
  filter->SetBackgroundValue(LabelNamed<LabelType>(argv[6]));
  filter->SetMaximumComponentSize(std::stoull(argv[7]));
  filter->SetKeepLargestComponents(std::stoull(argv[8]));
  filter->SetFullyConnected(std::string(argv[9]) == "full");
  typename FilterType::LabelSizeMapType sizes;
  std::istringstream                    pairs(std::string(argv[10]) == "-" ? "" : argv[10]);
  for (std::string pair; std::getline(pairs, pair, ',');)
  {
    sizes[LabelNamed<LabelType>(pair.substr(0, pair.find('=')))] = std::stoull(pair.substr(pair.find('=') + 1));
  }
  filter->SetMaximumComponentSizes(sizes);
  filter->GenerateRemovedMaskOn();
  filter->SetInput(sic::ReadImage<TImage>(argv[2], "image", nullptr));
  filter->Update();
  sic::WriteImage(filter->GetOutput(), argv[3], argv[3], "output", nullptr);
  sic::WriteImage(filter->GetRemovedMask(), argv[4], argv[4], "mask", nullptr);

  Json labels = Json::object();
  for (const auto & [label, statistics] : filter->GetLabelStatistics())
  {
    Json histogram = Json::array();
    for (const auto & [size, count] : statistics.Histogram)
    {
      histogram.push_back({ static_cast<std::uint64_t>(size), static_cast<std::uint64_t>(count) });
    }
    std::ostringstream key;
    key << std::fixed << std::setprecision(0) << static_cast<long double>(label) + 0.0L;
    labels[key.str()] = { { "components", static_cast<std::uint64_t>(statistics.Components) },
                          { "removed_components", static_cast<std::uint64_t>(statistics.RemovedComponents) },
                          { "removed_voxels", static_cast<std::uint64_t>(statistics.RemovedVoxels) },
                          { "gained_voxels", static_cast<std::uint64_t>(statistics.GainedVoxels) },
                          { "size_histogram", std::move(histogram) } };
  }
  Print({ { "labels", std::move(labels) },
          { "modified_voxels", static_cast<std::uint64_t>(filter->GetNumberOfModifiedVoxels()) },
          { "unrepairable_voxels", static_cast<std::uint64_t>(filter->GetNumberOfUnrepairableVoxels()) },
          { "effective_max_size", static_cast<std::uint64_t>(filter->GetEffectiveMaximumComponentSize()) } });
  return 0;
}

itk::IOComponentEnum
ComponentTypeNamed(const std::string & name)
{
  for (const auto type : { itk::IOComponentEnum::UCHAR,
                           itk::IOComponentEnum::CHAR,
                           itk::IOComponentEnum::USHORT,
                           itk::IOComponentEnum::SHORT,
                           itk::IOComponentEnum::UINT,
                           itk::IOComponentEnum::INT,
                           itk::IOComponentEnum::FLOAT,
                           itk::IOComponentEnum::DOUBLE,
                           itk::IOComponentEnum::ULONGLONG,
                           itk::IOComponentEnum::LONGLONG })
  {
    if (sic::PixelTypeName(type) == name)
    {
      return type;
    }
  }
  throw sic::ToolError("unknown pixel type " + name);
}

int
Probe(int argc, char * argv[])
{
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "make" && argc == 5 && std::string(argv[3]) == "rgb")
  {
    MakeRgbImage(argv[2]);
    return 0;
  }
  if (command == "make" && argc == 5)
  {
    sic::ScalarImageInfo info;
    info.ComponentType = ComponentTypeNamed(argv[3]);
    info.Dimension = static_cast<unsigned int>(std::stoul(argv[4]));
    sic::DispatchLabelImage(info, [&](auto tag) {
      MakeImage<typename decltype(tag)::ImageType>(argv[2]);
      return 0;
    });
    return 0;
  }
  if (command == "info" && argc == 3)
  {
    const sic::ScalarImageInfo info = sic::ReadLabelImageInfo(argv[2], "image");
    Print({ { "pixel_type", sic::PixelTypeName(info.ComponentType) },
            { "dimension", info.Dimension },
            { "size", info.Size },
            { "spacing", info.Spacing },
            { "origin", info.Origin } });
    return 0;
  }
  if (command == "count-nonzero" && argc == 3)
  {
    return sic::DispatchLabelImage(sic::ReadLabelImageInfo(argv[2], "image"),
                                   [&](auto tag) { return CountNonzero<typename decltype(tag)::ImageType>(argv[2]); });
  }
  if (command == "equal" && argc == 4)
  {
    return sic::DispatchLabelImage(sic::ReadLabelImageInfo(argv[2], "image"), [&](auto tag) {
      return Equal<typename decltype(tag)::ImageType>(argv[2], argv[3]);
    });
  }
  if (command == "json-sample" && argc == 2)
  {
    Print({ { "nan", std::nan("") },
            { "infinities", { HUGE_VAL, -HUGE_VAL } },
            { "doubles", { 0.1, 1.0 / 3.0, 2.0 / 3.0 * 1e300, 5e-324, -0.0, 150.0, 0.6400000000000001 } },
            { "integers", { std::numeric_limits<std::uint64_t>::max(), std::numeric_limits<std::int64_t>::min() } },
            { "text \"quoted\"", "back\\slash, tab\t, newline\n, bell\a, mm³" },
            { "not UTF-8", "a\xff\xfe b" },
            { "nested", Json::array({ { 1u, 2u }, { { "empty", Json::array() } } }) } });
    return 0;
  }
  if (command == "reference" && argc == 7)
  {
    const std::string file = argv[2];
    return sic::DispatchScalarImage(sic::ReadScalarImageInfo(file, "image"), [&](auto tag) {
      return Reference<typename decltype(tag)::ImageType>(
        file, std::stod(argv[3]), std::stoul(argv[4]), argv[5], std::string(argv[6]) == "full");
    });
  }
  if (command == "make-labels" && (argc == 6 || argc == 6 + std::atoi(argv[4])))
  {
    sic::ScalarImageInfo info;
    info.ComponentType = ComponentTypeNamed(argv[3]);
    info.Dimension = static_cast<unsigned int>(std::stoul(argv[4]));
    std::vector<std::uint64_t> extent;
    for (int i = 6; i < argc; ++i)
    {
      extent.push_back(std::stoull(argv[i]));
    }
    return sic::DispatchLabelImage(info, [&](auto tag) {
      MakeLabels<typename decltype(tag)::ImageType>(argv[2], std::stoull(argv[5]), extent);
      return 0;
    });
  }
  if (command == "label-reference" && argc == 11)
  {
    return sic::DispatchLabelImage(sic::ReadLabelImageInfo(argv[2], "image"),
                                   [&](auto tag) { return LabelReference<typename decltype(tag)::ImageType>(argv); });
  }
  std::cerr << "usage: see the comment at the top of SmallIsoComponentCLITestProbe.cxx" << std::endl;
  return 2;
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    return Probe(argc, argv);
  }
  catch (const std::exception & error)
  {
    std::cerr << "SmallIsoComponentCLITestProbe: " << error.what() << std::endl;
    return 2;
  }
}
