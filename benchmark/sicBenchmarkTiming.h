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
#ifndef sicBenchmarkTiming_h
#define sicBenchmarkTiming_h

// How the benchmarks time a run (wall time and the page faults taken meanwhile) and measure the
// memory one takes.

#include <sys/resource.h>
#if defined(__GLIBC__)
#  include <malloc.h>
#endif

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace sic
{
/** One timed run: wall time and the page faults the process took meanwhile. */
struct Sample
{
  double Ms{ 0 };
  double Faults{ 0 };
};

/** Minor and major page faults of the process so far. */
inline double
PageFaults()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_minflt + usage.ru_majflt);
}

inline double
Median(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

template <typename F>
Sample
TimeMs(F && work)
{
  const double faults = PageFaults();
  const auto   start = std::chrono::steady_clock::now();
  work();
  Sample sample;
  sample.Ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  sample.Faults = PageFaults() - faults;
  return sample;
}

/** Runs \a work untimed, once or until \a warmUpMs have passed, then times one more run;
 * \a prepare (untimed) comes before each. Every peer is thus timed right after a run of itself
 * at the same thread count, never after a different peer: on a virtual machine a core left
 * idle by a long single-threaded peer often comes back late (the next peer's second thread
 * then starts a millisecond or more after the first), which would weigh on whichever peer
 * happened to come next; after seconds of a peer's work, a fast filter needs some hundred
 * milliseconds of its own runs before it runs at its usual speed again. */
template <typename P, typename F>
Sample
TimeAfterWarmUp(P && prepare, F && work, double warmUpMs = 0)
{
  const auto start = std::chrono::steady_clock::now();
  do
  {
    prepare();
    work();
  } while (std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() < warmUpMs);
  prepare();
  return TimeMs(work);
}

/** The kB count of \a key ("VmRSS:", "VmHWM:") in /proc/self/status, in bytes; -1 where there is none. */
inline double
StatusBytes(const std::string & key)
{
  std::ifstream status("/proc/self/status");
  std::string   line;
  while (std::getline(status, line))
  {
    if (line.compare(0, key.size(), key) == 0)
    {
      return 1024.0 * std::strtod(line.c_str() + key.size(), nullptr);
    }
  }
  return -1;
}

/** The growth of the peak resident size while \a work runs, in bytes, from the peak reset just
 * before; -1 where the system does not say. Freed memory is given back to the system first, so
 * that \a work cannot reuse pages that earlier work made resident; run it after a run of the same
 * code, so that the code's own pages are resident already and only the memory it takes for its
 * data counts. */
template <typename F>
double
PeakGrowthBytes(F && work)
{
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
  std::ofstream reset("/proc/self/clear_refs");
  reset << "5" << std::flush;
  const double before = StatusBytes("VmHWM:");
  if (!reset || before < 0)
  {
    return -1;
  }
  work();
  return StatusBytes("VmHWM:") - before;
}
} // namespace sic

#endif
