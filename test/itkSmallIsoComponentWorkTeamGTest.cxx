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

// The work team that takes the filter's parallel loops: every item exactly once, the
// helpers really take part, a failing item's exception reaches the caller only after the
// other items in progress have ended, a busy pool (helpers that never start during the
// team's life) costs nothing but speed, a helper that misses the first loop stays out,
// and other threaders get the loops as before.

#include "itkSmallIsoComponentWorkTeam.h"
#include "itkPlatformMultiThreader.h"
#include "itkPoolMultiThreader.h"
#include "itkThreadPool.h"
#include "gtest/gtest.h"

#include <atomic>
#include <chrono>
#include <future>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace
{
using Team = itk::SmallIsoComponentDetail::WorkTeam;

/** Runs loops of random sizes and checks that each visits every item exactly once. */
void
CheckEveryItemOnce(Team & team, unsigned int loops, std::mt19937 & random)
{
  std::uniform_int_distribution<unsigned int> itemCount(0, 3000);
  for (unsigned int loop = 0; loop < loops; ++loop)
  {
    const unsigned int                     items = loop % 7 == 0 ? loop % 3 : itemCount(random);
    std::vector<std::atomic<unsigned int>> visits(items);
    for (auto & v : visits)
    {
      v = 0;
    }
    // Some items take a while, so that a loop that returned before its last items ended
    // would be seen.
    team.ForEach(items, [&](itk::SizeValueType item) {
      if (item % 97 == 1)
      {
        std::this_thread::sleep_for(std::chrono::microseconds(50));
      }
      ++visits[item];
    });
    for (unsigned int item = 0; item < items; ++item)
    {
      ASSERT_EQ(visits[item].load(), 1u) << "loop " << loop << " of " << items << " items, item " << item;
    }
  }
}

/** The threads that ran an item, recorded from any of them. */
class ThreadsSeen
{
public:
  void
  Record()
  {
    const std::lock_guard<std::mutex> lock(m_Mutex);
    m_Threads.insert(std::this_thread::get_id());
  }

  /** Read once the loops have ended. */
  const std::set<std::thread::id> &
  Get() const
  {
    return m_Threads;
  }

private:
  std::mutex                m_Mutex;
  std::set<std::thread::id> m_Threads;
};

itk::PoolMultiThreader::Pointer
PoolThreader(unsigned int workUnits)
{
  auto threader = itk::PoolMultiThreader::New();
  threader->SetMaximumNumberOfThreads(std::max(2u, workUnits));
  threader->SetNumberOfWorkUnits(workUnits);
  return threader;
}

/** Holds every thread of ITK's pool with a waiting task until Release() (or the end of
 * its life), so that helpers asked for meanwhile cannot start. */
class PoolHold
{
public:
  PoolHold()
    : m_Released(m_Release.get_future().share())
  {
    itk::ThreadPool * pool = itk::ThreadPool::GetInstance();
    m_Threads = pool->GetMaximumNumberOfThreads();
    for (unsigned int t = 0; t < m_Threads; ++t)
    {
      m_Holders.push_back(pool->AddWork([this] {
        ++m_Holding;
        m_Released.wait();
      }));
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!this->HoldsAll() && std::chrono::steady_clock::now() < deadline)
    {
      std::this_thread::yield();
    }
  }
  ~PoolHold() { this->Release(); }
  PoolHold(const PoolHold &) = delete;
  PoolHold &
  operator=(const PoolHold &) = delete;

  /** Whether every pool thread is held (within a minute of the start). */
  bool
  HoldsAll() const
  {
    return m_Holding.load() == m_Threads;
  }

  /** Frees the pool's threads and waits for the holding tasks to end. */
  void
  Release()
  {
    if (m_Holders.empty())
    {
      return;
    }
    m_Release.set_value();
    for (auto & holder : m_Holders)
    {
      holder.get();
    }
    m_Holders.clear();
  }

private:
  std::promise<void>             m_Release;
  std::shared_future<void>       m_Released;
  std::atomic<unsigned int>      m_Holding{ 0 };
  unsigned int                   m_Threads{ 0 };
  std::vector<std::future<void>> m_Holders;
};
} // namespace

TEST(SmallIsoComponentWorkTeam, EveryItemOnceForAnyNumberOfWorkUnits)
{
  std::mt19937 random(7);
  for (const unsigned int workUnits : { 1u, 2u, 3u, 8u })
  {
    auto threader = PoolThreader(workUnits);
    Team team(threader, workUnits);
    EXPECT_EQ(team.GetNumberOfHelpers() + 1, team.GetNumberOfWorkUnits());
    EXPECT_LE(team.GetNumberOfWorkUnits(), workUnits);
    const unsigned int cores = std::thread::hardware_concurrency();
    if (cores > 1)
    {
      EXPECT_LE(team.GetNumberOfHelpers(), cores - 1) << "more spinning helpers than other cores";
    }
    if (workUnits > 1)
    {
      EXPECT_GE(team.GetNumberOfHelpers(), 1u);
    }
    CheckEveryItemOnce(team, 300, random);
  }
}

TEST(SmallIsoComponentWorkTeam, HelpersTakePart)
{
  auto threader = PoolThreader(2);
  Team team(threader, 2);
  ASSERT_EQ(team.GetNumberOfHelpers(), 1u);
  // Item 0 waits until another item runs on another thread: that can only be a helper.
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<bool>     helperSeen{ false };
  ThreadsSeen           threads;
  team.ForEach(64, [&](itk::SizeValueType item) {
    threads.Record();
    if (std::this_thread::get_id() != caller)
    {
      helperSeen = true;
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (item == 0 && !helperSeen && std::chrono::steady_clock::now() < deadline)
    {
      std::this_thread::yield();
    }
  });
  EXPECT_TRUE(helperSeen.load()) << "no item ran on a helper within 10 s";
  EXPECT_EQ(threads.Get().size(), 2u);
}

TEST(SmallIsoComponentWorkTeam, ExceptionAfterTheItemsInProgressEnd)
{
  auto                      threader = PoolThreader(2);
  Team                      team(threader, 2);
  std::atomic<unsigned int> inside{ 0 };
  std::atomic<unsigned int> started{ 0 };
  try
  {
    team.ForEach(1000, [&](itk::SizeValueType item) {
      ++inside;
      ++started;
      if (item == 10)
      {
        --inside;
        throw std::runtime_error("item 10 failed");
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      --inside;
    });
    FAIL() << "ForEach() did not rethrow the item's exception";
  }
  catch (const std::runtime_error & error)
  {
    EXPECT_STREQ(error.what(), "item 10 failed");
    EXPECT_EQ(inside.load(), 0u) << "an item was still running when ForEach() threw";
    EXPECT_LT(started.load(), 1000u) << "the items after the failure were not skipped";
  }
  // The team still works after a failed loop.
  std::mt19937 random(11);
  CheckEveryItemOnce(team, 50, random);
}

TEST(SmallIsoComponentWorkTeam, BusyPoolDoesNotHoldUpTheCaller)
{
  // Every pool thread is held by a task until the team has ended: its helpers cannot
  // start, so the calling thread does every item, then they start late and leave.
  auto     threader = PoolThreader(2);
  PoolHold hold;
  ASSERT_TRUE(hold.HoldsAll());
  ThreadsSeen threads;
  {
    Team team(threader, 2);
    for (unsigned int loop = 0; loop < 20; ++loop)
    {
      std::vector<std::atomic<unsigned int>> visits(500);
      for (auto & v : visits)
      {
        v = 0;
      }
      team.ForEach(visits.size(), [&](itk::SizeValueType item) {
        ++visits[item];
        threads.Record();
      });
      for (const auto & v : visits)
      {
        ASSERT_EQ(v.load(), 1u);
      }
    }
  }
  EXPECT_EQ(threads.Get().size(), 1u);
  EXPECT_EQ(*threads.Get().begin(), std::this_thread::get_id());
  hold.Release();
  // The late helpers found the team gone and left; a new team gets helpers again.
  auto         threader2 = PoolThreader(2);
  Team         team(threader2, 2);
  std::mt19937 random(13);
  CheckEveryItemOnce(team, 20, random);
}

TEST(SmallIsoComponentWorkTeam, HelperLateForTheFirstLoopStaysOut)
{
  // The pool's threads are held through the team's first loop, then freed: the helper
  // that starts afterwards must not join the second loop.
  auto     threader = PoolThreader(2);
  PoolHold hold;
  ASSERT_TRUE(hold.HoldsAll());
  Team team(threader, 2);
  ASSERT_EQ(team.GetNumberOfHelpers(), 1u);
  ThreadsSeen threads;
  team.ForEach(100, [&](itk::SizeValueType) { threads.Record(); });
  hold.Release();
  // The pool is free now: a helper that joined would take items of this slow loop.
  team.ForEach(50, [&](itk::SizeValueType) {
    threads.Record();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  });
  EXPECT_EQ(threads.Get().size(), 1u) << "a helper that started after the first loop took items";
}

TEST(SmallIsoComponentWorkTeam, OtherThreadersTakeTheLoops)
{
  auto threader = itk::PlatformMultiThreader::New();
  threader->SetNumberOfWorkUnits(3);
  Team team(threader, 3);
  EXPECT_EQ(team.GetNumberOfHelpers(), 0u);
  EXPECT_EQ(team.GetNumberOfWorkUnits(), 3u);
  std::mt19937 random(17);
  CheckEveryItemOnce(team, 30, random);
  EXPECT_THROW(team.ForEach(100,
                            [](itk::SizeValueType item) {
                              if (item == 50)
                              {
                                throw std::runtime_error("item 50 failed");
                              }
                            }),
               std::runtime_error);
}

TEST(SmallIsoComponentWorkTeam, CheapLoopsAreSharedFromFewerItemsWhenHelpersAreAwake)
{
  // Without helpers a loop of cheap items stays on the calling thread below 2048 items;
  // from there it is cut into 32 chunks per work unit, at most one per item.
  auto platform = itk::PlatformMultiThreader::New();
  platform->SetNumberOfWorkUnits(3);
  const Team withoutHelpers(platform, 3);
  EXPECT_EQ(withoutHelpers.GetNumberOfChunks(0), 1u);
  EXPECT_EQ(withoutHelpers.GetNumberOfChunks(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShare - 1), 1u);
  EXPECT_EQ(withoutHelpers.GetNumberOfChunks(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShare),
            3 * itk::SmallIsoComponentDetail::Tuning::ChunksPerWorkUnit);
  const Team alone(platform, 1);
  EXPECT_EQ(alone.GetNumberOfChunks(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShare),
            itk::SmallIsoComponentDetail::Tuning::ChunksPerWorkUnit);
  // Loops with state per part: one part per work unit where the loop is shared, else one.
  EXPECT_EQ(withoutHelpers.GetNumberOfParts(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShare - 1), 1u);
  EXPECT_EQ(withoutHelpers.GetNumberOfParts(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShare), 3u);
  EXPECT_EQ(alone.GetNumberOfParts(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShare), 1u);
  // The parts cover the items in order, without gaps or overlaps, and differ by one at most.
  for (const itk::SizeValueType items : { 0u, 1u, 7u, 1000u })
  {
    for (const itk::SizeValueType parts : { 1u, 2u, 3u })
    {
      EXPECT_EQ(Team::PartBegin(items, 0, parts), 0u);
      EXPECT_EQ(Team::PartBegin(items, parts, parts), items);
      for (itk::SizeValueType part = 0; part < parts; ++part)
      {
        const itk::SizeValueType size = Team::PartBegin(items, part + 1, parts) - Team::PartBegin(items, part, parts);
        EXPECT_LE(size, items / parts + 1);
        EXPECT_GE(size, items / parts);
      }
    }
  }

  // Helpers are awake already: loops are shared from 256 items.
  auto       pool = PoolThreader(2);
  const Team withHelpers(pool, 2);
  if (withHelpers.GetNumberOfHelpers() == 0)
  {
    GTEST_SKIP() << "one core: the team has no helpers";
  }
  EXPECT_EQ(withHelpers.GetNumberOfChunks(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShareWithHelpers - 1),
            1u);
  EXPECT_EQ(withHelpers.GetNumberOfChunks(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShareWithHelpers),
            std::min<itk::SizeValueType>(itk::SmallIsoComponentDetail::Tuning::MinimumItemsToShareWithHelpers,
                                         2 * itk::SmallIsoComponentDetail::Tuning::ChunksPerWorkUnit));
  EXPECT_EQ(withHelpers.GetNumberOfChunks(40), 1u);
}
