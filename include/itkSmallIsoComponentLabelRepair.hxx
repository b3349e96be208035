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
#ifndef itkSmallIsoComponentLabelRepair_hxx
#define itkSmallIsoComponentLabelRepair_hxx

#include "itkNumericTraits.h"
#include <utility>

namespace itk
{
namespace SmallIsoComponentDetail
{
template <typename TLabel, unsigned int VDimension>
void
LabelRepair<TLabel, VDimension>::Walks::CollectVotes(const RunInOutput & part,
                                                     const RegionType &  region,
                                                     SizeValueType       x,
                                                     std::vector<Vote> & votes) const
{
  // Along a line the walks leave the run at its ends; along the other axes they pass voxels of
  // the component's label, which are all in the component, up to the first other label.
  const auto vote = [this, &votes](RunIndex at, SizeValueType steps) {
    votes.push_back({ Runs.Label(at), steps, !Runs.IsRemoved(at) });
  };
  votes.clear();
  const SizeValueType start = Runs.Start(part.Run);
  const SizeValueType end = Runs.End(part.Run, part.Line);
  if (start > 0)
  {
    vote(part.Run - 1, x - start + 1);
  }
  if (end < Extent[0])
  {
    vote(part.Run + 1, end - x);
  }
  const TLabel  label = Runs.Label(part.Run);
  SizeValueType lineStride = 1;
  for (unsigned int a = 1; a < VDimension; ++a)
  {
    const auto coordinate = static_cast<SizeValueType>(part.LineIndex[a] - region.GetIndex(a));
    for (const int direction : { -1, 1 })
    {
      SizeValueType other = part.Line;
      for (SizeValueType steps = 1; direction < 0 ? coordinate >= steps : coordinate + steps < Extent[a]; ++steps)
      {
        other = direction < 0 ? other - lineStride : other + lineStride;
        if (!(Input[other * Extent[0] + x] == label))
        {
          vote(Runs.RunAt(other, x), steps);
          break;
        }
      }
    }
    lineStride *= Extent[a];
  }
}

template <typename TLabel, unsigned int VDimension>
TLabel
LabelRepair<TLabel, VDimension>::Elect(const std::vector<Vote> & votes)
{
  const bool anyKept = std::any_of(votes.begin(), votes.end(), [](const Vote & vote) { return vote.Kept; });
  bool       found = false;
  TLabel     best{};
  std::pair<SizeValueType, SizeValueType> bestRank{ 0, 0 };
  for (const Vote & candidate : votes)
  {
    if (anyKept && !candidate.Kept)
    {
      continue;
    }
    // Rank: the most votes, then the nearest voter, then the smallest label.
    SizeValueType count = 0;
    SizeValueType nearest = NumericTraits<SizeValueType>::max();
    for (const Vote & vote : votes)
    {
      if ((vote.Kept || !anyKept) && vote.Label == candidate.Label)
      {
        ++count;
        nearest = std::min(nearest, vote.Steps);
      }
    }
    const std::pair<SizeValueType, SizeValueType> rank{ count, NumericTraits<SizeValueType>::max() - nearest };
    if (!found || rank > bestRank || (rank == bestRank && candidate.Label < best))
    {
      found = true;
      best = candidate.Label;
      bestRank = rank;
    }
  }
  return best;
}

template <typename TLabel, unsigned int VDimension>
SizeValueType
LabelRepair<TLabel, VDimension>::GetNumberOfRepairs() const
{
  SizeValueType repairs = 0;
  for (const Slab & slab : m_Slabs)
  {
    repairs += slab.Repairs.size();
  }
  return repairs;
}

template <typename TLabel, unsigned int VDimension>
SizeValueType
LabelRepair<TLabel, VDimension>::GetNumberOfUnrepairableVoxels() const
{
  SizeValueType unrepairable = 0;
  for (const Slab & slab : m_Slabs)
  {
    unrepairable += slab.Unrepairable;
  }
  return unrepairable;
}

template <typename TLabel, unsigned int VDimension>
std::map<TLabel, SizeValueType>
LabelRepair<TLabel, VDimension>::GetGainedVoxels() const
{
  std::map<TLabel, SizeValueType> gained;
  for (const Slab & slab : m_Slabs)
  {
    for (const auto & entry : slab.Gained)
    {
      gained[entry.first] += entry.second;
    }
  }
  return gained;
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
