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
#ifndef itkSmallIsoComponentPhaseClock_h
#define itkSmallIsoComponentPhaseClock_h

#include "itkSmallIsoComponentEnums.h"
#include <array>
#include <chrono>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class PhaseClock
 * \brief The wall time of each phase of an update of SmallIsoComponentImageFilter: each
 * phase ends where the next begins, so the phases' times add up to the update's, from
 * Start() to the last End(). One clock reading per phase boundary. Internal to the filter.
 *
 * \ingroup SmallIsoComponent
 */
class PhaseClock
{
public:
  using PhaseEnum = SmallIsoComponentEnums::Phase;

  /** Clears every phase's time and starts the first phase now. */
  void
  Start()
  {
    m_Seconds.fill(0.0);
    m_Last = Clock::now();
  }

  /** Ends \a phase now (adding to what it had, for a phase done in parts), and starts the
   * next. */
  void
  End(PhaseEnum phase)
  {
    const Clock::time_point now = Clock::now();
    m_Seconds[static_cast<unsigned int>(phase)] += std::chrono::duration<double>(now - m_Last).count();
    m_Last = now;
  }

  double
  GetSeconds(PhaseEnum phase) const
  {
    return m_Seconds[static_cast<unsigned int>(phase)];
  }

private:
  using Clock = std::chrono::steady_clock;

  std::array<double, SmallIsoComponentEnums::NumberOfPhases> m_Seconds{};
  Clock::time_point                                          m_Last{};
};
} // namespace SmallIsoComponentDetail
} // namespace itk

#endif
