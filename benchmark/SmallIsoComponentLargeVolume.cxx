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
// SmallIsoComponentLargeVolume: writes a synthetic uint8 volume of any size plane by plane (never
// holding more than one plane), for measuring the streaming mode on volumes larger than memory:
// smooth value noise (random values on a lattice of spacing 16, interpolated) above and below 128,
// with one voxel in a thousand flipped to the other side (specks and bubbles of one voxel and a
// few more where flips touch). The same size and seed always give the same file.

#include "sicStreamedImageFiles.h"
#include "sicToolError.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

namespace
{
uint64_t
Hash(uint64_t x)
{
  // SplitMix64's finalizer: a well-mixed 64-bit hash of a counter.
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

double
LatticeValue(uint64_t seed, uint64_t i, uint64_t j, uint64_t k)
{
  return static_cast<double>(Hash(seed ^ Hash(i ^ Hash(j ^ Hash(k)))) >> 11) / static_cast<double>(1ull << 53);
}
} // namespace

int
main(int argc, char * argv[])
{
  if (argc < 5 || argc > 6)
  {
    std::cerr << "usage: SmallIsoComponentLargeVolume OUTPUT.mhd|.mha|.nhdr|.nrrd NX NY NZ [SEED]\n"
                 "Writes an uncompressed uint8 volume of NX x NY x NZ voxels plane by plane: smooth noise\n"
                 "around 128 with one voxel in a thousand flipped across it (filter it at isovalue 127.5).\n";
    return 2;
  }
  try
  {
    const std::string   output = argv[1];
    sic::VolumeGeometry geometry;
    geometry.Dimension = 3;
    geometry.ComponentType = itk::IOComponentEnum::UCHAR;
    for (int a = 2; a <= 4; ++a)
    {
      geometry.Size.push_back(std::stoull(argv[a]));
    }
    geometry.Spacing = { 1.0, 1.0, 1.0 };
    geometry.Origin = { 0.0, 0.0, 0.0 };
    geometry.Direction = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    const uint64_t       seed = argc == 6 ? std::stoull(argv[5]) : 1;
    const auto           start = std::chrono::steady_clock::now();
    sic::PlaneWriter     writer(output, output, "volume", geometry, false);
    const uint64_t       nx = geometry.Size[0];
    const uint64_t       ny = geometry.Size[1];
    const uint64_t       nz = geometry.Size[2];
    constexpr uint64_t   Spacing = 16;
    std::vector<uint8_t> plane(nx * ny);
    // The lattice values of the two lattice planes around z, interpolated along x and y once.
    std::vector<double> below(nx * ny);
    std::vector<double> above(nx * ny);
    const auto          fillLatticePlane = [&](uint64_t k, std::vector<double> & values) {
      for (uint64_t y = 0; y < ny; ++y)
      {
        const uint64_t j = y / Spacing;
        const double   fy = static_cast<double>(y % Spacing) / Spacing;
        for (uint64_t x = 0; x < nx; ++x)
        {
          const uint64_t i = x / Spacing;
          const double   fx = static_cast<double>(x % Spacing) / Spacing;
          const double   v00 = LatticeValue(seed, i, j, k);
          const double   v10 = LatticeValue(seed, i + 1, j, k);
          const double   v01 = LatticeValue(seed, i, j + 1, k);
          const double   v11 = LatticeValue(seed, i + 1, j + 1, k);
          values[y * nx + x] = (v00 * (1 - fx) + v10 * fx) * (1 - fy) + (v01 * (1 - fx) + v11 * fx) * fy;
        }
      }
    };
    uint64_t latticePlane = ~uint64_t{ 0 };
    for (uint64_t z = 0; z < nz; ++z)
    {
      if (z / Spacing != latticePlane)
      {
        latticePlane = z / Spacing;
        fillLatticePlane(latticePlane, below);
        fillLatticePlane(latticePlane + 1, above);
      }
      const double fz = static_cast<double>(z % Spacing) / Spacing;
      for (uint64_t v = 0; v < nx * ny; ++v)
      {
        const double smooth = below[v] * (1 - fz) + above[v] * fz;
        auto         value = static_cast<int>(std::lround(40.0 + 176.0 * smooth));
        // One voxel in a thousand crosses 128.
        if (Hash(seed * 0x1000193ull ^ (z * nx * ny + v)) % 1000 == 0)
        {
          value = value >= 128 ? 127 - (value - 128) % 60 : 128 + (127 - value) % 60;
        }
        plane[v] = static_cast<uint8_t>(std::min(255, std::max(0, value)));
      }
      writer.Write(plane.data(), 1);
    }
    writer.Finish();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "Wrote " << output << ": " << nx << " x " << ny << " x " << nz << " uint8 voxels ("
              << (nx * ny * nz >> 20) << " MiB) in " << seconds << " s; filter it at isovalue 127.5." << std::endl;
    return 0;
  }
  catch (const std::exception & error)
  {
    std::cerr << "SmallIsoComponentLargeVolume: " << error.what() << std::endl;
    return 2;
  }
}
