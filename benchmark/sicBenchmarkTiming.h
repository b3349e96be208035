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

// How the benchmarks time a run: wall time and the page faults taken meanwhile.

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
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

/** Runs \a work once untimed, then times a second run; \a prepare (untimed) comes before
 * each. Every peer is thus timed right after a run of itself at the same thread count, never
 * after a different peer: on a virtual machine a core left idle by a long single-threaded
 * peer often comes back late (the next peer's second thread then starts a millisecond or
 * more after the first), which would weigh on whichever peer happened to come next. */
template <typename P, typename F>
Sample
TimeAfterWarmUp(P && prepare, F && work)
{
  prepare();
  work();
  prepare();
  return TimeMs(work);
}
} // namespace sic

#endif
