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
#ifndef itkSmallIsoComponentWorkTeam_h
#define itkSmallIsoComponentWorkTeam_h

#include "itkIntTypes.h"
#include "itkMultiThreaderBase.h"
#include "SmallIsoComponentExport.h"
#include "itkSmallIsoComponentTuning.h"

#include <algorithm>
#include <functional>
#include <memory>
#include <type_traits>
#include <utility>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class WorkTeam
 * \brief Threads that stay with one filter update and take its parallel loops one after
 * another. Internal to SmallIsoComponentImageFilter and SmallIsoComponentLabelImageFilter.
 *
 * It schedules every parallel loop of an update. A filter update runs several short
 * parallel loops with serial steps between them.
 * Handing each loop to the threader wakes its pool threads each time, which costs tens
 * of microseconds per loop on small volumes. A team asks ITK's thread pool once for its
 * helper threads (when the threader is a PoolMultiThreader); they stay for the life of the
 * team, waiting for the next loop (spinning briefly, then sleeping), and the thread that
 * made the team (the filter's thread) takes part in every loop and runs everything
 * between them, so progress and abort events stay on it.
 *
 * Items are handed out one at a time to whoever is free, so a helper that starts late or
 * never (a busy pool) only means the calling thread does more of the loop: the team never
 * waits for a helper to start. A helper that has not started by the end of the first loop
 * does not join at all: a thread that starts that late is on a busy core and likely to be
 * held up again in the middle of an item, which the loop would have to wait for. Other
 * threaders (or one work unit) get each loop through the threader's ParallelizeArray(),
 * as without a team.
 *
 * ForEach() must be called from the thread that made the team, one loop at a time. The
 * first exception thrown by an item is rethrown by ForEach() once every item in progress
 * has ended; the items not yet started are skipped.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT WorkTeam
{
public:
  /** A team for \a workUnits work units of \a threader: workUnits - 1 helpers at most,
   * fewer if the pool has fewer threads or the machine fewer other cores. */
  WorkTeam(MultiThreaderBase * threader, unsigned int workUnits);
  /** Dismisses the helpers and waits for the ones that started to leave. */
  ~WorkTeam();
  WorkTeam(const WorkTeam &) = delete;
  WorkTeam &
  operator=(const WorkTeam &) = delete;

  /** The work units a loop is shared among: the calling thread and the helpers asked
   * for, or the threader's work units when the team has no helpers. */
  unsigned int
  GetNumberOfWorkUnits() const
  {
    return m_NumberOfWorkUnits;
  }

  /** How many helpers were asked for (0: loops go through the threader). */
  unsigned int
  GetNumberOfHelpers() const
  {
    return m_NumberOfHelpers;
  }


  /** How many chunks a loop over \a items cheap items is cut into, for ForEach(): one
   * below the minimum to share, else Tuning::ChunksPerWorkUnit per work unit (at most one per
   * item). */
  SizeValueType
  GetNumberOfChunks(SizeValueType items) const
  {
    const SizeValueType minimum =
      m_NumberOfHelpers > 0 ? Tuning::MinimumItemsToShareWithHelpers : Tuning::MinimumItemsToShare;
    return items < minimum ? 1 : std::min<SizeValueType>(items, Tuning::ChunksPerWorkUnit * m_NumberOfWorkUnits);
  }
  /** How many parts a loop over \a items cheap items that keeps state of its own per part
   * is cut into: one per work unit where GetNumberOfChunks() would share the loop, else one. */
  SizeValueType
  GetNumberOfParts(SizeValueType items) const
  {
    return this->GetNumberOfChunks(items) > 1 ? m_NumberOfWorkUnits : 1;
  }
  /** The first of \a items in \a part of \a parts equal parts (part == parts gives items). */
  static SizeValueType
  PartBegin(SizeValueType items, SizeValueType part, SizeValueType parts)
  {
    return items * part / parts;
  }

  /** Calls function(item) once for every item in [0, items), each item taken by the
   * next free member of the team. Returns when every item has been handled. */
  template <typename TFunction>
  void
  ForEach(SizeValueType items, TFunction && function)
  {
    if (items == 0)
    {
      return;
    }
    if (items == 1 || m_NumberOfWorkUnits <= 1)
    {
      for (SizeValueType item = 0; item < items; ++item)
      {
        function(item);
      }
      return;
    }
    using FunctionType = typename std::remove_reference<TFunction>::type;
    this->Run(
      items,
      [](void * context, SizeValueType item) { (*static_cast<FunctionType *>(context))(item); },
      const_cast<void *>(static_cast<const void *>(&function)));
  }

  /** The shared state of a team (defined in the .cxx file). */
  struct State;

private:
  using CallType = void (*)(void *, SizeValueType);
  void
  Run(SizeValueType items, CallType call, void * context);

  MultiThreaderBase *    m_Threader;
  unsigned int           m_NumberOfWorkUnits{ 1 };
  unsigned int           m_NumberOfHelpers{ 0 };
  bool                   m_FirstLoopEnded{ false };
  std::shared_ptr<State> m_State;
};
/** \class BackgroundTask
 * \brief One thread beside the calling one, for one task at a time: Start() hands it the task
 * and returns at once, Wait() returns when the task has ended and rethrows what it threw.
 * Internal to StreamingSweep, which labels the next slab on it while the calling thread merges
 * and gives out the one before.
 *
 * The thread is made by the first Start() and ends with the object, which waits for a task in
 * progress first. Start() and Wait() must be called from one thread, alternately.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT BackgroundTask
{
public:
  BackgroundTask();
  ~BackgroundTask();
  BackgroundTask(const BackgroundTask &) = delete;
  BackgroundTask &
  operator=(const BackgroundTask &) = delete;

  /** Runs \a task on the background thread. */
  void
  Start(std::function<void()> task);
  /** Waits for the task given to Start() to end; rethrows the exception it ended with. */
  void
  Wait();
  /** Waits for the task to end, ignoring what it threw (for a caller that is unwinding). */
  void
  WaitQuietly() noexcept;

  /** The shared state of the thread (defined in the .cxx file). */
  struct State;

private:
  std::unique_ptr<State> m_State;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
