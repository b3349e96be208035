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
#ifndef itkSmallIsoComponentLabelRepair_h
#define itkSmallIsoComponentLabelRepair_h

#include "itkSmallIsoComponentLabelComponents.h"
#include "itkSmallIsoComponentRegionLines.h"
#include <algorithm>
#include <map>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class LabelRepair
 * The repair of a label image's removed voxels: each takes the label voted by the first voxels
 * outside its component along the 2N axis directions, the votes of kept components first, then
 * the most votes, the nearest voter, the smallest label. Only the voxels of the output's region
 * are repaired, in slabs of lines shared among the work units.
 * \ingroup SmallIsoComponent */
template <typename TLabel, unsigned int VDimension>
class LabelRepair
{
public:
  using Components = LabelComponents<TLabel>;
  using RunIndex = typename Components::RunIndex;
  using RegionType = ImageRegion<VDimension>;
  using IndexType = Index<VDimension>;

  /** A removed voxel's new label, at its offset in the output's buffer. */
  struct Repair
  {
    SizeValueType Offset;
    TLabel        Label;
  };

  /** Finds the new label of every removed voxel of \a outputRegion from \a input, the voxels of
   * \a region, and sets it to 1 in \a mask (cleared, the output region's) when given. The halo's
   * removed voxels are not written, so they are not repaired and the counts are those of the
   * output's voxels. */
  void
  Compute(const TLabel *     input,
          const Components & components,
          const RegionType & region,
          const RegionType & outputRegion,
          uint8_t *          mask,
          WorkTeam &         team)
  {
    m_Slabs.resize(SlabsFor(components.GetNumberOfLines(), team));
    for (Slab & slab : m_Slabs)
    {
      slab.Repairs.clear();
      slab.Gained.clear();
      slab.Unrepairable = 0;
    }
    const Walks walks{ input, components, region.GetSize() };
    ForEachRemovedRunInOutput(
      components, region, outputRegion, team, [&](SizeValueType slabIndex, const RunInOutput & part) {
        Slab & slab = m_Slabs[slabIndex];
        if (mask != nullptr)
        {
          std::fill(mask + part.Offset + part.Begin, mask + part.Offset + part.End, 1);
        }
        for (SizeValueType x = part.Begin; x < part.End; ++x)
        {
          walks.CollectVotes(part, region, x, slab.Votes);
          if (slab.Votes.empty())
          {
            ++slab.Unrepairable;
            continue;
          }
          const TLabel label = Elect(slab.Votes);
          ++slab.Gained[label];
          slab.Repairs.push_back({ part.Offset + x, label });
        }
      });
  }

  /** Calls function(repair) for every repair found by Compute(). */
  template <typename TFunction>
  void
  ForEachRepair(TFunction && function) const
  {
    for (const Slab & slab : m_Slabs)
    {
      std::for_each(slab.Repairs.begin(), slab.Repairs.end(), function);
    }
  }

  /** The voxels repaired, those left as they were for want of a vote, and those each label
   * gained, by Compute(). */
  SizeValueType
  GetNumberOfRepairs() const;
  SizeValueType
  GetNumberOfUnrepairableVoxels() const;
  std::map<TLabel, SizeValueType>
  GetGainedVoxels() const;

private:
  /** The part [Begin, End) of run Run, of line Line of the input region's buffer whose first
   * voxel is at LineIndex, that lies in the output's region: voxel x of the line is at
   * Offset + x in the output's buffer. */
  struct RunInOutput
  {
    SizeValueType Line;
    IndexType     LineIndex;
    RunIndex      Run;
    SizeValueType Begin;
    SizeValueType End;
    SizeValueType Offset;
  };

  /** Calls function(slab, part) for the part in \a outputRegion of each run of \a components,
   * runs of \a region, whose component is marked removed, in slabs of lines
   * shared among the members of \a team. Lines are placed in the output only at their
   * first removed run: removed runs are few, so most lines cost no index arithmetic. */
  template <typename TFunction>
  static void
  ForEachRemovedRunInOutput(const Components & components,
                            const RegionType & region,
                            const RegionType & outputRegion,
                            WorkTeam &         team,
                            const TFunction &  function)
  {
    const SizeValueType first = static_cast<SizeValueType>(outputRegion.GetIndex(0) - region.GetIndex(0));
    const SizeValueType last = first + outputRegion.GetSize(0);
    const SizeValueType lines = components.GetNumberOfLines();
    ForEachSlabOfLines(
      team, lines, SlabsFor(lines, team), [&](SizeValueType slab, SizeValueType begin, SizeValueType end) {
        for (SizeValueType line = begin; line < end; ++line)
        {
          RunInOutput part{ line, {}, 0, 0, 0, 0 };
          bool        placed = false;
          for (RunIndex run = components.LineBegin(line); run < components.LineEnd(line); ++run)
          {
            if (!components.IsRemoved(run))
            {
              continue;
            }
            part.Run = run;
            part.Begin = std::max(first, components.Start(run));
            part.End = std::min(last, components.End(run, line));
            if (part.Begin >= part.End)
            {
              continue;
            }
            if (!placed)
            {
              part.LineIndex = IndexOfLine(region, line);
              IndexType inOutput = part.LineIndex;
              inOutput[0] = outputRegion.GetIndex(0);
              if (!outputRegion.IsInside(inOutput))
              {
                break;
              }
              placed = true;
              part.Offset = OffsetOf(outputRegion, inOutput) - first;
            }
            function(slab, part);
          }
        }
      });
  }

  struct Vote
  {
    TLabel        Label;
    SizeValueType Steps;
    bool          Kept;
  };

  /** The walks from the removed voxels: what they read. */
  struct Walks
  {
    const TLabel *     Input;
    const Components & Runs;
    Size<VDimension>   Extent;

    void
    CollectVotes(const RunInOutput & part, const RegionType & region, SizeValueType x, std::vector<Vote> & votes) const;
  };

  /** A slab's repairs and counts, and its scratch votes, on cache lines of their own: the work
   * units write theirs at once, for every vote. */
  struct alignas(64) Slab
  {
    std::vector<Repair>             Repairs;
    std::map<TLabel, SizeValueType> Gained;
    SizeValueType                   Unrepairable{ 0 };
    std::vector<Vote>               Votes;
  };

  /** The winning label of \a votes (not empty). */
  static TLabel
  Elect(const std::vector<Vote> & votes);

  std::vector<Slab> m_Slabs;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#include "itkSmallIsoComponentLabelRepair.hxx"

#endif
