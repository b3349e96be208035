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
#ifndef itkSmallIsoComponentTouchingRuns_h
#define itkSmallIsoComponentTouchingRuns_h

#include "itkIntTypes.h"

namespace itk
{
namespace SmallIsoComponentDetail
{
/** Calls join(a, b) for every pair of runs a of one line and b of a neighbouring line that
 * touch and for which same(a, b). The runs a..aLast and b..bLast partition [0, length) of
 * their lines, run r spanning start[r] up to the next run's start. Runs touch where they
 * overlap and, with full connectivity, also diagonally where both end at the same x: the run
 * after each one then meets the other. One merge of the two lines visits every such pair. */
template <typename TStart, typename TIndex, typename TSame, typename TJoin>
inline void
JoinTouchingRuns(const TStart * start,
                 TIndex         a,
                 TIndex         aLast,
                 TIndex         b,
                 TIndex         bLast,
                 TStart         length,
                 bool           fullyConnected,
                 TSame &&       same,
                 TJoin &&       join)
{
  const auto endOf = [start, length](TIndex run, TIndex last) { return run < last ? start[run + 1] : length; };
  TStart     endA = endOf(a, aLast);
  TStart     endB = endOf(b, bLast);
  while (true)
  {
    if (same(a, b))
    {
      join(a, b);
    }
    if (endA < endB)
    {
      endA = endOf(++a, aLast);
    }
    else if (endB < endA)
    {
      endB = endOf(++b, bLast);
    }
    else
    {
      if (a == aLast || b == bLast)
      {
        return;
      }
      if (fullyConnected && same(a, b + 1))
      {
        join(a, b + 1);
      }
      if (fullyConnected && same(a + 1, b))
      {
        join(a + 1, b);
      }
      endA = endOf(++a, aLast);
      endB = endOf(++b, bLast);
    }
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
