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
// Block summaries against the brute-force reference: random volumes are cut into random grids of
// boxes, each box is labelled on its own (by a voxel flood fill written here, or by the module's
// run labelling through SummarizeLabeling()), and the summaries are merged in random orders; the
// statistics and every voxel's fate must be the reference's.

#include "itkSmallIsoComponentBlockSummary.h"
#include "itkSmallIsoComponentRunSummary.h"
#include "itkSmallIsoComponentThreshold.h"
#include "itkSmallIsoComponentTestUtilities.h"

#include "gtest/gtest.h"

#include <deque>

namespace
{
using namespace itk;
using namespace itk::SmallIsoComponentTest;
using Summary = itk::SmallIsoComponentDetail::BlockSummary;
using State = Summary::State;
using Box = std::array<std::array<uint64_t, 3>, 2>;

/** A volume seen as 3-D (a 2-D image has depth 1), with each voxel's side. */
struct Volume
{
  std::array<uint64_t, 3> Size{ 1, 1, 1 };
  std::vector<uint8_t>    Above;

  uint64_t
  Index(uint64_t x, uint64_t y, uint64_t z) const
  {
    return x + Size[0] * (y + Size[1] * z);
  }
};

/** Where a box's component stands: its node in a summary while undecided, then its fates. */
struct Track
{
  State             AbovePass{ State::Open };
  State             BelowPass{ State::Open };
  std::size_t       SummaryId{ 0 };
  Summary::NodeType Node{ Summary::NoNode };
};

void
Follow(Track & track, const Summary::Resolution & resolution, std::size_t summaryId)
{
  if (track.AbovePass == State::Open)
  {
    track.AbovePass = resolution.AbovePass;
  }
  track.BelowPass = resolution.BelowPass;
  track.Node = resolution.Node;
  track.SummaryId = summaryId;
}

/** A box labelled by flood fill: the component of each voxel, and the summary built from it. */
struct LabelledBox
{
  Box                   Bounds;
  std::vector<uint32_t> Label; // per voxel of the box
  std::vector<Track>    Tracks;
};

LabelledBox
LabelBox(const Volume &                                  volume,
         const Box &                                     box,
         const SmallIsoComponentDetail::ComponentRules & rules,
         Summary &                                       summary)
{
  LabelledBox labelled;
  labelled.Bounds = box;
  std::array<uint64_t, 3> extent;
  for (unsigned int a = 0; a < 3; ++a)
  {
    extent[a] = box[1][a] - box[0][a];
  }
  const uint64_t voxels = extent[0] * extent[1] * extent[2];
  const auto     sideAt = [&](uint64_t i) {
    const uint64_t x = i % extent[0];
    const uint64_t y = (i / extent[0]) % extent[1];
    const uint64_t z = i / (extent[0] * extent[1]);
    return volume.Above[volume.Index(box[0][0] + x, box[0][1] + y, box[0][2] + z)];
  };
  constexpr uint32_t None = 0xFFFFFFFFu;
  labelled.Label.assign(voxels, None);
  std::vector<uint64_t> sizes;
  std::vector<uint8_t>  sides;
  const int             reach = 1;
  const auto            neighbors = [&](uint64_t i, auto && visit) {
    const auto x = static_cast<int64_t>(i % extent[0]);
    const auto y = static_cast<int64_t>((i / extent[0]) % extent[1]);
    const auto z = static_cast<int64_t>(i / (extent[0] * extent[1]));
    for (int dz = -reach; dz <= reach; ++dz)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx)
        {
          const int moved = (dx != 0) + (dy != 0) + (dz != 0);
          if (moved == 0 || (!rules.FullyConnected && moved > 1))
          {
            continue;
          }
          const int64_t nx = x + dx, ny = y + dy, nz = z + dz;
          if (nx < 0 || ny < 0 || nz < 0 || nx >= static_cast<int64_t>(extent[0]) ||
              ny >= static_cast<int64_t>(extent[1]) || nz >= static_cast<int64_t>(extent[2]))
          {
            continue;
          }
          visit(
            static_cast<uint64_t>(nx + static_cast<int64_t>(extent[0]) * (ny + static_cast<int64_t>(extent[1]) * nz)));
        }
  };
  for (uint64_t seed = 0; seed < voxels; ++seed)
  {
    if (labelled.Label[seed] != None)
    {
      continue;
    }
    const auto           component = static_cast<uint32_t>(sizes.size());
    const uint8_t        side = sideAt(seed);
    std::deque<uint64_t> queue{ seed };
    labelled.Label[seed] = component;
    uint64_t size = 0;
    while (!queue.empty())
    {
      const uint64_t i = queue.front();
      queue.pop_front();
      ++size;
      neighbors(i, [&](uint64_t j) {
        if (labelled.Label[j] == None && sideAt(j) == side)
        {
          labelled.Label[j] = component;
          queue.push_back(j);
        }
      });
    }
    sizes.push_back(size);
    sides.push_back(side);
  }
  for (std::size_t c = 0; c < sizes.size(); ++c)
  {
    summary.AddComponent(sides[c] != 0, sizes[c]);
  }
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const unsigned int u = axis == 0 ? 1 : 0;
    const unsigned int v = axis == 2 ? 1 : 2;
    for (const bool upper : { false, true })
    {
      if (!summary.HasFace(axis, upper))
      {
        continue;
      }
      std::vector<Summary::NodeType> layer;
      for (uint64_t j = 0; j < extent[v]; ++j)
      {
        for (uint64_t i = 0; i < extent[u]; ++i)
        {
          std::array<uint64_t, 3> c{};
          c[axis] = upper ? extent[axis] - 1 : 0;
          c[u] = i;
          c[v] = j;
          layer.push_back(labelled.Label[c[0] + extent[0] * (c[1] + extent[1] * c[2])]);
        }
      }
      summary.SetFaceLayer(axis, upper, std::move(layer));
    }
  }
  for (uint64_t i = 0; i < voxels; ++i)
  {
    const uint32_t a = labelled.Label[i];
    if (sides[a] && summary.NeedsTouching(sizes[a]))
    {
      neighbors(i, [&](uint64_t j) {
        if (!sides[labelled.Label[j]])
        {
          summary.AddTouching(a, labelled.Label[j]);
        }
      });
    }
  }
  return labelled;
}

/** The same box labelled by the module's run labelling, its summary made by SummarizeLabeling(). */
template <typename TPixel>
LabelledBox
LabelBoxWithRuns(const Volume &                                  volume,
                 const std::vector<TPixel> &                     values,
                 double                                          isoValue,
                 const Box &                                     box,
                 const SmallIsoComponentDetail::ComponentRules & rules,
                 Summary &                                       summary)
{
  LabelledBox labelled;
  labelled.Bounds = box;
  Summary::IndexType extent;
  for (unsigned int a = 0; a < 3; ++a)
  {
    extent[a] = box[1][a] - box[0][a];
  }
  std::vector<TPixel> boxValues;
  for (uint64_t z = box[0][2]; z < box[1][2]; ++z)
    for (uint64_t y = box[0][1]; y < box[1][1]; ++y)
      for (uint64_t x = box[0][0]; x < box[1][0]; ++x)
      {
        boxValues.push_back(values[volume.Index(x, y, z)]);
      }
  auto                                 threader = MultiThreaderBase::New();
  SmallIsoComponentDetail::RunLabeling labeling;
  SmallIsoComponentDetail::LabelBox(boxValues.data(),
                                    extent,
                                    SmallIsoComponentDetail::RunEncoder<TPixel>(isoValue),
                                    rules.FullyConnected,
                                    rules.MaximumComponentSize,
                                    threader,
                                    1,
                                    labeling);
  summary = SmallIsoComponentDetail::SummarizeLabeling(labeling, extent, volume.Size, box[0], rules);
  labelled.Label.resize(boxValues.size());
  const auto table = labeling.GetRunTable();
  for (SizeValueType line = 0; line < labeling.GetNumberOfLines(); ++line)
  {
    for (SizeValueType run = table.LineBegin[line]; run < table.LineBegin[line + 1]; ++run)
    {
      for (SizeValueType x = table.Start[run]; x < table.End(run, line); ++x)
      {
        labelled.Label[line * extent[0] + x] = table.Component[run];
      }
    }
  }
  return labelled;
}

/** Cuts [0, extent) at random places. */
std::vector<uint64_t>
RandomCuts(RandomSource & random, uint64_t extent)
{
  std::vector<uint64_t> cuts{ 0 };
  const auto pieces = static_cast<uint64_t>(random.Between(1, static_cast<int>(std::min<uint64_t>(extent, 5))));
  for (uint64_t p = 1; p < pieces; ++p)
  {
    cuts.push_back(static_cast<uint64_t>(random.Between(1, static_cast<int>(extent - 1))));
  }
  cuts.push_back(extent);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  return cuts;
}

template <typename TPixel, unsigned int VDimension>
void
CheckSummariesOfRandomVolumes(uint32_t firstSeed, unsigned int numberOfVolumes, bool withRuns)
{
  unsigned int failures = 0;
  unsigned int withRemovedBelow = 0;
  unsigned int withManyBoxes = 0;
  for (uint32_t seed = firstSeed; seed < firstSeed + numberOfVolumes && failures < 5; ++seed)
  {
    const auto c = MakeRandomCase<TPixel, TPixel, VDimension>(seed);
    const auto expected = Reference::Run<TPixel>(c.Input.GetPointer(), c.Settings);
    const SmallIsoComponentDetail::Threshold<TPixel> threshold(c.Settings.IsoValue);
    Volume                                           volume;
    for (unsigned int a = 0; a < VDimension; ++a)
    {
      volume.Size[a] = c.Size[a];
    }
    for (const TPixel value : c.Values)
    {
      volume.Above.push_back(threshold.IsAbove(value) ? 1 : 0);
    }
    SmallIsoComponentDetail::ComponentRules rules;
    rules.MaximumComponentSize = c.Settings.MaximumComponentSize;
    rules.Side = c.Settings.Side;
    rules.FullyConnected = c.Settings.FullyConnected;
    rules.AnyAbove = threshold.AnyAbove();
    rules.AnyBelow = threshold.AnyBelow();

    RandomSource                         random(seed * 7919u + 13u);
    std::array<std::vector<uint64_t>, 3> cuts;
    for (unsigned int a = 0; a < 3; ++a)
    {
      cuts[a] = RandomCuts(random, volume.Size[a]);
    }
    // The grid of boxes, each labelled; summaries[id], the live ones in a grid of ids.
    std::vector<Summary>     summaries;
    std::vector<LabelledBox> boxes;
    std::array<uint64_t, 3>  count;
    for (unsigned int a = 0; a < 3; ++a)
    {
      count[a] = cuts[a].size() - 1;
    }
    std::vector<std::size_t> grid;
    for (uint64_t k = 0; k < count[2]; ++k)
      for (uint64_t j = 0; j < count[1]; ++j)
        for (uint64_t i = 0; i < count[0]; ++i)
        {
          const Box box{ std::array<uint64_t, 3>{ cuts[0][i], cuts[1][j], cuts[2][k] },
                         std::array<uint64_t, 3>{ cuts[0][i + 1], cuts[1][j + 1], cuts[2][k + 1] } };
          Summary   summary(volume.Size, box[0], box[1], rules);
          boxes.push_back(withRuns ? LabelBoxWithRuns(volume, c.Values, c.Settings.IsoValue, box, rules, summary)
                                   : LabelBox(volume, box, rules, summary));
          std::vector<Summary::Resolution> resolutions;
          summary.Settle(&resolutions);
          auto & tracks = boxes.back().Tracks;
          tracks.resize(resolutions.size());
          for (std::size_t n = 0; n < resolutions.size(); ++n)
          {
            Follow(tracks[n], resolutions[n], summaries.size());
          }
          grid.push_back(summaries.size());
          summaries.push_back(std::move(summary));
        }
    withManyBoxes += grid.size() > 1 ? 1 : 0;
    // Merge along the axes in a random order, adjacent pairs in random order along each.
    std::array<unsigned int, 3> order{ 0, 1, 2 };
    for (unsigned int a = 2; a > 0; --a)
    {
      std::swap(order[a], order[static_cast<unsigned int>(random.Between(0, static_cast<int>(a)))]);
    }
    const auto mergeInto = [&](std::size_t lowId, std::size_t highId) {
      if (random.Chance(0.3))
      {
        const auto bytes = summaries[lowId].Serialize();
        summaries[lowId] = Summary::Deserialize(bytes.data(), bytes.size());
      }
      std::vector<Summary::Resolution> low, high;
      const std::size_t                id = summaries.size();
      summaries.push_back(Summary::Merge(summaries[lowId], summaries[highId], &low, &high));
      for (auto & labelled : boxes)
      {
        for (auto & track : labelled.Tracks)
        {
          if (track.Node == Summary::NoNode)
          {
            continue;
          }
          if (track.SummaryId == lowId)
          {
            Follow(track, low[track.Node], id);
          }
          else if (track.SummaryId == highId)
          {
            Follow(track, high[track.Node], id);
          }
        }
      }
      return id;
    };
    for (const unsigned int axis : order)
    {
      std::array<uint64_t, 3> stride{ 1, count[0], count[0] * count[1] };
      std::array<uint64_t, 3> newCount = count;
      newCount[axis] = 1;
      std::vector<std::size_t> newGrid(newCount[0] * newCount[1] * newCount[2]);
      for (uint64_t k = 0; k < newCount[2]; ++k)
        for (uint64_t j = 0; j < newCount[1]; ++j)
          for (uint64_t i = 0; i < newCount[0]; ++i)
          {
            std::vector<std::size_t> line;
            for (uint64_t t = 0; t < count[axis]; ++t)
            {
              std::array<uint64_t, 3> at{ i, j, k };
              at[axis] = t;
              line.push_back(grid[at[0] * stride[0] + at[1] * stride[1] + at[2] * stride[2]]);
            }
            while (line.size() > 1)
            {
              const auto p = static_cast<std::size_t>(random.Between(0, static_cast<int>(line.size()) - 2));
              line[p] = mergeInto(line[p], line[p + 1]);
              line.erase(line.begin() + static_cast<std::ptrdiff_t>(p) + 1);
            }
            newGrid[i + newCount[0] * (j + newCount[1] * k)] = line[0];
          }
      grid.swap(newGrid);
      count = newCount;
    }
    const Summary &    whole = summaries[grid[0]];
    const auto &       tally = whole.GetTally();
    std::ostringstream differences;
    const auto         compareSide =
      [&](const char * name, const SmallIsoComponentDetail::SideTally & got, const Reference::SideStatistics & want) {
        if (got.GetComponents() != want.Components || got.GetRemovedComponents() != want.RemovedComponents ||
            got.GetRemovedVoxels() != want.RemovedVoxels)
        {
          differences << " " << name << ": components " << got.GetComponents() << "/" << want.Components << " removed "
                      << got.GetRemovedComponents() << "/" << want.RemovedComponents << " voxels "
                      << got.GetRemovedVoxels() << "/" << want.RemovedVoxels;
        }
        const auto histogram = got.GetHistogram();
        if (Reference::HistogramType(histogram.begin(), histogram.end()) != want.Histogram)
        {
          differences << " " << name << " histogram differs";
        }
      };
    compareSide("above", tally.Above, expected.Above);
    compareSide("below", tally.Below, expected.Below);
    if (tally.ModifiedVoxels != expected.ModifiedVoxels)
    {
      differences << " modified " << tally.ModifiedVoxels << "/" << expected.ModifiedVoxels;
    }
    if (tally.UnrepairableVoxels + expected.FallbackVoxels != expected.UnrepairableVoxels)
    {
      differences << " unrepairable " << tally.UnrepairableVoxels << "+" << expected.FallbackVoxels << "/"
                  << expected.UnrepairableVoxels;
    }
    if (whole.GetNumberOfNodes() != 0)
    {
      differences << " " << whole.GetNumberOfNodes() << " nodes left in the whole image's summary";
    }
    // Every voxel's fate is the reference mask.
    uint64_t wrongFates = 0;
    for (const auto & labelled : boxes)
    {
      const Box &    box = labelled.Bounds;
      const uint64_t ex = box[1][0] - box[0][0];
      const uint64_t ey = box[1][1] - box[0][1];
      for (uint64_t i = 0; i < labelled.Label.size(); ++i)
      {
        const Track &  track = labelled.Tracks[labelled.Label[i]];
        const uint8_t  fate = track.BelowPass == State::Removed ? 2 : (track.AbovePass == State::Removed ? 1 : 0);
        const bool     settled = track.AbovePass != State::Open && track.BelowPass != State::Open;
        const uint64_t x = box[0][0] + i % ex;
        const uint64_t y = box[0][1] + (i / ex) % ey;
        const uint64_t z = box[0][2] + i / (ex * ey);
        wrongFates += !settled || fate != expected.Mask[volume.Index(x, y, z)] ? 1 : 0;
      }
    }
    if (wrongFates > 0)
    {
      differences << " " << wrongFates << " voxels with a wrong fate";
    }
    if (!differences.str().empty())
    {
      ADD_FAILURE() << c.Description << " boxes=" << boxes.size() << ":" << differences.str();
      ++failures;
    }
    withRemovedBelow += expected.Below.RemovedComponents > 0 && c.Settings.Side == SideEnum::Both ? 1 : 0;
  }
  std::cout << numberOfVolumes << " volumes, " << withManyBoxes << " cut into several boxes, " << withRemovedBelow
            << " with bubbles removed after specks (side Both)" << std::endl;
  EXPECT_GT(withManyBoxes, numberOfVolumes / 2);
  EXPECT_GT(withRemovedBelow, numberOfVolumes / 20);
}
} // namespace

TEST(SmallIsoComponentBlockSummary, MergedSummariesOf3DVolumesMatchTheReference)
{
  CheckSummariesOfRandomVolumes<uint8_t, 3>(1, 400, false);
}

TEST(SmallIsoComponentBlockSummary, SummariesOfRunLabelledBoxesMatchTheReference)
{
  CheckSummariesOfRandomVolumes<uint8_t, 3>(3001, 400, true);
  CheckSummariesOfRandomVolumes<float, 2>(4001, 300, true);
}

TEST(SmallIsoComponentBlockSummary, MergedSummariesOf2DVolumesMatchTheReference)
{
  CheckSummariesOfRandomVolumes<float, 2>(1001, 400, false);
}

TEST(SmallIsoComponentBlockSummary, MergedSummariesOfInt16VolumesMatchTheReference)
{
  CheckSummariesOfRandomVolumes<int16_t, 3>(2001, 200, false);
}

TEST(SmallIsoComponentBlockSummary, DeserializeRefusesDamagedData)
{
  SmallIsoComponentDetail::ComponentRules rules;
  Summary                                 summary({ 4, 4, 4 }, { 0, 0, 0 }, { 4, 4, 2 }, rules);
  summary.AddComponent(true, 3);
  summary.SetFaceLayer(2, true, std::vector<Summary::NodeType>(16, 0));
  summary.Settle();
  auto          bytes = summary.Serialize();
  const Summary back = Summary::Deserialize(bytes.data(), bytes.size());
  EXPECT_EQ(back.GetNumberOfNodes(), 1u);
  EXPECT_THROW(Summary::Deserialize(bytes.data(), bytes.size() - 1), itk::ExceptionObject);
  bytes[0] ^= 0xFF;
  EXPECT_THROW(Summary::Deserialize(bytes.data(), bytes.size()), itk::ExceptionObject);
}
