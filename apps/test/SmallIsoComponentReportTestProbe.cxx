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
// A helper of SmallIsoComponentReportTest.py: it makes random test volumes and computes, by
// brute force and with none of the report tool's counting code, what the report must say.
//
//   random FILE TYPE DIMENSION SEED
//       a random volume of small random extents, values 0 to 9 (float types: some NaN);
//       TYPE uint8, int16, float32 or float64, DIMENSION 2 or 3
//   reference FILE CONNECTIVITY SIZES ISOVALUE...
//       the report as JSON (the tool's --format json), CONNECTIVITY face|full, SIZES a
//       comma-separated list; components by flood fill, active cubes by testing every
//       corner of every cell

#include "itkSmallIsoComponentReference.h"
#include "sicImageFiles.h"
#include "sicReportTable.h"
#include "sicScalarImageDispatch.h"
#include "sicSplitMix64.h"

#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIterator.h"

#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>

namespace
{
template <typename TImage>
int
MakeRandomImage(const std::string & path, std::uint64_t seed)
{
  using PixelType = typename TImage::PixelType;
  constexpr unsigned int    Dimension = TImage::ImageDimension;
  sic::SplitMix64           random(seed);
  typename TImage::SizeType size;
  for (unsigned int axis = 0; axis < Dimension; ++axis)
  {
    size[axis] = Dimension == 2 ? 1 + random.Next() % 30 : 1 + random.Next() % 12;
  }
  auto image = TImage::New();
  image->SetRegions(size);
  image->Allocate();
  // A few values per image so that components of every size occur.
  const std::uint64_t levels = 2 + random.Next() % 8;
  for (itk::ImageRegionIterator<TImage> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    const bool nan = std::numeric_limits<PixelType>::has_quiet_NaN && random.Next() % 20 == 0;
    it.Set(nan ? std::numeric_limits<PixelType>::quiet_NaN() : static_cast<PixelType>(random.Next() % levels));
  }
  sic::WriteImage(image.GetPointer(), path, path, "test image", nullptr);
  return 0;
}

/** The number of cells with a corner >= isoValue and a corner < isoValue (NaN: below). */
template <typename TImage>
std::uint64_t
CountActiveCells(const TImage * image, double isoValue)
{
  constexpr unsigned int      Dimension = TImage::ImageDimension;
  const auto                  size = image->GetBufferedRegion().GetSize();
  typename TImage::RegionType cells;
  typename TImage::SizeType   cellSize;
  for (unsigned int axis = 0; axis < Dimension; ++axis)
  {
    if (size[axis] < 2)
    {
      return 0;
    }
    cellSize[axis] = size[axis] - 1;
  }
  cells.SetSize(cellSize);
  std::uint64_t active = 0;
  for (itk::ImageRegionConstIteratorWithIndex<TImage> it(image, cells); !it.IsAtEnd(); ++it)
  {
    bool anyAbove = false;
    bool anyBelow = false;
    for (unsigned int corner = 0; corner < (1u << Dimension); ++corner)
    {
      auto index = it.GetIndex();
      for (unsigned int axis = 0; axis < Dimension; ++axis)
      {
        index[axis] += (corner >> axis) & 1;
      }
      const bool above = itk::SmallIsoComponentReference::IsAbove(image->GetPixel(index), isoValue);
      anyAbove = anyAbove || above;
      anyBelow = anyBelow || !above;
    }
    active += anyAbove && anyBelow ? 1 : 0;
  }
  return active;
}

sic::SideRow
RemovalCounts(const itk::SmallIsoComponentReference::SideStatistics & side, const std::vector<std::uint64_t> & sizes)
{
  sic::SideRow row;
  row.Components = side.Components;
  for (const std::uint64_t k : sizes)
  {
    std::uint64_t components = 0;
    std::uint64_t voxels = 0;
    for (const auto & [size, count] : side.Histogram)
    {
      if (size <= k)
      {
        components += count;
        voxels += size * count;
      }
    }
    row.RemovedComponents.push_back(components);
    row.ModifiedVoxels.push_back(voxels);
  }
  return row;
}

template <typename TImage>
int
WriteReference(const std::string &                path,
               bool                               fullyConnected,
               const std::vector<std::uint64_t> & sizes,
               const std::vector<double> &        isoValues)
{
  const auto  image = sic::ReadImage<TImage>(path, "test image", nullptr);
  sic::Report report;
  report.Input = path;
  for (const auto extent : image->GetBufferedRegion().GetSize())
  {
    report.Size.push_back(extent);
  }
  report.FullyConnected = fullyConnected;
  report.MaximumSizes = sizes;
  for (const double isoValue : isoValues)
  {
    const auto counts = itk::SmallIsoComponentReference::CountComponents(image.GetPointer(), isoValue, fullyConnected);
    sic::ReportRow row;
    row.IsoValue = isoValue;
    row.ActiveCubes = CountActiveCells(image.GetPointer(), isoValue);
    row.Above = RemovalCounts(counts.Above, sizes);
    row.Below = RemovalCounts(counts.Below, sizes);
    report.Rows.push_back(row);
  }
  sic::WriteReportJson(std::cout, report);
  return 0;
}

itk::IOComponentEnum
ComponentTypeNamed(const std::string & name)
{
  if (name == "uint8")
  {
    return itk::IOComponentEnum::UCHAR;
  }
  if (name == "int16")
  {
    return itk::IOComponentEnum::SHORT;
  }
  if (name == "float32")
  {
    return itk::IOComponentEnum::FLOAT;
  }
  if (name == "float64")
  {
    return itk::IOComponentEnum::DOUBLE;
  }
  throw std::invalid_argument("unknown pixel type " + name);
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    const std::string command = argc > 1 ? argv[1] : "";
    if (command == "random" && argc == 6)
    {
      sic::ScalarImageInfo info;
      info.ComponentType = ComponentTypeNamed(argv[3]);
      info.Dimension = static_cast<unsigned int>(std::stoul(argv[4]));
      const std::uint64_t seed = std::stoull(argv[5]);
      return sic::DispatchScalarImage(
        info, [&](auto tag) { return MakeRandomImage<typename decltype(tag)::ImageType>(argv[2], seed); });
    }
    if (command == "reference" && argc >= 6)
    {
      const sic::ScalarImageInfo info = sic::ReadScalarImageInfo(argv[2], "test image");
      std::vector<std::uint64_t> sizes;
      std::istringstream         list(argv[4]);
      for (std::string item; std::getline(list, item, ',');)
      {
        sizes.push_back(std::stoull(item));
      }
      std::vector<double> isoValues;
      for (int i = 5; i < argc; ++i)
      {
        isoValues.push_back(std::stod(argv[i]));
      }
      return sic::DispatchScalarImage(info, [&](auto tag) {
        return WriteReference<typename decltype(tag)::ImageType>(
          argv[2], std::string(argv[3]) == "full", sizes, isoValues);
      });
    }
    std::cerr << "usage: see the comment at the top of SmallIsoComponentReportTestProbe.cxx" << std::endl;
    return 2;
  }
  catch (const std::exception & error)
  {
    std::cerr << "SmallIsoComponentReportTestProbe: " << error.what() << std::endl;
    return 1;
  }
}
