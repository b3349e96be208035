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
#include "sicPhantom.h"
#include "sicSplitMix64.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sic
{
namespace
{
constexpr double Air = -1000.0;
constexpr double SoftTissue = 40.0;
constexpr double Bone = 700.0;
constexpr double Marrow = 60.0;
constexpr double Rod = 1000.0;
constexpr double NoiseScale = 20.0;

struct Point
{
  double X, Y, Z;
};

/** Approximate signed distance, in voxels, from p to an ellipsoid centred on the origin. */
double
EllipsoidDistance(const Point & p, const Point & radii)
{
  const double x = p.X / radii.X;
  const double y = p.Y / radii.Y;
  const double z = p.Z / radii.Z;
  const double q = std::sqrt(x * x + y * y + z * z);
  if (q == 0.0)
  {
    return -std::min({ radii.X, radii.Y, radii.Z });
  }
  // First order: (q - 1) / |grad q|.
  const double gx = x / radii.X;
  const double gy = y / radii.Y;
  const double gz = z / radii.Z;
  return (q - 1.0) * q / std::sqrt(gx * gx + gy * gy + gz * gz);
}

/** The fraction of a voxel at signed distance d that is inside: a one-voxel ramp. */
double
Inside(double distance)
{
  return std::clamp(0.5 - distance, 0.0, 1.0);
}

/** The phantom's geometry, in voxel coordinates relative to the centre. */
class Geometry
{
public:
  explicit Geometry(unsigned int size)
  {
    const double half = 0.5 * size;
    m_Body = { 0.85 * half, 0.7 * half, 0.92 * half };
    m_Outer = { 0.5 * half, 0.4 * half, 0.7 * half };
    const double wall = std::max(2.5, 0.12 * half);
    m_Inner = { m_Outer.X - wall, m_Outer.Y - wall, m_Outer.Z - wall };
    m_RodY = -0.56 * half;
    m_RodRadius = std::max(1.5, 0.09 * half);
    m_RodHalfLength = 0.8 * half;
  }

  /** The noiseless value at p. */
  double
  Value(const Point & p) const
  {
    double value = Air;
    value += (SoftTissue - value) * Inside(EllipsoidDistance(p, m_Body));
    value += (Bone - value) * Inside(EllipsoidDistance(p, m_Outer));
    value += (Marrow - value) * Inside(EllipsoidDistance(p, m_Inner));
    const double radial = std::hypot(p.X, p.Y - m_RodY) - m_RodRadius;
    const double axial = std::fabs(p.Z) - m_RodHalfLength;
    value += (Rod - value) * Inside(std::max(radial, axial));
    return value;
  }

private:
  Point  m_Body{};
  Point  m_Outer{};
  Point  m_Inner{};
  double m_RodY{};
  double m_RodRadius{};
  double m_RodHalfLength{};
};

/** Noise of standard deviation NoiseScale: the sum of three uniforms in [-1, 1), each
 * from 21 bits of one draw. */
double
Noise(SplitMix64 & random)
{
  const std::uint64_t bits = random.Next();
  double              sum = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    sum += static_cast<double>((bits >> (21 * k)) & 0x1fffff) / 1048576.0 - 1.0;
  }
  return NoiseScale * sum;
}

std::int16_t
ToPixel(double value)
{
  const double clamped = std::clamp(value,
                                    static_cast<double>(std::numeric_limits<std::int16_t>::lowest()),
                                    static_cast<double>(std::numeric_limits<std::int16_t>::max()));
  return static_cast<std::int16_t>(std::lround(clamped));
}

/** Stamps \a count small ellipsoids (radii from \a minimumRadius to \a maximumRadius voxels
 * along each axis) of a value from \a low to \a high, centred on voxels where \a accept
 * holds. */
template <typename TAccept>
void
StampBlobs(PhantomImageType * image,
           SplitMix64 &       random,
           SplitMix64 &       noise,
           std::uint64_t      count,
           double             minimumRadius,
           double             maximumRadius,
           double             low,
           double             high,
           TAccept            accept)
{
  const auto    n = static_cast<std::int64_t>(image->GetLargestPossibleRegion().GetSize()[0]);
  std::uint64_t placed = 0;
  for (std::uint64_t attempt = 0; placed < count && attempt < 50 * count; ++attempt)
  {
    std::array<std::int64_t, 3> center;
    std::array<double, 3>       radius;
    for (int axis = 0; axis < 3; ++axis)
    {
      center[axis] = 1 + static_cast<std::int64_t>(random.Uniform() * static_cast<double>(n - 2));
    }
    for (int axis = 0; axis < 3; ++axis)
    {
      radius[axis] = random.Uniform(minimumRadius, maximumRadius);
    }
    const double value = random.Uniform(low, high);
    const double largest = std::max({ radius[0], radius[1], radius[2] });
    if (!accept(center, largest))
    {
      continue;
    }
    ++placed;
    std::array<std::int64_t, 3> first;
    std::array<std::int64_t, 3> last;
    for (int axis = 0; axis < 3; ++axis)
    {
      const auto reach = static_cast<std::int64_t>(radius[axis]);
      first[axis] = std::max<std::int64_t>(0, center[axis] - reach);
      last[axis] = std::min(n - 1, center[axis] + reach);
    }
    for (std::int64_t z = first[2]; z <= last[2]; ++z)
    {
      for (std::int64_t y = first[1]; y <= last[1]; ++y)
      {
        for (std::int64_t x = first[0]; x <= last[0]; ++x)
        {
          const double dx = static_cast<double>(x - center[0]) / radius[0];
          const double dy = static_cast<double>(y - center[1]) / radius[1];
          const double dz = static_cast<double>(z - center[2]) / radius[2];
          if (dx * dx + dy * dy + dz * dz <= 1.0)
          {
            const PhantomImageType::IndexType index = { { static_cast<itk::IndexValueType>(x),
                                                          static_cast<itk::IndexValueType>(y),
                                                          static_cast<itk::IndexValueType>(z) } };
            image->SetPixel(index, ToPixel(value + Noise(noise)));
          }
        }
      }
    }
  }
}
} // namespace

PhantomImageType::Pointer
MakePhantom(unsigned int size, std::uint64_t seed)
{
  auto                             image = PhantomImageType::New();
  const PhantomImageType::SizeType imageSize{ { size, size, size } };
  image->SetRegions(imageSize);
  const double spacing[3] = { 0.8, 0.8, 1.0 };
  image->SetSpacing(spacing);
  double origin[3];
  for (int axis = 0; axis < 3; ++axis)
  {
    origin[axis] = -0.5 * (size - 1) * spacing[axis];
  }
  image->SetOrigin(origin);
  image->Allocate();

  const Geometry geometry(size);
  const double   center = 0.5 * (size - 1);
  const auto     at = [center](std::int64_t x, std::int64_t y, std::int64_t z) {
    return Point{ static_cast<double>(x) - center, static_cast<double>(y) - center, static_cast<double>(z) - center };
  };
  SplitMix64     noise(seed);
  std::int16_t * buffer = image->GetBufferPointer();
  for (std::int64_t z = 0; z < size; ++z)
  {
    for (std::int64_t y = 0; y < size; ++y)
    {
      for (std::int64_t x = 0; x < size; ++x)
      {
        *buffer++ = ToPixel(geometry.Value(at(x, y, z)) + Noise(noise));
      }
    }
  }

  SplitMix64          placement(seed ^ 0x6a09e667f3bcc908ULL);
  const std::uint64_t voxels = static_cast<std::uint64_t>(size) * size * size;
  // Specks: dense blobs where the volume is not dense.
  StampBlobs(
    image,
    placement,
    noise,
    std::max<std::uint64_t>(8, voxels / 1500),
    0.45,
    1.8,
    300.0,
    1000.0,
    [&](const std::array<std::int64_t, 3> & c, double) { return geometry.Value(at(c[0], c[1], c[2])) < 100.0; });
  // Bubbles: light blobs inside the dense parts, with dense material all around them.
  StampBlobs(image,
             placement,
             noise,
             std::max<std::uint64_t>(8, voxels / 3000),
             0.45,
             1.5,
             -200.0,
             100.0,
             [&](const std::array<std::int64_t, 3> & c, double radius) {
               const auto reach = static_cast<std::int64_t>(radius) + 1;
               for (const auto & d : { std::array<std::int64_t, 3>{ 0, 0, 0 },
                                       std::array<std::int64_t, 3>{ reach, 0, 0 },
                                       std::array<std::int64_t, 3>{ -reach, 0, 0 },
                                       std::array<std::int64_t, 3>{ 0, reach, 0 },
                                       std::array<std::int64_t, 3>{ 0, -reach, 0 },
                                       std::array<std::int64_t, 3>{ 0, 0, reach },
                                       std::array<std::int64_t, 3>{ 0, 0, -reach } })
               {
                 if (geometry.Value(at(c[0] + d[0], c[1] + d[1], c[2] + d[2])) < 500.0)
                 {
                   return false;
                 }
               }
               return true;
             });
  return image;
}
} // namespace sic
