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
#ifndef itkSmallIsoComponentTestUtilities_h
#define itkSmallIsoComponentTestUtilities_h

#include "itkSmallIsoComponentImageFilter.h"
#include "itkSmallIsoComponentReference.h"
#include <algorithm>
#include <cstring>
#include <random>
#include <sstream>
#include <string>

namespace itk
{
/** What the GoogleTest files share: seeded random test volumes, a filter runner, and
 * comparisons that say where the filter and the reference differ. */
namespace SmallIsoComponentTest
{
namespace Reference = SmallIsoComponentReference;
using Reference::Parameters;
using SideEnum = SmallIsoComponentEnums::Side;

/** std::mt19937 with its raw output mapped by hand, so that a seed gives the same volume
 * with every standard library (the std distributions are implementation-defined). */
class RandomSource
{
public:
  explicit RandomSource(uint32_t seed)
    : m_Engine(seed)
  {}

  uint32_t
  Bits()
  {
    return static_cast<uint32_t>(m_Engine());
  }
  /** An integer in [low, high]. */
  int64_t
  Between(int64_t low, int64_t high)
  {
    return low + static_cast<int64_t>(this->Bits() % static_cast<uint64_t>(high - low + 1));
  }
  /** A double in [0, 1). */
  double
  Uniform()
  {
    return this->Bits() * (1.0 / 4294967296.0);
  }
  bool
  Chance(double probability)
  {
    return this->Uniform() < probability;
  }
  template <typename T, size_t N>
  T
  Pick(const std::array<T, N> & choices)
  {
    return choices[this->Bits() % N];
  }

private:
  std::mt19937 m_Engine;
};

template <typename TPixel, unsigned int VDimension>
typename Image<TPixel, VDimension>::Pointer
MakeImage(const std::array<SizeValueType, VDimension> & extent, const std::vector<TPixel> & values)
{
  using ImageType = Image<TPixel, VDimension>;
  typename ImageType::SizeType size;
  for (unsigned int a = 0; a < VDimension; ++a)
  {
    size[a] = extent[a];
  }
  auto image = ImageType::New();
  image->SetRegions(size);
  image->Allocate();
  std::copy(values.begin(), values.end(), image->GetBufferPointer());
  return image;
}

/** Prints a pixel so that its exact value can be read back (uint8 as a number). */
template <typename TPixel>
std::string
PixelToString(TPixel value)
{
  std::ostringstream out;
  out.precision(std::numeric_limits<TPixel>::max_digits10);
  out << +value;
  return out.str();
}

template <typename TPixel>
bool
SameBits(TPixel a, TPixel b)
{
  return std::memcmp(&a, &b, sizeof(TPixel)) == 0;
}

template <typename TPixel>
std::string
BufferToString(const std::vector<TPixel> & values)
{
  std::ostringstream out;
  for (SizeValueType v = 0; v < values.size(); ++v)
  {
    out << (v ? " " : "") << PixelToString(values[v]);
  }
  return out.str();
}

/** A random test volume and the filter parameters drawn with it from one seed. */
template <typename TInputPixel, unsigned int VDimension>
struct RandomCase
{
  using ImageType = Image<TInputPixel, VDimension>;
  uint32_t                              Seed{ 0 };
  std::array<SizeValueType, VDimension> Size{};
  std::vector<TInputPixel>              Values;
  typename ImageType::Pointer           Input;
  Parameters                            Settings;
  std::string                           Description;
};

namespace Detail
{
/** One extent, mostly small, sometimes up to 40 (up to 10 from four dimensions on). */
inline SizeValueType
DrawExtent(RandomSource & random, unsigned int dimension)
{
  const double r = random.Uniform();
  if (dimension > 3)
  {
    return static_cast<SizeValueType>(r < 0.9 ? random.Between(1, 6) : random.Between(7, 10));
  }
  if (r < 0.75)
  {
    return static_cast<SizeValueType>(random.Between(1, dimension == 2 ? 16 : 9));
  }
  if (r < 0.95)
  {
    return static_cast<SizeValueType>(random.Between(dimension == 2 ? 17 : 10, 24));
  }
  return static_cast<SizeValueType>(random.Between(25, 40));
}

/** Three box blurs of radius 1 along every axis: smooth blobs from white noise. */
template <unsigned int VDimension>
void
Blur(const Reference::Grid<VDimension> & grid, std::vector<double> & field, unsigned int passes)
{
  for (unsigned int pass = 0; pass < passes; ++pass)
  {
    for (unsigned int axis = 0; axis < VDimension; ++axis)
    {
      const std::vector<double> before = field;
      for (SizeValueType v = 0; v < field.size(); ++v)
      {
        auto         c = grid.Coordinates(v);
        double       sum = 0.0;
        unsigned int count = 0;
        for (const int d : { -1, 0, 1 })
        {
          auto n = c;
          n[axis] += d;
          if (grid.Inside(n))
          {
            sum += before[grid.Linear(n)];
            ++count;
          }
        }
        field[v] = sum / count;
      }
    }
  }
}

/** A field in [0, 1] of one of several kinds; high values are meant to end up above σ. */
template <unsigned int VDimension>
std::vector<double>
DrawField(RandomSource & random, const Reference::Grid<VDimension> & grid, std::ostream & description)
{
  const SizeValueType n = grid.NumberOfVoxels();
  std::vector<double> field(n);
  const int           kind = static_cast<int>(random.Between(0, 3));
  if (kind == 0)
  {
    const auto passes = static_cast<unsigned int>(random.Between(1, 3));
    description << " field=smooth(" << passes << ")";
    for (double & f : field)
    {
      f = random.Uniform();
    }
    Blur(grid, field, passes);
    const auto [low, high] = std::minmax_element(field.begin(), field.end());
    const double lowValue = *low;
    const double range = *high - *low;
    for (double & f : field)
    {
      f = range > 0.0 ? (f - lowValue) / range : 0.5;
    }
  }
  else if (kind == 1)
  {
    // Solid balls on a background, salt noise (specks and bubbles), and planted shells:
    // a bubble inside a speck, or a speck inside a bubble.
    const double salt = random.Pick(std::array<double, 4>{ 0.0, 0.01, 0.05, 0.15 });
    const auto   balls = static_cast<unsigned int>(random.Between(1, 4));
    const auto   shells = static_cast<unsigned int>(random.Between(0, 3));
    description << " field=blobs(balls " << balls << ", salt " << salt << ", shells " << shells << ")";
    std::vector<uint8_t> inside(n, 0);
    for (unsigned int b = 0; b < balls; ++b)
    {
      std::array<double, VDimension> center;
      SizeValueType                  largest = 1;
      for (unsigned int a = 0; a < VDimension; ++a)
      {
        center[a] = random.Uniform() * static_cast<double>(grid.Size()[a]);
        largest = std::max(largest, grid.Size()[a]);
      }
      const double radius = 0.5 + random.Uniform() * static_cast<double>(largest) / 2.0;
      for (SizeValueType v = 0; v < n; ++v)
      {
        const auto c = grid.Coordinates(v);
        double     d2 = 0.0;
        for (unsigned int a = 0; a < VDimension; ++a)
        {
          d2 += (static_cast<double>(c[a]) + 0.5 - center[a]) * (static_cast<double>(c[a]) + 0.5 - center[a]);
        }
        inside[v] |= d2 <= radius * radius ? 1 : 0;
      }
    }
    for (unsigned int s = 0; s < shells; ++s)
    {
      // A 3^N cube (clipped at the border) of one kind with its centre of the other.
      const bool                                            shellInside = random.Chance(0.5);
      typename Reference::Grid<VDimension>::CoordinatesType corner;
      for (unsigned int a = 0; a < VDimension; ++a)
      {
        corner[a] = random.Between(-1, static_cast<int64_t>(grid.Size()[a]) - 2);
      }
      for (SizeValueType code = 0; code < Math::UnsignedPower(3, VDimension); ++code)
      {
        auto          c = corner;
        SizeValueType rest = code;
        bool          center = true;
        for (unsigned int a = 0; a < VDimension; ++a)
        {
          c[a] += static_cast<OffsetValueType>(rest % 3);
          center = center && rest % 3 == 1;
          rest /= 3;
        }
        if (grid.Inside(c))
        {
          inside[grid.Linear(c)] = center != shellInside ? 1 : 0;
        }
      }
    }
    const double jitter = random.Pick(std::array<double, 3>{ 0.0, 0.1, 0.3 });
    for (SizeValueType v = 0; v < n; ++v)
    {
      const bool high = (inside[v] != 0) != random.Chance(salt);
      field[v] = (high ? 0.75 : 0.25) + jitter * (random.Uniform() - 0.5);
    }
  }
  else if (kind == 2)
  {
    const double density = 0.05 + 0.9 * random.Uniform();
    description << " field=salt(density " << density << ")";
    for (double & f : field)
    {
      f = random.Chance(density) ? 0.5 + 0.5 * random.Uniform() : 0.5 * random.Uniform();
    }
  }
  else
  {
    // A few levels only: many samples equal to σ and to each other.
    const auto levels = static_cast<int>(random.Between(2, 5));
    description << " field=levels(" << levels << ")";
    for (double & f : field)
    {
      f = static_cast<double>(random.Between(0, levels - 1)) / (levels - 1);
    }
  }
  return field;
}

/** Maps the field to the input pixel type. */
template <typename TInputPixel>
std::vector<TInputPixel>
FieldToPixels(RandomSource & random, const std::vector<double> & field, std::ostream & description)
{
  std::vector<TInputPixel> values(field.size());
  if constexpr (std::is_same<TInputPixel, uint8_t>::value)
  {
    for (SizeValueType v = 0; v < field.size(); ++v)
    {
      values[v] = static_cast<TInputPixel>(std::lround(field[v] * 255.0));
    }
  }
  else if constexpr (std::is_integral<TInputPixel>::value)
  {
    // A narrow range (many equal samples, σ often equal to one) or most of the type's
    // range (at most ±10^9).
    using Limits = std::numeric_limits<TInputPixel>;
    const double low = std::max(static_cast<double>(Limits::lowest()), -1.0e9);
    const double high = std::min(static_cast<double>(Limits::max()), 1.0e9);
    const bool   narrow = random.Chance(0.5);
    const double scale = narrow ? 12.0 : 0.95 * (high - low);
    const double offset =
      narrow ? static_cast<double>(random.Between(Limits::is_signed ? -8 : 0, 8)) : low + 0.025 * (high - low);
    description << " int(scale " << scale << ", offset " << offset << ")";
    for (SizeValueType v = 0; v < field.size(); ++v)
    {
      values[v] = static_cast<TInputPixel>(std::lround(field[v] * scale + offset));
    }
  }
  else
  {
    const double scale = random.Pick(std::array<double, 3>{ 1.0, 100.0, 1.0e-3 });
    const double offset = scale * (random.Uniform() - 0.5);
    const double nan = random.Pick(std::array<double, 4>{ 0.0, 0.0, 0.02, 0.15 });
    description << " float(scale " << scale << ", offset " << offset << ", nan " << nan << ")";
    for (SizeValueType v = 0; v < field.size(); ++v)
    {
      values[v] = random.Chance(nan) ? std::numeric_limits<TInputPixel>::quiet_NaN()
                                     : static_cast<TInputPixel>(field[v] * scale + offset);
    }
  }
  return values;
}

/** σ as the output type sees it: a sample value, halfway between two samples, or (rarely)
 * beyond every sample and, for integers, beyond the type's range. */
template <typename TOutputPixel, typename TInputPixel>
double
DrawIsoValue(RandomSource & random, const std::vector<TInputPixel> & values, std::ostream & description)
{
  const auto sample = [&]() {
    for (int attempt = 0; attempt < 20; ++attempt)
    {
      const auto value = static_cast<TOutputPixel>(values[random.Between(0, static_cast<int64_t>(values.size()) - 1)]);
      if (!Reference::IsNaN(value))
      {
        return static_cast<double>(value);
      }
    }
    return 0.0;
  };
  const double r = random.Uniform();
  double       iso = 0.0;
  if (r < 0.45)
  {
    iso = sample();
    description << " iso=sample";
  }
  else if (r < 0.94)
  {
    const double a = sample();
    const double b = sample();
    iso = a != b ? (a + b) / 2.0 : a + 0.5;
    description << " iso=between";
  }
  else
  {
    using Limits = std::numeric_limits<TOutputPixel>;
    if constexpr (std::is_integral<TOutputPixel>::value)
    {
      iso = random.Pick(std::array<double, 4>{ static_cast<double>(Limits::lowest()),
                                               static_cast<double>(Limits::lowest()) - 0.5,
                                               static_cast<double>(Limits::max()) + 0.5,
                                               static_cast<double>(Limits::max()) + 7.0 });
    }
    else
    {
      iso = random.Pick(std::array<double, 2>{ -1.0e6, 1.0e6 });
    }
    description << " iso=extreme";
  }
  description.precision(17);
  description << "(" << iso << ")";
  return iso;
}
} // namespace Detail

/** The volume and parameters of one seed. Extents are mostly small; \a large draws every
 * extent from 20 to 40 instead. */
template <typename TInputPixel, typename TOutputPixel, unsigned int VDimension>
RandomCase<TInputPixel, VDimension>
MakeRandomCase(uint32_t seed, bool large = false)
{
  RandomSource                        random(seed);
  RandomCase<TInputPixel, VDimension> c;
  c.Seed = seed;
  std::ostringstream description;
  description << "seed=" << seed << " size=[";
  for (unsigned int a = 0; a < VDimension; ++a)
  {
    c.Size[a] = large ? static_cast<SizeValueType>(random.Between(20, 40)) : Detail::DrawExtent(random, VDimension);
    description << (a ? "," : "") << c.Size[a];
  }
  description << "]";
  const Reference::Grid<VDimension> grid(c.Size, false);
  const auto                        field = Detail::DrawField(random, grid, description);
  c.Values = Detail::FieldToPixels<TInputPixel>(random, field, description);
  c.Input = MakeImage<TInputPixel, VDimension>(c.Size, c.Values);
  c.Settings.IsoValue = Detail::DrawIsoValue<TOutputPixel>(random, c.Values, description);
  const SizeValueType n = grid.NumberOfVoxels();
  c.Settings.MaximumComponentSize =
    random.Pick(std::array<SizeValueType, 6>{ 0, 1, 2, 5, 20, n + static_cast<SizeValueType>(random.Between(0, 9)) });
  c.Settings.Side = random.Pick(std::array<SideEnum, 3>{ SideEnum::Above, SideEnum::Below, SideEnum::Both });
  c.Settings.FullyConnected = random.Chance(0.5);
  description << " K=" << c.Settings.MaximumComponentSize << " side=" << c.Settings.Side
              << " fullyConnected=" << c.Settings.FullyConnected;
  if (n <= 64)
  {
    description << " input={" << BufferToString(c.Values) << "}";
  }
  c.Description = description.str();
  return c;
}

template <typename TInputImage, typename TOutputImage = TInputImage>
typename SmallIsoComponentImageFilter<TInputImage, TOutputImage>::Pointer
RunFilter(const TInputImage * input,
          const Parameters &  settings,
          unsigned int        workUnits = 1,
          bool                inPlace = false,
          bool                generateMask = true,
          SizeValueType       slabThickness = 0)
{
  auto filter = SmallIsoComponentImageFilter<TInputImage, TOutputImage>::New();
  filter->SetSlabThickness(slabThickness);
  filter->SetGenerateRemovedMask(generateMask);
  filter->SetInput(input);
  filter->SetIsoValue(settings.IsoValue);
  filter->SetMaximumComponentSize(settings.MaximumComponentSize);
  filter->SetSide(settings.Side);
  filter->SetFullyConnected(settings.FullyConnected);
  filter->SetNumberOfWorkUnits(workUnits);
  filter->SetInPlace(inPlace);
  filter->Update();
  return filter;
}

inline std::string
HistogramToString(const Reference::HistogramType & histogram)
{
  std::ostringstream out;
  out << "{";
  for (const auto & entry : histogram)
  {
    out << " " << entry.first << ":" << entry.second;
  }
  out << " }";
  return out.str();
}

/** Empty when the filter's outputs and statistics equal the reference's; otherwise what
 * differs, with the first differing voxels. A filter that made no mask must have left it
 * without voxels. */
template <typename TFilter>
std::string
DifferencesFromReference(TFilter *                                                               filter,
                         const Reference::Result<typename TFilter::OutputImageType::PixelType> & expected,
                         SizeValueType                                                           expectedK)
{
  std::ostringstream out;
  const auto *       output = filter->GetOutput()->GetBufferPointer();
  const auto *       mask = filter->GetRemovedMask()->GetBufferPointer();
  const bool         hasMask = filter->GetGenerateRemovedMask();
  const auto         n = filter->GetOutput()->GetBufferedRegion().GetNumberOfPixels();
  if (n != expected.Output.size() ||
      filter->GetRemovedMask()->GetBufferedRegion().GetNumberOfPixels() != (hasMask ? n : 0))
  {
    std::ostringstream sizes;
    sizes << "output or mask has the wrong number of voxels: output " << n << ", expected " << expected.Output.size()
          << "; mask " << filter->GetRemovedMask()->GetBufferedRegion().GetNumberOfPixels() << ", expected "
          << (hasMask ? n : 0);
    return sizes.str();
  }
  SizeValueType reported = 0;
  for (SizeValueType v = 0; v < n; ++v)
  {
    const int got = hasMask ? int{ mask[v] } : int{ expected.Mask[v] };
    if ((!SameBits(output[v], expected.Output[v]) || got != expected.Mask[v]) && reported++ < 5)
    {
      out << " voxel " << filter->GetOutput()->ComputeIndex(static_cast<OffsetValueType>(v)) << ": expected "
          << PixelToString(expected.Output[v]) << " mask " << int{ expected.Mask[v] } << ", got "
          << PixelToString(output[v]) << " mask " << got << ";";
    }
  }
  if (reported > 5)
  {
    out << " (" << reported << " voxels differ);";
  }
  const auto compare = [&out](const char * what, SizeValueType e, SizeValueType g) {
    if (e != g)
    {
      out << " " << what << ": expected " << e << ", got " << g << ";";
    }
  };
  const std::array<std::pair<SideEnum, const Reference::SideStatistics *>, 2> sides{
    { { SideEnum::Above, &expected.Above }, { SideEnum::Below, &expected.Below } }
  };
  for (const auto & side : sides)
  {
    const std::string name = side.first == SideEnum::Above ? "above " : "below ";
    compare((name + "components").c_str(), side.second->Components, filter->GetNumberOfComponents(side.first));
    compare((name + "removed components").c_str(),
            side.second->RemovedComponents,
            filter->GetNumberOfRemovedComponents(side.first));
    compare(
      (name + "removed voxels").c_str(), side.second->RemovedVoxels, filter->GetNumberOfRemovedVoxels(side.first));
    if (side.second->Histogram != filter->GetComponentSizeHistogram(side.first))
    {
      out << " " << name << "histogram: expected " << HistogramToString(side.second->Histogram) << ", got "
          << HistogramToString(filter->GetComponentSizeHistogram(side.first)) << ";";
    }
  }
  compare("modified voxels", expected.ModifiedVoxels, filter->GetNumberOfModifiedVoxels());
  compare("unrepairable voxels", expected.UnrepairableVoxels, filter->GetNumberOfUnrepairableVoxels());
  compare("effective K", expectedK, filter->GetEffectiveMaximumComponentSize());
  return out.str();
}

/** Voxels whose bits differ between two images of the same size. */
template <typename TImage>
SizeValueType
CountDifferentVoxels(const TImage * a, const TImage * b)
{
  const auto    n = a->GetBufferedRegion().GetNumberOfPixels();
  SizeValueType differ = 0;
  for (SizeValueType v = 0; v < n; ++v)
  {
    differ += SameBits(a->GetBufferPointer()[v], b->GetBufferPointer()[v]) ? 0 : 1;
  }
  return differ;
}
} // namespace SmallIsoComponentTest
} // end namespace itk

#endif
