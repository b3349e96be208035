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
#ifndef itkSmallIsoComponentLabelReference_h
#define itkSmallIsoComponentLabelReference_h

#include "itkIntTypes.h"
#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

namespace itk
{
/** A brute-force implementation of the label-map rule (components of equal labels, removal
 * decided once on the input, repair by a vote of the axis walks), written to be obviously
 * right rather than fast, for the tests to compare the label filter with.
 *
 * It shares no code with the module: components are found by a breadth-first flood fill
 * over single voxels, and every walk steps voxel by voxel through the input. */
namespace SmallIsoComponentLabelReference
{
using HistogramType = std::map<SizeValueType, SizeValueType>; // component size -> number of components

struct LabelStatistics
{
  SizeValueType Components{ 0 }; // components of this label in the input (selected or not)
  SizeValueType RemovedComponents{ 0 };
  SizeValueType RemovedVoxels{ 0 }; // voxels of removed components (unrepairable ones included)
  SizeValueType GainedVoxels{ 0 };  // removed voxels (of other labels) that took this label
  HistogramType Histogram;          // sizes of all this label's components
};

enum class Selection
{
  All,
  AllButBackground,
  BackgroundOnly,
  Listed
};

template <typename TLabel>
struct Parameters
{
  SizeValueType                   MaximumComponentSize{ 20 }; // K
  std::map<TLabel, SizeValueType> MaximumSizePerLabel;        // K for the labels it names
  Selection                       Selected{ Selection::All };
  std::vector<TLabel>             SelectedLabels; // used when Selected == Listed
  TLabel                          Background{ 0 };
  SizeValueType                   KeepLargest{ 0 }; // N; 0: off
  bool                            FullyConnected{ false };
};

template <typename TLabel>
struct Result
{
  std::vector<TLabel>               Output;
  std::vector<uint8_t>              Mask;                    // 1 for every voxel of a removed component, else 0
  std::map<TLabel, LabelStatistics> Labels;                  // one entry per label present in the input
  SizeValueType                     ModifiedVoxels{ 0 };     // voxels whose output label differs from the input
  SizeValueType                     UnrepairableVoxels{ 0 }; // removed voxels for which no walk found anything
};

namespace Detail
{
template <unsigned int VDimension>
using OffsetType = std::array<int64_t, VDimension>;

/** The voxel at \a offset from voxel v, axis 0 varying fastest as in an ITK image buffer;
 * false when it is outside the image. */
template <unsigned int VDimension>
bool
Neighbor(const std::array<SizeValueType, VDimension> & size,
         SizeValueType                                 v,
         const OffsetType<VDimension> &                offset,
         SizeValueType &                               u)
{
  SizeValueType stride = 1;
  u = 0;
  for (unsigned int a = 0; a < VDimension; stride *= size[a], v /= size[a], ++a)
  {
    const int64_t coordinate = static_cast<int64_t>(v % size[a]) + offset[a];
    if (coordinate < 0 || coordinate >= static_cast<int64_t>(size[a]))
    {
      return false;
    }
    u += static_cast<SizeValueType>(coordinate) * stride;
  }
  return true;
}

/** Every offset in {-1, 0, 1}^N but 0; face connectivity keeps those along one axis. */
template <unsigned int VDimension>
std::vector<OffsetType<VDimension>>
NeighborOffsets(bool fullyConnected)
{
  SizeValueType combinations = 1;
  for (unsigned int a = 0; a < VDimension; ++a)
  {
    combinations *= 3;
  }
  std::vector<OffsetType<VDimension>> offsets;
  for (SizeValueType code = 0; code < combinations; ++code)
  {
    OffsetType<VDimension> offset;
    SizeValueType          rest = code;
    unsigned int           nonZero = 0;
    for (unsigned int a = 0; a < VDimension; ++a, rest /= 3)
    {
      offset[a] = static_cast<int64_t>(rest % 3) - 1;
      nonZero += offset[a] != 0 ? 1 : 0;
    }
    if (nonZero == 1 || (nonZero > 1 && fullyConnected))
    {
      offsets.push_back(offset);
    }
  }
  return offsets;
}

template <typename TLabel>
struct Components
{
  std::vector<SizeValueType> Id;     // component of each voxel
  std::vector<SizeValueType> Sizes;  // voxels of each component
  std::vector<TLabel>        Labels; // label of each component
};

template <typename TLabel, unsigned int VDimension>
Components<TLabel>
FindComponents(const std::array<SizeValueType, VDimension> & size, const std::vector<TLabel> & input, bool fully)
{
  constexpr SizeValueType none = std::numeric_limits<SizeValueType>::max();
  const auto              offsets = NeighborOffsets<VDimension>(fully);
  Components<TLabel>      c;
  c.Id.assign(input.size(), none);
  std::deque<SizeValueType> queue;
  for (SizeValueType seed = 0; seed < input.size(); ++seed)
  {
    if (c.Id[seed] != none)
    {
      continue;
    }
    const SizeValueType id = c.Sizes.size();
    c.Sizes.push_back(0);
    c.Labels.push_back(input[seed]);
    c.Id[seed] = id;
    queue.push_back(seed);
    while (!queue.empty())
    {
      const SizeValueType v = queue.front();
      queue.pop_front();
      ++c.Sizes[id];
      for (const auto & offset : offsets)
      {
        SizeValueType u = 0;
        if (Neighbor<VDimension>(size, v, offset, u) && c.Id[u] == none && input[u] == input[seed])
        {
          c.Id[u] = id;
          queue.push_back(u);
        }
      }
    }
  }
  return c;
}

template <typename TLabel>
bool
IsSelected(const Parameters<TLabel> & p, TLabel label)
{
  const auto & listed = p.SelectedLabels;
  return p.Selected == Selection::All || (p.Selected == Selection::AllButBackground && label != p.Background) ||
         (p.Selected == Selection::BackgroundOnly && label == p.Background) ||
         (p.Selected == Selection::Listed && std::find(listed.begin(), listed.end(), label) != listed.end());
}

/** Whether each component is removed: selected, and at most K voxels or smaller than its
 * label's N-th largest component (ties with it are kept, so nothing depends on position). */
template <typename TLabel>
std::vector<uint8_t>
DecideRemovals(const Components<TLabel> & c, const Parameters<TLabel> & p)
{
  std::map<TLabel, std::vector<SizeValueType>> sizesOfLabel; // largest first
  for (SizeValueType id = 0; id < c.Sizes.size(); ++id)
  {
    sizesOfLabel[c.Labels[id]].push_back(c.Sizes[id]);
  }
  for (auto & entry : sizesOfLabel)
  {
    std::sort(entry.second.begin(), entry.second.end(), std::greater<SizeValueType>());
  }
  std::vector<uint8_t> removed(c.Sizes.size(), 0);
  for (SizeValueType id = 0; id < c.Sizes.size(); ++id)
  {
    const TLabel label = c.Labels[id];
    const auto & sizes = sizesOfLabel[label];
    const auto   k = p.MaximumSizePerLabel.find(label);
    const bool   small = c.Sizes[id] <= (k != p.MaximumSizePerLabel.end() ? k->second : p.MaximumComponentSize);
    // A label with fewer than N components loses none by this rule.
    const bool beyond = p.KeepLargest > 0 && sizes.size() >= p.KeepLargest && c.Sizes[id] < sizes[p.KeepLargest - 1];
    removed[id] = IsSelected(p, label) && (small || beyond) ? 1 : 0;
  }
  return removed;
}

/** The new label of voxel v of a removed component, by the vote of the first voxels not in
 * the component met along each axis direction; false when every walk leaves the image. */
template <typename TLabel, unsigned int VDimension>
bool
VoteLabel(const std::array<SizeValueType, VDimension> & size,
          const std::vector<TLabel> &                   input,
          const Components<TLabel> &                    c,
          const std::vector<uint8_t> &                  removed,
          SizeValueType                                 v,
          TLabel &                                      label)
{
  // label -> (votes, steps to its nearest voter), among the kept voxels found and among all.
  std::map<TLabel, std::pair<SizeValueType, SizeValueType>> kept;
  std::map<TLabel, std::pair<SizeValueType, SizeValueType>> all;
  const auto                                                vote = [](auto & tally, TLabel voted, SizeValueType steps) {
    auto & t = tally.emplace(voted, std::make_pair(SizeValueType{ 0 }, steps)).first->second;
    ++t.first;
    t.second = std::min(t.second, steps);
  };
  for (unsigned int axis = 0; axis < VDimension; ++axis)
  {
    for (const int64_t direction : { -1, 1 })
    {
      OffsetType<VDimension> step{};
      step[axis] = direction;
      SizeValueType steps = 1;
      for (SizeValueType w = v, u = 0; Neighbor<VDimension>(size, w, step, u); w = u, ++steps)
      {
        if (input[u] != input[v]) // a voxel of v's label on this line would be in v's component
        {
          vote(all, input[u], steps);
          if (!removed[c.Id[u]])
          {
            vote(kept, input[u], steps);
          }
          break;
        }
      }
    }
  }
  const auto & tally = kept.empty() ? all : kept;
  if (tally.empty())
  {
    return false;
  }
  // Labels ascend in the map, so the smallest wins a tie in votes and steps.
  auto best = tally.begin();
  for (auto it = tally.begin(); it != tally.end(); ++it)
  {
    const auto & [votes, steps] = it->second;
    if (votes > best->second.first || (votes == best->second.first && steps < best->second.second))
    {
      best = it;
    }
  }
  label = best->first;
  return true;
}
} // namespace Detail

/** Runs the label-map rule on a buffer of \a size voxels (axis 0 fastest). */
template <typename TLabel, unsigned int VDimension>
Result<TLabel>
Run(const std::array<SizeValueType, VDimension> & size,
    const std::vector<TLabel> &                   input,
    const Parameters<TLabel> &                    parameters)
{
  if (std::accumulate(size.begin(), size.end(), SizeValueType{ 1 }, std::multiplies<>()) != input.size())
  {
    throw std::invalid_argument("SmallIsoComponentLabelReference::Run: the buffer does not match the size");
  }
  const auto     c = Detail::FindComponents<TLabel, VDimension>(size, input, parameters.FullyConnected);
  const auto     removed = Detail::DecideRemovals(c, parameters);
  Result<TLabel> result;
  result.Output = input;
  result.Mask.assign(input.size(), 0);
  for (SizeValueType id = 0; id < c.Sizes.size(); ++id)
  {
    LabelStatistics & s = result.Labels[c.Labels[id]];
    ++s.Components;
    ++s.Histogram[c.Sizes[id]];
    s.RemovedComponents += removed[id];
    s.RemovedVoxels += removed[id] ? c.Sizes[id] : 0;
  }
  for (SizeValueType v = 0; v < input.size(); ++v)
  {
    if (!removed[c.Id[v]])
    {
      continue;
    }
    result.Mask[v] = 1;
    TLabel label{};
    if (Detail::VoteLabel<TLabel, VDimension>(size, input, c, removed, v, label))
    {
      result.Output[v] = label;
      ++result.Labels[label].GainedVoxels;
      ++result.ModifiedVoxels;
    }
    else
    {
      ++result.UnrepairableVoxels;
    }
  }
  return result;
}
} // namespace SmallIsoComponentLabelReference
} // end namespace itk

#endif
