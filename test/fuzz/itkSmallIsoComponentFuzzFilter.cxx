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

// libFuzzer target: the filter on a small volume made from the fuzzer's bytes (dimension, extents, pixel type,
// parameters, then the voxels), checked against the brute-force reference with 1 and 3 work units; any difference
// aborts, which libFuzzer records as a crash with its input.

#include "itkSmallIsoComponentTestUtilities.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>

namespace
{
using namespace itk::SmallIsoComponentTest;

/** The fuzzer's bytes, read front to back; zeros once they run out. */
class ByteSource
{
public:
  ByteSource(const std::uint8_t * data, size_t size)
    : m_Data(data)
    , m_Size(size)
  {}

  std::uint8_t
  Next()
  {
    return m_Position < m_Size ? m_Data[m_Position++] : 0;
  }

  template <typename T>
  T
  Value()
  {
    std::uint8_t bytes[sizeof(T)];
    for (std::uint8_t & byte : bytes)
    {
      byte = Next();
    }
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

private:
  const std::uint8_t * m_Data;
  size_t               m_Size;
  size_t               m_Position{ 0 };
};

template <typename TPixel, unsigned int VDimension>
void
Check(ByteSource & bytes)
{
  using ImageType = itk::Image<TPixel, VDimension>;
  typename ImageType::SizeType size;
  for (unsigned int axis = 0; axis < VDimension; ++axis)
  {
    // Extents 1 to 8 (to 16 in 2-D): small enough for the reference, large enough for every kind of component.
    size[axis] = 1 + bytes.Next() % (VDimension == 2 ? 16 : 8);
  }
  const std::uint8_t choices = bytes.Next();
  Parameters         settings;
  settings.Side = static_cast<SideEnum>(choices % 3);
  settings.FullyConnected = (choices & 4) != 0;
  settings.MaximumComponentSize = bytes.Next() % 32;
  // Integer isovalues tie with the voxels, half-integers fall between them.
  settings.IsoValue = bytes.Value<std::int8_t>() / 2.0;

  auto image = ImageType::New();
  image->SetRegions(size);
  image->Allocate();
  TPixel * const voxels = image->GetBufferPointer();
  const size_t   count = image->GetBufferedRegion().GetNumberOfPixels();
  for (size_t v = 0; v < count; ++v)
  {
    // Few distinct values, so that components form and samples tie with the isovalue.
    voxels[v] = static_cast<TPixel>(static_cast<std::int8_t>(bytes.Next()) / 16);
  }

  const auto expected = Reference::Run<TPixel>(image.GetPointer(), settings);
  for (const unsigned int workUnits : { 1u, 3u })
  {
    const auto        filter = RunFilter<ImageType, ImageType>(image, settings, workUnits);
    const std::string differences =
      DifferencesFromReference(filter.GetPointer(), expected, settings.MaximumComponentSize);
    if (!differences.empty())
    {
      std::cerr << "the filter differs from the reference with " << workUnits << " work units:" << differences
                << std::endl;
      std::abort();
    }
  }
}

template <typename TPixel>
void
CheckDimension(ByteSource & bytes, bool threeD)
{
  if (threeD)
  {
    Check<TPixel, 3>(bytes);
  }
  else
  {
    Check<TPixel, 2>(bytes);
  }
}
} // namespace

extern "C" int
LLVMFuzzerTestOneInput(const std::uint8_t * data, size_t size)
{
  ByteSource         bytes(data, size);
  const std::uint8_t kind = bytes.Next();
  const bool         threeD = (kind & 1) != 0;
  switch ((kind >> 1) % 4)
  {
    case 0:
      CheckDimension<std::uint8_t>(bytes, threeD);
      break;
    case 1:
      CheckDimension<std::int16_t>(bytes, threeD);
      break;
    case 2:
      CheckDimension<float>(bytes, threeD);
      break;
    default:
      CheckDimension<double>(bytes, threeD);
      break;
  }
  return 0;
}
