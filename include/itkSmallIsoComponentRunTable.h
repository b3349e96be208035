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
#ifndef itkSmallIsoComponentRunTable_h
#define itkSmallIsoComponentRunTable_h

#include "itkIntTypes.h"
#include "itkSmallIsoComponentTuning.h"

#include <algorithm>
#include <cstdint>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class RunTable
 * \brief A labelling's runs, read-only, as arrays, for the loops over many runs
 * (RunLabeling::GetRunTable()): each line's runs, their starts and components, and the
 * lookups of the run holding a voxel.
 * \ingroup SmallIsoComponent
 */
struct RunTable
{
  using CoordinateType = uint32_t;
  using ComponentIndexType = uint32_t;

  /** The first voxel of each run along axis 0. */
  const CoordinateType * Start;
  /** The component of each run (after LabelComponents()). */
  const ComponentIndexType * Component;
  /** The first run of each line; LineBegin[line + 1] ends the line's runs. */
  const SizeValueType * LineBegin;
  /** Whether each line's first run is above (then its runs alternate). */
  const uint8_t * LineFirstAbove;
  SizeValueType   LineLength;
  /** Each line's boundary bits (a bit per voxel, set where a run starts; BitsWords words a
   * line) where they are kept (see RunLabeling::GetKeptLineBits()), else nullptr. */
  const uint64_t * Bits;
  SizeValueType    BitsWords;

  /** One past the last voxel of \a run, whose line is \a line. */
  SizeValueType
  End(SizeValueType run, SizeValueType line) const
  {
    return run + 1 < LineBegin[line + 1] ? SizeValueType{ Start[run + 1] } : LineLength;
  }
  /** Whether \a run, whose line is \a line, is above (sides alternate along a line). */
  bool
  IsAbove(SizeValueType run, SizeValueType line) const
  {
    return (LineFirstAbove[line] != 0) == (((run - LineBegin[line]) & 1) == 0);
  }
  /** The run of \a line that holds voxel \a x (the last one starting at or before it; a
   * line's first run starts at 0). */
  SizeValueType
  RunHolding(SizeValueType line, SizeValueType x) const
  {
    return this->LastStartingBy(LineBegin[line], LineBegin[line + 1], x);
  }
  /** Where among \a line's runs the run holding voxel \a x would be if the runs were
   * spread evenly along the line (\a perVoxel: 1 / LineLength). */
  SizeValueType
  GuessRunHolding(SizeValueType line, SizeValueType x, double perVoxel) const
  {
    const SizeValueType begin = LineBegin[line];
    return begin + static_cast<SizeValueType>(static_cast<double>(LineBegin[line + 1] - begin) *
                                              static_cast<double>(x) * perVoxel);
  }
  /** RunHolding(), searching first the runs within Tuning::NearRuns of \a guess (a run of
   * \a line): where runs are spread about evenly, only the cache lines near the guess are
   * read, and they can be requested ahead. */
  SizeValueType
  RunHolding(SizeValueType line, SizeValueType x, SizeValueType guess) const
  {
    const SizeValueType begin = LineBegin[line];
    const SizeValueType end = LineBegin[line + 1];
    const SizeValueType low = guess > begin + Tuning::NearRuns ? guess - Tuning::NearRuns : begin;
    const SizeValueType high = std::min(end, guess + Tuning::NearRuns + 1);
    if (low >= high || Start[low] > x || (high < end && Start[high] <= x))
    {
      return this->LastStartingBy(begin, end, x);
    }
    return this->LastStartingBy(low, high, x);
  }
  /** The last of the runs [first, last) (first starting at or before \a x) that starts at
   * or before \a x, found by a binary search without branches, which the run starts
   * would make unpredictable. */
  SizeValueType
  LastStartingBy(SizeValueType first, SizeValueType last, SizeValueType x) const
  {
    const CoordinateType * holder = Start + first;
    for (SizeValueType candidates = last - first; candidates > 1;)
    {
      const SizeValueType half = candidates / 2;
      holder = holder[half] <= x ? holder + half : holder;
      candidates -= half;
    }
    return static_cast<SizeValueType>(holder - Start);
  }
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
