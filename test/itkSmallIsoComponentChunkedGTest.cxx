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
 *  =========================================================================*/
// The chunked mode's two pieces against the brute-force reference, on random volumes cut into
// random grids of chunks: each chunk filtered with its halo (FilterBoxPart) gives the whole image's
// voxels, and the chunks' summaries (SummarizeBox) merged along the grid give its statistics.

#include "itkSmallIsoComponentInternalsTestUtilities.h"
#include "itkSmallIsoComponentRunSummary.h"
#include "itkSmallIsoComponentStreamingSweep.h"

#include "gtest/gtest.h"

namespace
{
using namespace itk;
using namespace itk::SmallIsoComponentTest;
using Summary = SmallIsoComponentDetail::BlockSummary;
using IndexType = Summary::IndexType;

std::vector<uint64_t>
RandomCuts(RandomSource & random, uint64_t extent)
{
  std::vector<uint64_t> cuts{ 0, extent };
  const int             pieces = random.Between(1, static_cast<int>(std::min<uint64_t>(extent, 6)));
  for (int p = 1; p < pieces; ++p)
  {
    cuts.push_back(static_cast<uint64_t>(random.Between(1, static_cast<int>(extent) - 1)));
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  return cuts;
}

/** Filters \a c chunk by chunk with halos of \a halo voxels and merges the chunks' summaries; returns
 * how the result differs from the reference. */
template <typename TPixel, unsigned int VDimension>
std::string
ChunkedDifferences(const RandomCase<TPixel, VDimension> & c, uint64_t halo, RandomSource & random)
{
  const auto                                       expected = Reference::Run<TPixel>(c.Input.GetPointer(), c.Settings);
  const IndexType                                  size = PlaneBox<VDimension>(c.Size);
  const SmallIsoComponentDetail::Threshold<TPixel> threshold(c.Settings.IsoValue);
  SmallIsoComponentDetail::ComponentRules          rules;
  rules.MaximumComponentSize = c.Settings.MaximumComponentSize;
  rules.Side = c.Settings.Side;
  rules.FullyConnected = c.Settings.FullyConnected;
  auto threader = MultiThreaderBase::New();

  std::array<std::vector<uint64_t>, 3> cuts;
  std::array<uint64_t, 3>              count;
  for (unsigned int a = 0; a < 3; ++a)
  {
    cuts[a] = RandomCuts(random, size[a]);
    count[a] = cuts[a].size() - 1;
  }
  const auto           at = [&](uint64_t x, uint64_t y, uint64_t z) { return x + size[0] * (y + size[1] * z); };
  std::vector<TPixel>  output(c.Values.size());
  std::vector<uint8_t> mask(c.Values.size());
  std::vector<Summary> grid;
  for (uint64_t k = 0; k < count[2]; ++k)
    for (uint64_t j = 0; j < count[1]; ++j)
      for (uint64_t i = 0; i < count[0]; ++i)
      {
        const IndexType begin{ cuts[0][i], cuts[1][j], cuts[2][k] };
        const IndexType end{ cuts[0][i + 1], cuts[1][j + 1], cuts[2][k + 1] };
        // The chunk alone, for the statistics.
        std::vector<TPixel> chunk;
        for (uint64_t z = begin[2]; z < end[2]; ++z)
          for (uint64_t y = begin[1]; y < end[1]; ++y)
            for (uint64_t x = begin[0]; x < end[0]; ++x)
            {
              chunk.push_back(c.Values[at(x, y, z)]);
            }
        const IndexType extent{ end[0] - begin[0], end[1] - begin[1], end[2] - begin[2] };
        grid.push_back(SmallIsoComponentDetail::SummarizeBox(
          chunk.data(), extent, size, begin, c.Settings.IsoValue, rules, threader, 1));
        // The chunk with its halo, for the voxels.
        IndexType haloBegin;
        IndexType haloEnd;
        for (unsigned int a = 0; a < 3; ++a)
        {
          haloBegin[a] = begin[a] >= halo ? begin[a] - halo : 0;
          haloEnd[a] = std::min(size[a], end[a] + halo);
        }
        std::vector<TPixel> box;
        for (uint64_t z = haloBegin[2]; z < haloEnd[2]; ++z)
          for (uint64_t y = haloBegin[1]; y < haloEnd[1]; ++y)
            for (uint64_t x = haloBegin[0]; x < haloEnd[0]; ++x)
            {
              box.push_back(c.Values[at(x, y, z)]);
            }
        const IndexType boxExtent{ haloEnd[0] - haloBegin[0], haloEnd[1] - haloBegin[1], haloEnd[2] - haloBegin[2] };
        const IndexType cropBegin{ begin[0] - haloBegin[0], begin[1] - haloBegin[1], begin[2] - haloBegin[2] };
        const IndexType cropEnd{ cropBegin[0] + extent[0], cropBegin[1] + extent[1], cropBegin[2] + extent[2] };
        std::vector<TPixel>  part(chunk.size());
        std::vector<uint8_t> partMask(chunk.size());
        SmallIsoComponentDetail::FilterBoxPart(box.data(),
                                               boxExtent,
                                               cropBegin,
                                               cropEnd,
                                               c.Settings.IsoValue,
                                               c.Settings.MaximumComponentSize,
                                               c.Settings.Side,
                                               c.Settings.FullyConnected,
                                               threader,
                                               1,
                                               part.data(),
                                               partMask.data());
        uint64_t n = 0;
        for (uint64_t z = begin[2]; z < end[2]; ++z)
          for (uint64_t y = begin[1]; y < end[1]; ++y)
            for (uint64_t x = begin[0]; x < end[0]; ++x, ++n)
            {
              output[at(x, y, z)] = part[n];
              mask[at(x, y, z)] = partMask[n];
            }
      }
  // Merge along x, then y, then z, each row in order.
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    std::array<uint64_t, 3> newCount = count;
    newCount[axis] = 1;
    std::vector<Summary> merged;
    for (uint64_t k = 0; k < newCount[2]; ++k)
      for (uint64_t j = 0; j < newCount[1]; ++j)
        for (uint64_t i = 0; i < newCount[0]; ++i)
        {
          std::array<uint64_t, 3> position{ i, j, k };
          const auto              index = [&](uint64_t t) {
            std::array<uint64_t, 3> p = position;
            p[axis] = t;
            return p[0] + count[0] * (p[1] + count[1] * p[2]);
          };
          Summary row = grid[index(0)];
          for (uint64_t t = 1; t < count[axis]; ++t)
          {
            row = Summary::Merge(row, grid[index(t)]);
          }
          merged.push_back(std::move(row));
        }
    grid.swap(merged);
    count = newCount;
  }

  std::ostringstream differences;
  const uint64_t     fallbacks = AppendVoxelDifferences(differences, output, mask, expected);
  const auto &       tally = grid[0].GetTally();
  AppendSideDifferences(differences, tally, expected);
  if (tally.ModifiedVoxels != expected.ModifiedVoxels ||
      tally.UnrepairableVoxels + fallbacks != expected.UnrepairableVoxels)
  {
    differences << " modified or unrepairable voxels differ";
  }
  return differences.str();
}

template <typename TPixel, unsigned int VDimension>
void
CheckChunkedRandomVolumes(uint32_t firstSeed, unsigned int numberOfVolumes)
{
  unsigned int failures = 0;
  for (uint32_t seed = firstSeed; seed < firstSeed + numberOfVolumes && failures < 5; ++seed)
  {
    const auto        c = MakeRandomCase<TPixel, TPixel, VDimension>(seed);
    RandomSource      random(seed * 131u + 5u);
    const uint64_t    halo = SmallIsoComponentDetail::BoxHalo(c.Settings.MaximumComponentSize, c.Settings.Side);
    const std::string differences = ChunkedDifferences(c, halo, random);
    if (!differences.empty())
    {
      ADD_FAILURE() << c.Description << " halo=" << halo << ":" << differences;
      ++failures;
    }
  }
}
} // namespace

TEST(SmallIsoComponentChunked, ChunksWithTheirHalosMatchTheReferenceIn3D)
{
  CheckChunkedRandomVolumes<uint8_t, 3>(1, 500);
}

TEST(SmallIsoComponentChunked, ChunksWithTheirHalosMatchTheReferenceIn2D)
{
  CheckChunkedRandomVolumes<float, 2>(20001, 500);
}

TEST(SmallIsoComponentChunked, ChunksWithTheirHalosMatchTheReferenceForDoubleWithNaN)
{
  CheckChunkedRandomVolumes<double, 3>(30001, 300);
}

TEST(SmallIsoComponentChunked, AHaloOneVoxelThinnerThanTheBoundGoesWrong)
{
  // Small K on volumes of random noise, so that components reach across the chunks' faces.
  unsigned int wrong = 0;
  for (uint32_t seed = 1; seed <= 300; ++seed)
  {
    RandomSource           random(seed);
    RandomCase<uint8_t, 3> c;
    c.Size = { 12, 12, 12 };
    for (SizeValueType v = 0; v < 12 * 12 * 12; ++v)
    {
      c.Values.push_back(random.Chance(0.5) ? 255 : 0);
    }
    c.Input = MakeImage<uint8_t, 3>(c.Size, c.Values);
    c.Settings.IsoValue = 127.5;
    c.Settings.MaximumComponentSize = static_cast<SizeValueType>(random.Between(2, 6));
    c.Settings.Side = seed % 2 == 0 ? SideEnum::Both : SideEnum::Above;
    c.Settings.FullyConnected = false;
    const uint64_t halo = SmallIsoComponentDetail::BoxHalo(c.Settings.MaximumComponentSize, c.Settings.Side);
    wrong += ChunkedDifferences(c, halo - 1, random).empty() ? 0 : 1;
  }
  EXPECT_GT(wrong, 0u);
}
