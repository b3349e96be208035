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
#include "itkSmallIsoComponentWorkTeam.h"

#include "itkPoolMultiThreader.h"
#include "itkThreadPool.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#if defined(__x86_64__) || defined(_M_X64) || defined(__i386__) || defined(_M_IX86)
#  include <immintrin.h>
#  define SMALLISO_CPU_PAUSE() _mm_pause()
#else
#  define SMALLISO_CPU_PAUSE() std::this_thread::yield()
#endif

namespace itk
{
namespace SmallIsoComponentDetail
{
namespace
{
using Clock = std::chrono::steady_clock;


/** Spins until done() is true, yielding the core now and then so that a thread it waits
 * for can run on a busy machine. */
template <typename TDone>
void
SpinUntil(TDone && done)
{
  for (unsigned int round = 1; !done(); ++round)
  {
    if (round % 64 == 0)
    {
      std::this_thread::yield();
    }
    else
    {
      SMALLISO_CPU_PAUSE();
    }
  }
}

/** One loop handed to the team. */
struct Job
{
  SizeValueType Items;
  void (*Call)(void *, SizeValueType);
  void *                     Context;
  std::atomic<SizeValueType> Next{ 0 };
  std::atomic<bool>          Failed{ false };
  std::mutex                 ErrorMutex;
  std::exception_ptr         Error;

  /** Takes and handles items until none is left; an exception skips the rest. */
  void
  Work()
  {
    for (SizeValueType item = Next++; item < Items; item = Next++)
    {
      if (!Failed.load(std::memory_order_relaxed))
      {
        try
        {
          Call(Context, item);
        }
        catch (...)
        {
          const std::lock_guard<std::mutex> lock(ErrorMutex);
          if (!Error)
          {
            Error = std::current_exception();
          }
          Failed = true;
        }
      }
    }
  }
};
} // namespace

struct WorkTeam::State
{
  std::mutex              Mutex;
  std::condition_variable Wake;
  std::condition_variable Left;
  // Guarded by Mutex; Quitting mirrors Quit for the helpers' spinning.
  bool Quit{ false };
  // Whether a helper that starts now may still join (see Run()).
  bool              Open{ true };
  unsigned int      Active{ 0 };
  std::atomic<bool> Quitting{ false };
  // Helpers asleep on Wake (changed under Mutex).
  std::atomic<unsigned int> Sleeping{ 0 };
  // Incremented for every loop; the loop is Current while it runs.
  std::atomic<uint64_t> Generation{ 0 };
  std::atomic<Job *>    Current{ nullptr };
  // Helpers that may be looking at Current.
  std::atomic<unsigned int> Busy{ 0 };

  void
  Help()
  {
    {
      const std::lock_guard<std::mutex> lock(Mutex);
      if (Quit || !Open)
      {
        // The team ended, or its first loop did, before this helper started.
        return;
      }
      ++Active;
    }
    uint64_t seen = 0;
    while (true)
    {
      const auto news = [&] { return Quitting.load() || Generation.load() != seen; };
      const auto spinEnd = Clock::now() + Tuning::HelperSpinTime;
      for (unsigned int round = 1; !news(); ++round)
      {
        SMALLISO_CPU_PAUSE();
        if (round % 256 == 0 && Clock::now() > spinEnd)
        {
          std::unique_lock<std::mutex> lock(Mutex);
          ++Sleeping;
          Wake.wait(lock, news);
          --Sleeping;
          break;
        }
      }
      if (Quitting.load())
      {
        break;
      }
      seen = Generation.load();
      ++Busy;
      if (Job * job = Current.load())
      {
        job->Work();
      }
      --Busy;
    }
    const std::lock_guard<std::mutex> lock(Mutex);
    --Active;
    Left.notify_all();
  }
};

WorkTeam::WorkTeam(MultiThreaderBase * threader, unsigned int workUnits)
  : m_Threader(threader)
  , m_NumberOfWorkUnits(std::max(1u, workUnits))
{
  if (workUnits <= 1 || dynamic_cast<PoolMultiThreader *>(threader) == nullptr)
  {
    return;
  }
  ThreadPool * pool = ThreadPool::GetInstance();
  // Helpers wait by spinning for a while: no more of them than the other cores. (Asked
  // once: the C++ library reads it from the system, tens of microseconds per call here.)
  static const unsigned int cores = std::thread::hardware_concurrency();
  m_NumberOfHelpers =
    std::min<unsigned int>(workUnits - 1, std::max<unsigned int>(1, pool->GetMaximumNumberOfThreads()));
  if (cores > 1)
  {
    m_NumberOfHelpers = std::min(m_NumberOfHelpers, cores - 1);
  }
  m_NumberOfWorkUnits = m_NumberOfHelpers + 1;
  m_State = std::make_shared<State>();
  for (unsigned int helper = 0; helper < m_NumberOfHelpers; ++helper)
  {
    // The helper holds the state: it may start after the team has ended.
    pool->AddWork([state = m_State] { state->Help(); });
  }
}

WorkTeam::~WorkTeam()
{
  if (!m_State)
  {
    return;
  }
  std::unique_lock<std::mutex> lock(m_State->Mutex);
  m_State->Quit = true;
  m_State->Quitting = true;
  m_State->Wake.notify_all();
  m_State->Left.wait(lock, [this] { return m_State->Active == 0; });
}

void
WorkTeam::Run(SizeValueType items, CallType call, void * context)
{
  Job job;
  job.Items = items;
  job.Call = call;
  job.Context = context;
  if (!m_State)
  {
    // No helpers: the threader's work units take the items.
    const SizeValueType units = std::min<SizeValueType>(items, m_NumberOfWorkUnits);
    m_Threader->ParallelizeArray(
      0, units, [&job](SizeValueType) { job.Work(); }, nullptr);
  }
  else
  {
    State & state = *m_State;
    state.Current = &job;
    ++state.Generation;
    if (state.Sleeping.load() > 0)
    {
      const std::lock_guard<std::mutex> lock(state.Mutex);
      state.Wake.notify_all();
    }
    job.Work();
    // Every item is taken. Once the job is withdrawn and no helper is busy, no helper is
    // handling an item or can still reach the job (a helper counts itself busy before it
    // looks for the job).
    state.Current = nullptr;
    SpinUntil([&] { return state.Busy.load() == 0; });
    if (!m_FirstLoopEnded)
    {
      // A helper that has not started by the end of the first loop stays out: its core
      // is evidently busy (a thread woken that late is often held up again), and a
      // loop cannot end before every item a helper took has ended.
      const std::lock_guard<std::mutex> lock(state.Mutex);
      state.Open = false;
      m_FirstLoopEnded = true;
    }
  }
  if (job.Error)
  {
    std::rethrow_exception(job.Error);
  }
}
struct BackgroundTask::State
{
  std::mutex              Mutex;
  std::condition_variable Changed;
  std::function<void()>   Task;
  bool                    Busy{ false };
  bool                    Quit{ false };
  std::exception_ptr      Error;
  std::thread             Thread;

  void
  Serve()
  {
    std::unique_lock<std::mutex> lock(Mutex);
    for (;;)
    {
      Changed.wait(lock, [this] { return Quit || static_cast<bool>(Task); });
      if (!Task)
      {
        return;
      }
      std::function<void()> task = std::move(Task);
      Task = nullptr;
      lock.unlock();
      std::exception_ptr error;
      try
      {
        task();
      }
      catch (...)
      {
        error = std::current_exception();
      }
      lock.lock();
      Error = error;
      Busy = false;
      Changed.notify_all();
    }
  }
};

BackgroundTask::BackgroundTask()
  : m_State(std::make_unique<State>())
{}

BackgroundTask::~BackgroundTask()
{
  this->WaitQuietly();
  if (m_State->Thread.joinable())
  {
    {
      std::lock_guard<std::mutex> lock(m_State->Mutex);
      m_State->Quit = true;
    }
    m_State->Changed.notify_all();
    m_State->Thread.join();
  }
}

void
BackgroundTask::Start(std::function<void()> task)
{
  State & state = *m_State;
  if (!state.Thread.joinable())
  {
    state.Thread = std::thread([&state] { state.Serve(); });
  }
  {
    std::lock_guard<std::mutex> lock(state.Mutex);
    state.Task = std::move(task);
    state.Busy = true;
    state.Error = nullptr;
  }
  state.Changed.notify_all();
}

void
BackgroundTask::Wait()
{
  State &                      state = *m_State;
  std::unique_lock<std::mutex> lock(state.Mutex);
  state.Changed.wait(lock, [&state] { return !state.Busy; });
  if (state.Error)
  {
    std::exception_ptr error = state.Error;
    state.Error = nullptr;
    std::rethrow_exception(error);
  }
}

void
BackgroundTask::WaitQuietly() noexcept
{
  State &                      state = *m_State;
  std::unique_lock<std::mutex> lock(state.Mutex);
  state.Changed.wait(lock, [&state] { return !state.Busy; });
  state.Error = nullptr;
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
