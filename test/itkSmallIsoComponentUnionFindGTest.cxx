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

// The engine's union-find against a flood fill of the same joins: the same groups, each with
// its smallest member as root, whichever way the joins are made (Rem's splicing, joins that add
// up at the roots, joins from several threads at once).

#include "itkSmallIsoComponentUnionFind.h"
#include "gtest/gtest.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <random>
#include <thread>
#include <utility>
#include <vector>

namespace
{
using namespace itk::SmallIsoComponentDetail;
using Pairs = std::vector<std::pair<uint32_t, uint32_t>>;

/** Each node's group as its smallest member, by flood fill over the pairs. */
std::vector<uint32_t>
SmallestOfGroups(uint32_t nodes, const Pairs & pairs)
{
  std::vector<std::vector<uint32_t>> neighbours(nodes);
  for (const auto & pair : pairs)
  {
    neighbours[pair.first].push_back(pair.second);
    neighbours[pair.second].push_back(pair.first);
  }
  std::vector<uint32_t> smallest(nodes, nodes);
  for (uint32_t start = 0; start < nodes; ++start)
  {
    if (smallest[start] != nodes)
    {
      continue;
    }
    std::vector<uint32_t> stack{ start };
    smallest[start] = start;
    while (!stack.empty())
    {
      const uint32_t node = stack.back();
      stack.pop_back();
      for (uint32_t next : neighbours[node])
      {
        if (smallest[next] == nodes)
        {
          smallest[next] = start;
          stack.push_back(next);
        }
      }
    }
  }
  return smallest;
}

Pairs
RandomPairs(std::mt19937 & random, uint32_t nodes)
{
  // Near neighbours mostly, as runs are joined, and far ones now and then.
  Pairs                                   pairs(std::uniform_int_distribution<uint32_t>(0, 2 * nodes)(random));
  std::uniform_int_distribution<uint32_t> any(0, nodes - 1);
  for (auto & pair : pairs)
  {
    pair.first = any(random);
    pair.second = random() % 4 == 0 ? any(random) : std::min<uint32_t>(nodes - 1, pair.first + 1 + random() % 3);
  }
  return pairs;
}

TEST(SmallIsoComponentUnionFind, EveryWayOfJoiningGivesTheFloodFillsGroupsRootedAtTheirSmallestMember)
{
  std::mt19937 random(41);
  for (int trial = 0; trial < 2000; ++trial)
  {
    const uint32_t              nodes = 1 + random() % 200;
    const Pairs                 pairs = RandomPairs(random, nodes);
    const std::vector<uint32_t> expected = SmallestOfGroups(nodes, pairs);

    std::vector<uint32_t> spliced(nodes);
    std::vector<uint32_t> rooted(nodes);
    std::vector<uint32_t> size(nodes, 1);
    for (uint32_t node = 0; node < nodes; ++node)
    {
      spliced[node] = rooted[node] = node;
    }
    for (auto [a, b] : pairs)
    {
      Join(spliced.data(), a, b);
      if (JoinRoots(rooted.data(), a, b))
      {
        ASSERT_LT(a, b);
        size[a] += size[b];
      }
    }
    std::vector<uint32_t> expectedSize(nodes, 0);
    for (uint32_t node = 0; node < nodes; ++node)
    {
      ASSERT_EQ(FindRoot(spliced.data(), node), expected[node]) << "trial " << trial;
      ASSERT_EQ(FindRoot(rooted.data(), node), expected[node]) << "trial " << trial;
      ++expectedSize[expected[node]];
    }
    for (uint32_t node = 0; node < nodes; ++node)
    {
      if (expected[node] == node)
      {
        ASSERT_EQ(size[node], expectedSize[node]) << "trial " << trial;
      }
    }
  }
}

TEST(SmallIsoComponentUnionFind, JoinsFromSeveralThreadsAtOnceGiveTheFloodFillsGroups)
{
  std::mt19937 random(42);
  for (int trial = 0; trial < 200; ++trial)
  {
    const uint32_t                           nodes = 1 + random() % 5000;
    const Pairs                              pairs = RandomPairs(random, nodes);
    std::unique_ptr<std::atomic<uint32_t>[]> parent(new std::atomic<uint32_t>[nodes]);
    for (uint32_t node = 0; node < nodes; ++node)
    {
      parent[node].store(node);
    }
    const unsigned int       threads = 4;
    std::vector<std::thread> team;
    for (unsigned int t = 0; t < threads; ++t)
    {
      team.emplace_back([&, t] {
        for (std::size_t p = t; p < pairs.size(); p += threads)
        {
          JoinShared(parent.get(), pairs[p].first, pairs[p].second);
        }
      });
    }
    for (auto & thread : team)
    {
      thread.join();
    }
    const std::vector<uint32_t> expected = SmallestOfGroups(nodes, pairs);
    for (uint32_t node = 0; node < nodes; ++node)
    {
      ASSERT_EQ(FindRootShared(parent.get(), node), expected[node]) << "trial " << trial;
    }
  }
}
} // namespace
