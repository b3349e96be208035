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
 * After Find() every run points at its component's root, the component's smallest run; the
 * sizes are kept per root, not per run, and a removed component is marked at its root.
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
       TLabel *                           copy = nullptr);

  /** The slabs Find() linked the runs in; each component has its root in one of them. */
  SizeValueType
  GetNumberOfSlabs() const
  {
    return m_SlabRoots.size();
  }

  /** Calls function(root, size) for the root of every component whose root is in \a slab, in
   * the order of the roots, with the component's number of voxels. */
  template <typename TFunction>
  void
  ForEachComponentOfSlab(SizeValueType slab, TFunction && function) const
  {
    const SlabRoots & roots = m_SlabRoots[slab];
    for (std::size_t i = 0; i < roots.Roots.size(); ++i)
    {
      if (this->Component(roots.Roots[i]) == roots.Roots[i])
      {
        function(roots.Roots[i], roots.Sizes[i]);
      }
    }
  }

  /** The root of \a run's component. */
  RunIndex
  Component(RunIndex run) const
  {
    return m_Parent[run] & ~Marked;
  }

  /** Marks the component whose root is \a root as removed. */
  void
  MarkRemoved(RunIndex root)
  {
    m_Parent[root] |= Marked;
  }
  /** Whether \a run's component was marked removed. */
  bool
  IsRemoved(RunIndex run) const
  {
    return (m_Parent[this->Component(run)] & Marked) != 0;
  }

private:
  /** A slab's roots and their sizes, on cache lines of their own: the work units add to theirs
   * at once. */
  struct alignas(64) SlabRoots
  {
    std::vector<RunIndex>      Roots;
    std::vector<SizeValueType> Sizes;
  };

  /** Joins the runs of \a line with the runs of the same label they touch on line \a earlier. */
  void
  JoinLines(SizeValueType line, SizeValueType earlier, bool fullyConnected);

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
  LinkSlab(const LineNeighbors & neighbors, bool fullyConnected, SizeValueType begin, SizeValueType end);

  /** Points every run of the lines [begin, end) at its root in the slab and lists the slab's
   * roots with their sizes. A run's parent is an earlier run, so it points at its root already
   * when the run's turn comes; meanwhile a root's own entry holds its size, marked. */
  void
  SizeSlab(SizeValueType begin, SizeValueType end, SlabRoots & roots);

  /** Adds \a size voxels to the marked size of \a node's root and returns whether \a node is a
   * root: then its entry becomes its marked size; otherwise its parent is the root or points
   * at it, and \a node is pointed at the root. */
  bool
  AddToRoot(RunIndex node, SizeValueType size);

  /** Moves the marked sizes of those of \a roots that are still roots into the list, each its
   * own parent again. */
  void
  TakeSizes(SlabRoots & roots);

  /** Points every run of the lines [begin, end) at its component's root. Its parent is a slab's
   * root, which points there already; a run is written only when that changes it, so that no
   * slab's root, which the runs of other slabs read, is written. */
  void
  PointAtComponentRoots(SizeValueType begin, SizeValueType end);

  /** Joins the runs of each slab's first lines with those of the lines before the slab, then
   * points each slab's root at its component's root, adding the sizes up there. Every parent is
   * a slab's root, and an earlier run: in the order of the runs, a root's parent is already the
   * component's root when its turn comes. */
  void
  JoinSeams(const LineNeighbors & neighbors, bool fullyConnected, SizeValueType lines, SizeValueType slabs);

  /** The top bit of a root's parent entry: it marks the entry as the root's size while the
   * sizes are added up, and marks a removed component after Find(). */
  static constexpr RunIndex Marked = RunIndex{ 1 } << (8 * sizeof(RunIndex) - 1);

  std::vector<RunIndex>  m_Parent;
  std::vector<SlabRoots> m_SlabRoots;
};

template <typename TLabel>
inline void
LabelComponents<TLabel>::Find(const TLabel *                     labels,
                              const std::vector<SizeValueType> & size,
                              bool                               fullyConnected,
                              WorkTeam &                         team,
                              TLabel *                           copy)
{
  this->Encode(labels, size, team, copy);
  const SizeValueType lines = this->GetNumberOfLines();
  const LineNeighbors neighbors(size, fullyConnected);
  // One work unit links the whole image as one slab: no seams to join.
  const SizeValueType slabs =
    team.GetNumberOfWorkUnits() > 1 ? SlabsFor(lines, team) : std::min<SizeValueType>(lines, 1);
  m_Parent.resize(this->GetNumberOfRuns());
  m_SlabRoots.resize(slabs);
  ForEachSlabOfLines(team, lines, slabs, [&](SizeValueType slab, SizeValueType begin, SizeValueType end) {
    this->LinkSlab(neighbors, fullyConnected, begin, end);
    this->SizeSlab(begin, end, m_SlabRoots[slab]);
  });
  if (slabs > 1)
  {
    this->JoinSeams(neighbors, fullyConnected, lines, slabs);
    ForEachSlabOfLines(team, lines, slabs, [this](SizeValueType, SizeValueType begin, SizeValueType end) {
      this->PointAtComponentRoots(begin, end);
    });
  }
}

template <typename TLabel>
inline void
LabelComponents<TLabel>::JoinLines(SizeValueType line, SizeValueType earlier, bool fullyConnected)
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

template <typename TLabel>
inline void
LabelComponents<TLabel>::LinkSlab(const LineNeighbors & neighbors,
                                  bool                  fullyConnected,
                                  SizeValueType         begin,
                                  SizeValueType         end)
{
  for (RunIndex run = this->LineBegin(begin); run < this->LineBegin(end); ++run)
  {
    m_Parent[run] = run;
  }
  this->JoinWithEarlierLines(
    neighbors, fullyConnected, begin, end, [begin](SizeValueType earlier) { return earlier >= begin; });
}

template <typename TLabel>
inline void
LabelComponents<TLabel>::SizeSlab(SizeValueType begin, SizeValueType end, SlabRoots & roots)
{
  roots.Roots.clear();
  for (SizeValueType line = begin; line < end; ++line)
  {
    for (RunIndex run = this->LineBegin(line); run < this->LineEnd(line); ++run)
    {
      if (this->AddToRoot(run, this->End(run, line) - this->Start(run)))
      {
        roots.Roots.push_back(run);
      }
    }
  }
  this->TakeSizes(roots);
}

template <typename TLabel>
inline bool
LabelComponents<TLabel>::AddToRoot(RunIndex node, SizeValueType size)
{
  const RunIndex parent = m_Parent[node];
  if (parent == node)
  {
    m_Parent[node] = Marked | size;
    return true;
  }
  const RunIndex root = (m_Parent[parent] & Marked) != 0 ? parent : m_Parent[parent];
  m_Parent[node] = root;
  m_Parent[root] += size;
  return false;
}

template <typename TLabel>
inline void
LabelComponents<TLabel>::TakeSizes(SlabRoots & roots)
{
  roots.Sizes.resize(roots.Roots.size());
  for (std::size_t i = 0; i < roots.Roots.size(); ++i)
  {
    const RunIndex root = roots.Roots[i];
    if ((m_Parent[root] & Marked) != 0)
    {
      roots.Sizes[i] = m_Parent[root] & ~Marked;
      m_Parent[root] = root;
    }
  }
}

template <typename TLabel>
inline void
LabelComponents<TLabel>::PointAtComponentRoots(SizeValueType begin, SizeValueType end)
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

template <typename TLabel>
inline void
LabelComponents<TLabel>::JoinSeams(const LineNeighbors & neighbors,
                                   bool                  fullyConnected,
                                   SizeValueType         lines,
                                   SizeValueType         slabs)
{
  for (SizeValueType slab = 1; slab < slabs; ++slab)
  {
    const SizeValueType begin = SlabBeginLine(lines, slabs, slab);
    const SizeValueType end = std::min(SlabBeginLine(lines, slabs, slab + 1), begin + neighbors.GetFarthestEarlier());
    this->JoinWithEarlierLines(
      neighbors, fullyConnected, begin, end, [begin](SizeValueType earlier) { return earlier < begin; });
  }
  for (SlabRoots & roots : m_SlabRoots)
  {
    for (std::size_t i = 0; i < roots.Roots.size(); ++i)
    {
      this->AddToRoot(roots.Roots[i], roots.Sizes[i]);
    }
  }
  for (SlabRoots & roots : m_SlabRoots)
  {
    this->TakeSizes(roots);
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
