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
#ifndef itkSmallIsoComponentLabelComponents_h
#define itkSmallIsoComponentLabelComponents_h

#include "itkSmallIsoComponentLabelRuns.h"
#include "itkSmallIsoComponentLineNeighbors.h"
#include "itkSmallIsoComponentTouchingRuns.h"
#include "itkSmallIsoComponentUnionFind.h"
#include <algorithm>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class LabelComponents
 * The components of a label image: each line's runs of one label, joined with the runs of
 * the same label they touch on neighbouring lines (LineNeighbors says which lines those are).
 * After Find() every run points at its component's root, the component's smallest run, which
 * holds the component's size.
 * \ingroup SmallIsoComponent */
template <typename TLabel>
class LabelComponents : public LabelRuns<TLabel>
{
public:
  using RunIndex = typename LabelRuns<TLabel>::RunIndex;

  /** Finds the components of \a labels, an image of extent \a size with axis 0 fastest, with
   * the members of \a team: each links and sizes the runs of its slab of lines, then the
   * seams between the slabs are joined and the slabs' roots moved under the components' roots.
   * With \a copy, the image is also copied there as its runs are found (LabelRuns::Encode()). */
  void
  Find(const TLabel *                     labels,
       const std::vector<SizeValueType> & size,
       bool                               fullyConnected,
       WorkTeam &                         team,
       TLabel *                           copy = nullptr)
  {
    this->Encode(labels, size, team, copy);
    const SizeValueType lines = this->GetNumberOfLines();
    const LineNeighbors neighbors(size, fullyConnected);
    // One work unit links the whole image as one slab: no seams to join.
    const SizeValueType slabs =
      team.GetNumberOfWorkUnits() > 1 ? SlabsFor(lines, team) : std::min<SizeValueType>(lines, 1);
    m_Parent.resize(this->GetNumberOfRuns());
    m_Size.resize(this->GetNumberOfRuns());
    m_SlabRoots.resize(slabs);
    ForEachSlabOfLines(team, lines, slabs, [&](SizeValueType slab, SizeValueType begin, SizeValueType end) {
      this->LinkSlab(neighbors, fullyConnected, begin, end);
      this->SizeSlab(begin, end, m_SlabRoots[slab].Roots);
    });
    if (slabs > 1)
    {
      this->JoinSeams(neighbors, fullyConnected, lines, slabs);
      ForEachSlabOfLines(team, lines, slabs, [this](SizeValueType, SizeValueType begin, SizeValueType end) {
        this->PointAtComponentRoots(begin, end);
      });
    }
  }

  /** The slabs Find() linked the runs in; each component has its root in one of them. */
  SizeValueType
  GetNumberOfSlabs() const
  {
    return m_SlabRoots.size();
  }

  /** Calls function(root) for the root of every component whose root is in \a slab, in the
   * order of the roots. */
  template <typename TFunction>
  void
  ForEachComponentOfSlab(SizeValueType slab, TFunction && function) const
  {
    for (const RunIndex root : m_SlabRoots[slab].Roots)
    {
      if (m_Parent[root] == root)
      {
        function(root);
      }
    }
  }

  /** The root of \a run's component. */
  RunIndex
  Component(RunIndex run) const
  {
    return m_Parent[run];
  }
  /** The number of voxels of the component whose root is \a root. */
  SizeValueType
  Size(RunIndex root) const
  {
    return m_Size[root];
  }

private:
  /** Joins the runs of \a line with the runs of the same label they touch on line \a earlier. */
  void
  JoinLines(SizeValueType line, SizeValueType earlier, bool fullyConnected)
  {
    JoinTouchingRuns(
      this->GetStarts(),
      this->LineBegin(line),
      this->LineEnd(line) - 1,
      this->LineBegin(earlier),
      this->LineEnd(earlier) - 1,
      static_cast<typename LabelRuns<TLabel>::CoordinateType>(this->GetLineLength()),
      fullyConnected,
      [this](RunIndex a, RunIndex b) { return this->Label(a) == this->Label(b); },
      [this](RunIndex a, RunIndex b) { Join(m_Parent.data(), a, b); });
  }

  /** Joins the runs of each line of [begin, end) with those of its earlier neighbours that
   * \a joinWith(earlier) accepts. */
  template <typename TAccept>
  void
  JoinWithEarlierLines(const LineNeighbors & neighbors,
                       bool                  fullyConnected,
                       SizeValueType         begin,
                       SizeValueType         end,
                       const TAccept &       joinWith)
  {
    LineNeighbors::Position position = neighbors.At(begin);
    for (SizeValueType line = begin; line < end; ++line, neighbors.Next(position))
    {
      neighbors.ForEachEarlier(position, [&](SizeValueType earlier) {
        if (joinWith(earlier))
        {
          this->JoinLines(line, earlier, fullyConnected);
        }
      });
    }
  }

  /** Links the runs of the lines [begin, end) with each other, touching no other run. */
  void
  LinkSlab(const LineNeighbors & neighbors, bool fullyConnected, SizeValueType begin, SizeValueType end)
  {
    for (RunIndex run = this->LineBegin(begin); run < this->LineBegin(end); ++run)
    {
      m_Parent[run] = run;
    }
    this->JoinWithEarlierLines(
      neighbors, fullyConnected, begin, end, [begin](SizeValueType earlier) { return earlier >= begin; });
  }

  /** Points every run of the lines [begin, end) at its root in the slab and adds its voxels to
   * the root's size; lists the slab's roots in \a roots. A run's parent is an earlier run, so
   * it points at its root already when the run's turn comes. */
  void
  SizeSlab(SizeValueType begin, SizeValueType end, std::vector<RunIndex> & roots)
  {
    roots.clear();
    for (SizeValueType line = begin; line < end; ++line)
    {
      for (RunIndex run = this->LineBegin(line); run < this->LineEnd(line); ++run)
      {
        const RunIndex root = m_Parent[m_Parent[run]];
        m_Parent[run] = root;
        if (root == run)
        {
          roots.push_back(run);
          m_Size[run] = 0;
        }
        m_Size[root] += this->End(run, line) - this->Start(run);
      }
    }
  }

  /** Points every run of the lines [begin, end) at its component's root. Its parent is a slab's
   * root, which points there already; a run is written only when that changes it, so that no
   * slab's root, which the runs of other slabs read, is written. */
  void
  PointAtComponentRoots(SizeValueType begin, SizeValueType end)
  {
    for (RunIndex run = this->LineBegin(begin); run < this->LineBegin(end); ++run)
    {
      const RunIndex root = m_Parent[m_Parent[run]];
      if (root != m_Parent[run])
      {
        m_Parent[run] = root;
      }
    }
  }

  /** Joins the runs of each slab's first lines with those of the lines before the slab, then
   * points each slab's root at its component's root, adding the sizes up there. Every parent is
   * a slab's root, and an earlier run: in the order of the runs, a root's parent is already the
   * component's root when its turn comes. */
  void
  JoinSeams(const LineNeighbors & neighbors, bool fullyConnected, SizeValueType lines, SizeValueType slabs)
  {
    for (SizeValueType slab = 1; slab < slabs; ++slab)
    {
      const SizeValueType begin = SlabBeginLine(lines, slabs, slab);
      const SizeValueType end = std::min(SlabBeginLine(lines, slabs, slab + 1), begin + neighbors.GetFarthestEarlier());
      this->JoinWithEarlierLines(
        neighbors, fullyConnected, begin, end, [begin](SizeValueType earlier) { return earlier < begin; });
    }
    for (const SlabRoots & roots : m_SlabRoots)
    {
      for (const RunIndex slabRoot : roots.Roots)
      {
        const RunIndex root = m_Parent[m_Parent[slabRoot]];
        if (root != slabRoot)
        {
          m_Parent[slabRoot] = root;
          m_Size[root] += m_Size[slabRoot];
        }
      }
    }
  }

  /** A slab's roots, on cache lines of their own: the work units add to theirs at once. */
  struct alignas(64) SlabRoots
  {
    std::vector<RunIndex> Roots;
  };

  std::vector<RunIndex>      m_Parent;
  std::vector<SizeValueType> m_Size;
  std::vector<SlabRoots>     m_SlabRoots;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
