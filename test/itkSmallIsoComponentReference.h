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
#ifndef itkSmallIsoComponentReference_h
#define itkSmallIsoComponentReference_h

#include "itkImage.h"
#include "itkSmallIsoComponentEnums.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <type_traits>
#include <vector>

namespace itk
{
/** A brute-force implementation of SmallIsoComponentImageFilter's semantics, written to
 * be obviously right rather than fast, for the tests to compare the filter with.
 *
 * It shares no code with the filter: components are found by a flood fill over single
 * voxels (an explicit stack of linear indices, every neighbour of the chosen connectivity
 * checked one by one), and every repair value by walking voxel by voxel. Each pass
 * relabels the image it is given, so Side Both really runs the below pass on the image
 * the above pass produced.
 *
 * Integer pixel types of at most 32 bits and floating-point types are supported (the
 * repair mean is rounded with std::floor(mean + 0.5), which is exact for those). */
namespace SmallIsoComponentReference
{
using HistogramType = std::map<SizeValueType, SizeValueType>;
using SideEnum = SmallIsoComponentEnums::Side;

/** Marks a voxel that belongs to no component of the side being labelled. */
constexpr SizeValueType NoComponent = std::numeric_limits<SizeValueType>::max();

struct SideStatistics
{
  SizeValueType Components{ 0 };
  SizeValueType RemovedComponents{ 0 };
  SizeValueType RemovedVoxels{ 0 };
  HistogramType Histogram;
};

struct Parameters
{
  double        IsoValue{ 0.0 };
  SizeValueType MaximumComponentSize{ 20 };
  SideEnum      Side{ SideEnum::Both };
  bool          FullyConnected{ false };
};

template <typename TPixel>
struct Result
{
  std::vector<TPixel>  Output;
  std::vector<uint8_t> Mask;
  SideStatistics       Above;
  SideStatistics       Below;
  SizeValueType        ModifiedVoxels{ 0 };
  SizeValueType        UnrepairableVoxels{ 0 };
  /** The part of UnrepairableVoxels that got the fallback value (every walk left the image). */
  SizeValueType FallbackVoxels{ 0 };
};

/** A voxel grid of VDimension axes, axis 0 varying fastest (ITK's buffer order). */
template <unsigned int VDimension>
class Grid
{
public:
  using SizeType = std::array<SizeValueType, VDimension>;
  using CoordinatesType = std::array<OffsetValueType, VDimension>;
  using OffsetType = std::array<int, VDimension>;

  Grid(const SizeType & size, bool fullyConnected)
    : m_Size(size)
  {
    // Every offset in {-1, 0, 1}^N except 0; face connectivity keeps those along one axis.
    SizeValueType combinations = 1;
    for (unsigned int a = 0; a < VDimension; ++a)
    {
      combinations *= 3;
    }
    for (SizeValueType code = 0; code < combinations; ++code)
    {
      OffsetType    offset;
      SizeValueType rest = code;
      unsigned int  nonZero = 0;
      for (unsigned int a = 0; a < VDimension; ++a)
      {
        offset[a] = static_cast<int>(rest % 3) - 1;
        rest /= 3;
        nonZero += offset[a] != 0 ? 1 : 0;
      }
      if (nonZero == 1 || (nonZero > 1 && fullyConnected))
      {
        m_Neighborhood.push_back(offset);
      }
    }
  }

  SizeValueType
  NumberOfVoxels() const
  {
    SizeValueType n = 1;
    for (unsigned int a = 0; a < VDimension; ++a)
    {
      n *= m_Size[a];
    }
    return n;
  }

  const SizeType &
  Size() const
  {
    return m_Size;
  }

  CoordinatesType
  Coordinates(SizeValueType linear) const
  {
    CoordinatesType c;
    for (unsigned int a = 0; a < VDimension; ++a)
    {
      c[a] = static_cast<OffsetValueType>(linear % m_Size[a]);
      linear /= m_Size[a];
    }
    return c;
  }

  bool
  Inside(const CoordinatesType & c) const
  {
    for (unsigned int a = 0; a < VDimension; ++a)
    {
      if (c[a] < 0 || c[a] >= static_cast<OffsetValueType>(m_Size[a]))
      {
        return false;
      }
    }
    return true;
  }

  SizeValueType
  Linear(const CoordinatesType & c) const
  {
    SizeValueType linear = 0;
    for (unsigned int a = VDimension; a-- > 0;)
    {
      linear = linear * m_Size[a] + static_cast<SizeValueType>(c[a]);
    }
    return linear;
  }

  const std::vector<OffsetType> &
  Neighborhood() const
  {
    return m_Neighborhood;
  }

private:
  SizeType                m_Size;
  std::vector<OffsetType> m_Neighborhood;
};

/** The classification every test shares: above iff value >= σ, compared as double. A NaN
 * compares false, so it is below. */
template <typename TPixel>
bool
IsAbove(TPixel value, double isoValue)
{
  return static_cast<double>(value) >= isoValue;
}

template <typename TPixel>
bool
IsNaN(TPixel value)
{
  return value != value;
}

/** The largest value of TPixel that is below σ; false when there is none. */
template <typename TPixel>
bool
LargestValueBelow(double isoValue, TPixel & value)
{
  using Limits = std::numeric_limits<TPixel>;
  if constexpr (std::is_integral<TPixel>::value)
  {
    if (static_cast<double>(Limits::max()) < isoValue)
    {
      value = Limits::max();
      return true;
    }
    if (!(static_cast<double>(Limits::lowest()) < isoValue))
    {
      return false;
    }
    value = static_cast<TPixel>(std::ceil(isoValue) - 1.0);
    return true;
  }
  else
  {
    if (isoValue > static_cast<double>(Limits::max()))
    {
      value = Limits::max();
      return true;
    }
    if (isoValue < static_cast<double>(Limits::lowest()))
    {
      value = -Limits::infinity();
      return isoValue > -std::numeric_limits<double>::infinity();
    }
    value = static_cast<TPixel>(isoValue);
    while (!(static_cast<double>(value) < isoValue))
    {
      value = std::nextafter(value, -Limits::infinity());
    }
    while (static_cast<double>(std::nextafter(value, Limits::infinity())) < isoValue)
    {
      value = std::nextafter(value, Limits::infinity());
    }
    return true;
  }
}

/** The smallest value of TPixel that is not below σ; false when there is none. */
template <typename TPixel>
bool
SmallestValueNotBelow(double isoValue, TPixel & value)
{
  using Limits = std::numeric_limits<TPixel>;
  if constexpr (std::is_integral<TPixel>::value)
  {
    if (isoValue <= static_cast<double>(Limits::lowest()))
    {
      value = Limits::lowest();
      return true;
    }
    if (isoValue > static_cast<double>(Limits::max()))
    {
      return false;
    }
    value = static_cast<TPixel>(std::ceil(isoValue));
    return true;
  }
  else
  {
    if (isoValue > static_cast<double>(Limits::max()))
    {
      value = Limits::infinity();
      return true;
    }
    if (isoValue < static_cast<double>(Limits::lowest()))
    {
      value = isoValue == -std::numeric_limits<double>::infinity() ? -Limits::infinity() : Limits::lowest();
      return true;
    }
    value = static_cast<TPixel>(isoValue);
    while (static_cast<double>(value) < isoValue)
    {
      value = std::nextafter(value, Limits::infinity());
    }
    while (static_cast<double>(std::nextafter(value, -Limits::infinity())) >= isoValue)
    {
      value = std::nextafter(value, -Limits::infinity());
    }
    return true;
  }
}

/** The mean as a pixel: rounded half up for integers, plainly converted for floats. */
template <typename TPixel>
TPixel
MeanAsPixel(double mean)
{
  if constexpr (std::is_integral<TPixel>::value)
  {
    return static_cast<TPixel>(static_cast<int64_t>(std::floor(mean + 0.5)));
  }
  else
  {
    return static_cast<TPixel>(mean);
  }
}

/** Labels the voxels with member[v] != 0 by flood fill; other voxels get NoComponent.
 * componentSizes receives the number of voxels of each component. */
template <unsigned int VDimension>
std::vector<SizeValueType>
LabelComponents(const Grid<VDimension> &     grid,
                const std::vector<uint8_t> & member,
                std::vector<SizeValueType> & componentSizes)
{
  const SizeValueType        n = grid.NumberOfVoxels();
  std::vector<SizeValueType> label(n, NoComponent);
  std::vector<SizeValueType> stack;
  componentSizes.clear();
  for (SizeValueType seed = 0; seed < n; ++seed)
  {
    if (!member[seed] || label[seed] != NoComponent)
    {
      continue;
    }
    const SizeValueType component = componentSizes.size();
    componentSizes.push_back(0);
    label[seed] = component;
    stack.push_back(seed);
    while (!stack.empty())
    {
      const SizeValueType v = stack.back();
      stack.pop_back();
      ++componentSizes[component];
      const auto c = grid.Coordinates(v);
      for (const auto & offset : grid.Neighborhood())
      {
        auto neighbor = c;
        for (unsigned int a = 0; a < VDimension; ++a)
        {
          neighbor[a] += offset[a];
        }
        if (!grid.Inside(neighbor))
        {
          continue;
        }
        const SizeValueType u = grid.Linear(neighbor);
        if (member[u] && label[u] == NoComponent)
        {
          label[u] = component;
          stack.push_back(u);
        }
      }
    }
  }
  return label;
}

/** The components of one side of an image: their count, histogram, and the label of
 * every voxel (NoComponent on the other side). */
template <typename TPixel, unsigned int VDimension>
SideStatistics
LabelSide(const Grid<VDimension> &     grid,
          const std::vector<TPixel> &  image,
          double                       isoValue,
          bool                         above,
          std::vector<SizeValueType> & label,
          std::vector<SizeValueType> & componentSizes)
{
  std::vector<uint8_t> member(image.size());
  for (SizeValueType v = 0; v < image.size(); ++v)
  {
    member[v] = IsAbove(image[v], isoValue) == above ? 1 : 0;
  }
  label = LabelComponents(grid, member, componentSizes);
  SideStatistics statistics;
  statistics.Components = componentSizes.size();
  for (const SizeValueType size : componentSizes)
  {
    ++statistics.Histogram[size];
  }
  return statistics;
}

/** The repair value of voxel v of a removed component: the mean of the first values on
 * the other side met along each axis direction, read from \a before. Returns false when
 * no direction finds a value. */
template <typename TPixel, unsigned int VDimension>
bool
RepairValue(const Grid<VDimension> &    grid,
            const std::vector<TPixel> & before,
            double                      isoValue,
            bool                        removedAreAbove,
            SizeValueType               v,
            TPixel &                    value)
{
  std::vector<double> found;
  for (unsigned int axis = 0; axis < VDimension; ++axis)
  {
    for (const int direction : { -1, 1 })
    {
      auto c = grid.Coordinates(v);
      while (true)
      {
        c[axis] += direction;
        if (!grid.Inside(c))
        {
          break;
        }
        const TPixel u = before[grid.Linear(c)];
        if (IsAbove(u, isoValue) != removedAreAbove)
        {
          if (!IsNaN(u))
          {
            found.push_back(static_cast<double>(u));
          }
          break;
        }
      }
    }
  }
  if (found.empty())
  {
    return false;
  }
  const auto count = static_cast<double>(found.size());
  double     sum = 0.0;
  bool       infinite = false;
  for (const double u : found)
  {
    sum += u;
    infinite = infinite || std::isinf(u);
  }
  double mean = sum / count;
  if (std::isinf(sum) && !infinite)
  {
    // The sum of finite doubles overflowed: the mean of the values divided by 16, times 16,
    // within the finite doubles.
    double scaled = 0.0;
    for (const double u : found)
    {
      scaled += u / 16.0;
    }
    mean = std::clamp(scaled / count * 16.0, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
  }
  value = MeanAsPixel<TPixel>(mean);
  return true;
}

/** One removal pass on \a image: labels the side \a removeAbove, records the side's
 * statistics, and when \a active removes its components of at most K voxels. */
template <typename TPixel, unsigned int VDimension>
void
RemovalPass(const Grid<VDimension> & grid,
            const Parameters &       parameters,
            bool                     removeAbove,
            bool                     active,
            uint8_t                  maskValue,
            std::vector<TPixel> &    image,
            std::vector<uint8_t> &   mask,
            SideStatistics &         statistics,
            SizeValueType &          unrepairable,
            SizeValueType &          fallbacks)
{
  std::vector<SizeValueType> label;
  std::vector<SizeValueType> componentSizes;
  statistics = LabelSide(grid, image, parameters.IsoValue, removeAbove, label, componentSizes);
  if (!active)
  {
    return;
  }
  TPixel               fallback{};
  const bool           haveFallback = removeAbove ? LargestValueBelow(parameters.IsoValue, fallback)
                                                  : SmallestValueNotBelow(parameters.IsoValue, fallback);
  std::vector<uint8_t> removed(componentSizes.size(), 0);
  for (SizeValueType c = 0; c < componentSizes.size(); ++c)
  {
    if (componentSizes[c] > parameters.MaximumComponentSize)
    {
      continue;
    }
    if (haveFallback)
    {
      removed[c] = 1;
      ++statistics.RemovedComponents;
      statistics.RemovedVoxels += componentSizes[c];
    }
    else
    {
      unrepairable += componentSizes[c];
    }
  }
  const std::vector<TPixel> before = image;
  for (SizeValueType v = 0; v < image.size(); ++v)
  {
    if (label[v] == NoComponent || !removed[label[v]])
    {
      continue;
    }
    if (!RepairValue(grid, before, parameters.IsoValue, removeAbove, v, image[v]))
    {
      image[v] = fallback;
      ++unrepairable;
      ++fallbacks;
    }
    mask[v] = maskValue;
  }
}

/** Runs the filter's semantics on a buffer of \a size voxels (axis 0 fastest). */
template <typename TOutputPixel, unsigned int VDimension, typename TInputPixel>
Result<TOutputPixel>
Run(const std::array<SizeValueType, VDimension> & size,
    const std::vector<TInputPixel> &              input,
    const Parameters &                            parameters)
{
  const Grid<VDimension> grid(size, parameters.FullyConnected);
  Result<TOutputPixel>   result;
  result.Output.resize(input.size());
  for (SizeValueType v = 0; v < input.size(); ++v)
  {
    result.Output[v] = static_cast<TOutputPixel>(input[v]);
  }
  result.Mask.assign(input.size(), 0);
  if (parameters.Side == SideEnum::Above)
  {
    // Only pass A changes the image; the below statistics describe the input.
    std::vector<TOutputPixel> unchanged = result.Output;
    RemovalPass(grid,
                parameters,
                false,
                false,
                2,
                unchanged,
                result.Mask,
                result.Below,
                result.UnrepairableVoxels,
                result.FallbackVoxels);
  }
  RemovalPass(grid,
              parameters,
              true,
              parameters.Side != SideEnum::Below,
              1,
              result.Output,
              result.Mask,
              result.Above,
              result.UnrepairableVoxels,
              result.FallbackVoxels);
  if (parameters.Side != SideEnum::Above)
  {
    // Pass B sees the result of pass A (the input itself when pass A did not run).
    RemovalPass(grid,
                parameters,
                false,
                true,
                2,
                result.Output,
                result.Mask,
                result.Below,
                result.UnrepairableVoxels,
                result.FallbackVoxels);
  }
  for (const uint8_t m : result.Mask)
  {
    result.ModifiedVoxels += m != 0 ? 1 : 0;
  }
  return result;
}

template <typename TImage>
std::array<SizeValueType, TImage::ImageDimension>
SizeOf(const TImage * image)
{
  std::array<SizeValueType, TImage::ImageDimension> size;
  for (unsigned int a = 0; a < TImage::ImageDimension; ++a)
  {
    size[a] = image->GetBufferedRegion().GetSize()[a];
  }
  return size;
}

template <typename TImage>
std::vector<typename TImage::PixelType>
BufferOf(const TImage * image)
{
  const auto * first = image->GetBufferPointer();
  return std::vector<typename TImage::PixelType>(first, first + image->GetBufferedRegion().GetNumberOfPixels());
}

/** Runs the reference on an ITK image. */
template <typename TOutputPixel, typename TInputImage>
Result<TOutputPixel>
Run(const TInputImage * input, const Parameters & parameters)
{
  return Run<TOutputPixel, TInputImage::ImageDimension>(SizeOf(input), BufferOf(input), parameters);
}

/** The components of both sides of an image, found by relabelling it. */
struct ComponentCounts
{
  SideStatistics Above;
  SideStatistics Below;
};

template <typename TImage>
ComponentCounts
CountComponents(const TImage * image, double isoValue, bool fullyConnected)
{
  const Grid<TImage::ImageDimension> grid(SizeOf(image), fullyConnected);
  const auto                         values = BufferOf(image);
  std::vector<SizeValueType>         label;
  std::vector<SizeValueType>         componentSizes;
  ComponentCounts                    counts;
  counts.Above = LabelSide(grid, values, isoValue, true, label, componentSizes);
  counts.Below = LabelSide(grid, values, isoValue, false, label, componentSizes);
  return counts;
}
} // namespace SmallIsoComponentReference
} // end namespace itk

#endif
