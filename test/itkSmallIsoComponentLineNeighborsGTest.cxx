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

// The neighbouring lines of every line, in 1-D to 4-D images with either connectivity,
// against the lines whose coordinates differ by at most one along each axis (along one
// axis only with face connectivity), whether the walk steps through the lines in order or
// jumps to them.

#include "itkSmallIsoComponentLineNeighbors.h"
#include "itkSmallIsoComponentTestUtilities.h"
#include "gtest/gtest.h"

#include <cstdlib>
#include <algorithm>
#include <set>
#include <vector>

namespace
{
using itk::SizeValueType;
using itk::SmallIsoComponentDetail::LineNeighbors;

/** The neighbours of \a line by definition. */
std::multiset<SizeValueType>
NaiveNeighbors(const std::vector<SizeValueType> & size, bool fullyConnected, SizeValueType line, bool earlierOnly)
{
  SizeValueType lines = 1;
  for (unsigned int a = 1; a < size.size(); ++a)
  {
    lines *= size[a];
  }
  const auto coordinatesOf = [&](SizeValueType l) {
    std::vector<SizeValueType> c;
    for (unsigned int a = 1; a < size.size(); ++a)
    {
      c.push_back(l % size[a]);
      l /= size[a];
    }
    return c;
  };
  const auto                   mine = coordinatesOf(line);
  std::multiset<SizeValueType> neighbors;
  for (SizeValueType other = 0; other < lines; ++other)
  {
    const auto   theirs = coordinatesOf(other);
    unsigned int moves = 0;
    bool         near = true;
    for (unsigned int a = 0; a < mine.size(); ++a)
    {
      const auto d = static_cast<long long>(theirs[a]) - static_cast<long long>(mine[a]);
      near = near && std::llabs(d) <= 1;
      moves += d != 0 ? 1 : 0;
    }
    if (near && moves > 0 && (fullyConnected || moves == 1) && (!earlierOnly || other < line))
    {
      neighbors.insert(other);
    }
  }
  return neighbors;
}
} // namespace

TEST(SmallIsoComponentLineNeighbors, EveryNeighbourOnceInOneToFourDimensions)
{
  itk::SmallIsoComponentTest::RandomSource random(5);
  for (unsigned int trial = 0; trial < 120; ++trial)
  {
    const auto                 dimension = static_cast<unsigned int>(1 + trial % 4);
    std::vector<SizeValueType> size;
    for (unsigned int a = 0; a < dimension; ++a)
    {
      size.push_back(static_cast<SizeValueType>(random.Between(1, dimension > 3 ? 4 : 6)));
    }
    SizeValueType lines = 1;
    for (unsigned int a = 1; a < dimension; ++a)
    {
      lines *= size[a];
    }
    for (const bool fullyConnected : { false, true })
    {
      const LineNeighbors     neighbors(size, fullyConnected);
      LineNeighbors::Position walked = neighbors.At(0);
      LineNeighbors::Position jumped;
      SizeValueType           farthestEarlier = 0;
      for (SizeValueType line = 0; line < lines; ++line, neighbors.Next(walked))
      {
        const std::multiset<SizeValueType> earlier = NaiveNeighbors(size, fullyConnected, line, true);
        farthestEarlier = std::max(farthestEarlier, earlier.empty() ? 0 : line - *earlier.begin());
        // Jumps in a random order of lines are checked against the walk in order.
        const SizeValueType jumpLine = static_cast<SizeValueType>(random.Between(0, static_cast<int64_t>(lines) - 1));
        neighbors.MoveTo(jumped, jumpLine);
        for (const bool earlierOnly : { false, true })
        {
          std::multiset<SizeValueType> seenWalking;
          std::multiset<SizeValueType> seenJumping;
          const auto                   collect = [&](const LineNeighbors::Position & position, auto & seen) {
            if (earlierOnly)
            {
              neighbors.ForEachEarlier(position, [&](SizeValueType other) { seen.insert(other); });
            }
            else
            {
              neighbors.ForEachNeighbor(position, [&](SizeValueType other) { seen.insert(other); });
            }
          };
          collect(walked, seenWalking);
          collect(jumped, seenJumping);
          EXPECT_EQ(seenWalking, NaiveNeighbors(size, fullyConnected, line, earlierOnly))
            << "dimension " << dimension << " line " << line << " full " << fullyConnected << " earlier "
            << earlierOnly;
          EXPECT_EQ(seenJumping, NaiveNeighbors(size, fullyConnected, jumpLine, earlierOnly))
            << "dimension " << dimension << " jumped to line " << jumpLine << " full " << fullyConnected;
        }
      }
      // Slab seams and line rings reach back this far: an axis of one line must not count.
      EXPECT_EQ(neighbors.GetFarthestEarlier(), farthestEarlier)
        << "dimension " << dimension << " full " << fullyConnected;
    }
  }
}
