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
#ifndef sicSplitMix64_h
#define sicSplitMix64_h

#include <cstdint>

namespace sic
{
/** The SplitMix64 pseudo-random generator: a 64-bit state and a fixed mixing function, so
 * a seed gives the same numbers on every platform and standard library (which the
 * std::*_distribution classes do not promise). */
class SplitMix64
{
public:
  explicit SplitMix64(std::uint64_t seed)
    : m_State(seed)
  {}

  std::uint64_t
  Next()
  {
    std::uint64_t z = (m_State += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

  /** Uniform in [0, 1), from the top 53 bits. */
  double
  Uniform()
  {
    return static_cast<double>(Next() >> 11) * (1.0 / 9007199254740992.0);
  }

  /** Uniform in [low, high). */
  double
  Uniform(double low, double high)
  {
    return low + (high - low) * Uniform();
  }

private:
  std::uint64_t m_State;
};
} // namespace sic

#endif
