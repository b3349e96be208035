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

// Checks of the brute-force label-map reference: hand-built cases whose answer follows from
// the rule, properties every result must have on seeded random label maps (checked with
// components found another way, by comparing every pair of voxels), symmetry under flips
// and transpositions, and the relation to the scalar reference on {0, 1} images.

#include "itkSmallIsoComponentLabelReference.h"
#include "itkSmallIsoComponentReference.h"
#include "gtest/gtest.h"
#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>

namespace
{
namespace LabelReference = itk::SmallIsoComponentLabelReference;
using itk::SizeValueType;
using LabelReference::Selection;

template <unsigned int VDimension>
using SizeType = std::array<SizeValueType, VDimension>;

template <typename TLabel, unsigned int VDimension>
struct Case
{
  SizeType<VDimension>               Size;
  std::vector<TLabel>                Input;
  LabelReference::Parameters<TLabel> Parameters;
  std::string                        Description;
};

/** The voxels' coordinates, computed with strides (the reference divides repeatedly). */
template <unsigned int VDimension>
std::vector<std::array<SizeValueType, VDimension>>
IndicesOf(const SizeType<VDimension> & size)
{
  const SizeValueType n = std::accumulate(size.begin(), size.end(), SizeValueType{ 1 }, std::multiplies<>());
  std::vector<std::array<SizeValueType, VDimension>> indices(n);
  for (SizeValueType v = 0; v < n; ++v)
  {
    SizeValueType stride = 1;
    for (unsigned int a = 0; a < VDimension; ++a)
    {
      indices[v][a] = (v / stride) % size[a];
      stride *= size[a];
    }
  }
  return indices;
}

/** The face neighbour of v along an axis, or false at the border. */
template <unsigned int VDimension>
bool
Step(const SizeType<VDimension> & size, SizeValueType v, unsigned int axis, bool up, SizeValueType & u)
{
  const SizeValueType stride =
    std::accumulate(size.begin(), size.begin() + axis, SizeValueType{ 1 }, std::multiplies<>());
  const SizeValueType position = (v / stride) % size[axis];
  if (up ? position + 1 >= size[axis] : position == 0)
  {
    return false;
  }
  u = up ? v + stride : v - stride;
  return true;
}

/** The first voxel of another label met walking from v along an axis, or false. */
template <typename TLabel, unsigned int VDimension>
bool
WalkFrom(const Case<TLabel, VDimension> & c, SizeValueType v, unsigned int axis, bool up, SizeValueType & hit)
{
  for (SizeValueType u = v; Step<VDimension>(c.Size, u, axis, up, u);)
  {
    if (c.Input[u] != c.Input[v])
    {
      hit = u;
      return true;
    }
  }
  return false;
}

/** Components found by testing every pair of voxels for adjacency and merging with a
 * union-find: slow, and independent of the reference's flood fill. */
template <typename TLabel, unsigned int VDimension>
std::vector<SizeValueType>
ComponentOfEachVoxel(const SizeType<VDimension> & size, const std::vector<TLabel> & input, bool fully)
{
  const auto                 index = IndicesOf<VDimension>(size);
  std::vector<SizeValueType> parent(input.size());
  std::iota(parent.begin(), parent.end(), SizeValueType{ 0 });
  const auto root = [&parent](SizeValueType v) {
    while (parent[v] != v)
    {
      v = parent[v];
    }
    return v;
  };
  for (SizeValueType v = 0; v < input.size(); ++v)
  {
    for (SizeValueType u = v + 1; u < input.size(); ++u)
    {
      SizeValueType manhattan = 0;
      SizeValueType chebyshev = 0;
      for (unsigned int a = 0; a < VDimension; ++a)
      {
        const SizeValueType d = index[v][a] > index[u][a] ? index[v][a] - index[u][a] : index[u][a] - index[v][a];
        manhattan += d;
        chebyshev = std::max(chebyshev, d);
      }
      if ((fully ? chebyshev == 1 : manhattan == 1) && input[u] == input[v])
      {
        parent[root(u)] = root(v);
      }
    }
  }
  std::vector<SizeValueType> component(input.size());
  for (SizeValueType v = 0; v < input.size(); ++v)
  {
    component[v] = root(v);
  }
  return component;
}

/** The removal rule, with "smaller than the N-th largest" stated as "at least N components
 * of the label are strictly larger". */
template <typename TLabel>
bool
ShouldBeRemoved(const LabelReference::Parameters<TLabel> & p,
                TLabel                                     label,
                SizeValueType                              componentSize,
                const std::vector<SizeValueType> &         sizesOfLabel)
{
  const bool selected =
    p.Selected == Selection::All || (p.Selected == Selection::AllButBackground && label != p.Background) ||
    (p.Selected == Selection::BackgroundOnly && label == p.Background) ||
    (p.Selected == Selection::Listed && std::count(p.SelectedLabels.begin(), p.SelectedLabels.end(), label) > 0);
  const SizeValueType k = p.MaximumSizePerLabel.count(label) ? p.MaximumSizePerLabel.at(label) : p.MaximumComponentSize;
  const auto          larger =
    std::count_if(sizesOfLabel.begin(), sizesOfLabel.end(), [=](SizeValueType s) { return s > componentSize; });
  return selected && (componentSize <= k || (p.KeepLargest > 0 && SizeValueType(larger) >= p.KeepLargest));
}

/** Whether the new label of repaired voxel v wins the vote of the voxels its walks find:
 * most votes among the kept ones (all when none is kept), then nearest, then smallest. */
template <typename TLabel, unsigned int VDimension>
bool
WinsTheVote(const Case<TLabel, VDimension> &                           c,
            const LabelReference::Result<TLabel> &                     r,
            const std::vector<std::array<SizeValueType, VDimension>> & index,
            SizeValueType                                              v)
{
  const auto &                                  in = c.Input;
  std::vector<std::pair<TLabel, SizeValueType>> all; // (label, steps) of each voxel found
  std::vector<std::pair<TLabel, SizeValueType>> kept;
  for (unsigned int axis = 0; axis < VDimension; ++axis)
  {
    for (const bool up : { false, true })
    {
      SizeValueType u = 0;
      if (WalkFrom(c, v, axis, up, u))
      {
        const SizeValueType steps = std::max(index[u][axis], index[v][axis]) - std::min(index[u][axis], index[v][axis]);
        all.emplace_back(in[u], steps);
        if (r.Mask[u] == 0)
        {
          kept.emplace_back(in[u], steps);
        }
      }
    }
  }
  const auto & voters = kept.empty() ? all : kept;
  const auto   votesFor = [&voters](TLabel label) {
    return std::count_if(voters.begin(), voters.end(), [=](const auto & voter) { return voter.first == label; });
  };
  const auto nearest = [&voters](TLabel label) {
    SizeValueType steps = std::numeric_limits<SizeValueType>::max();
    for (const auto & voter : voters)
    {
      steps = voter.first == label ? std::min(steps, voter.second) : steps;
    }
    return steps;
  };
  const TLabel mine = r.Output[v];
  return votesFor(mine) > 0 && std::none_of(voters.begin(), voters.end(), [&](const auto & voter) {
           const TLabel other = voter.first;
           return votesFor(other) > votesFor(mine) ||
                  (votesFor(other) == votesFor(mine) &&
                   (nearest(other) < nearest(mine) || (nearest(other) == nearest(mine) && other < mine)));
         });
}

/** Whether the statistics are those counted by the test, and the totals add up. */
template <typename TLabel>
std::string
StatisticsViolation(const LabelReference::Result<TLabel> &                    r,
                    const std::map<TLabel, LabelReference::LabelStatistics> & expected,
                    SizeValueType                                             masked,
                    SizeValueType                                             unrepairable)
{
  for (const auto & [label, s] : expected)
  {
    const auto found = r.Labels.find(label);
    if (found == r.Labels.end() || found->second.Components != s.Components ||
        found->second.RemovedComponents != s.RemovedComponents || found->second.RemovedVoxels != s.RemovedVoxels ||
        found->second.GainedVoxels != s.GainedVoxels || found->second.Histogram != s.Histogram)
    {
      std::ostringstream problem;
      problem << "the statistics of label " << +label << " are wrong";
      return problem.str();
    }
  }
  SizeValueType removedVoxels = 0;
  SizeValueType gainedVoxels = 0;
  for (const auto & [label, s] : r.Labels)
  {
    removedVoxels += s.RemovedVoxels;
    gainedVoxels += s.GainedVoxels;
  }
  if (r.Labels.size() != expected.size() || removedVoxels != masked || r.UnrepairableVoxels != unrepairable ||
      gainedVoxels + unrepairable != removedVoxels || r.ModifiedVoxels != gainedVoxels)
  {
    std::ostringstream problem;
    problem << "the totals do not add up: labels " << r.Labels.size() << ", removed " << removedVoxels << ", masked "
            << masked << ", gained " << gainedVoxels << ", unrepairable " << r.UnrepairableVoxels << " (counted "
            << unrepairable << "), modified " << r.ModifiedVoxels;
    return problem.str();
  }
  return "";
}

/** Every property the result must have; returns the first one that fails, else "". */
template <typename TLabel, unsigned int VDimension>
std::string
Violation(const Case<TLabel, VDimension> & c, const LabelReference::Result<TLabel> & r)
{
  std::ostringstream problem;
  const auto &       in = c.Input;
  const auto         index = IndicesOf<VDimension>(c.Size);
  const auto         component = ComponentOfEachVoxel<TLabel, VDimension>(c.Size, in, c.Parameters.FullyConnected);
  std::map<SizeValueType, SizeValueType>       sizeOf;
  std::map<TLabel, std::vector<SizeValueType>> sizesOfLabel;
  std::map<SizeValueType, std::set<TLabel>>    labelsNextTo; // labels face-adjacent to a component
  for (SizeValueType v = 0; v < in.size(); ++v)
  {
    ++sizeOf[component[v]];
    for (unsigned int axis = 0; axis < VDimension; ++axis)
    {
      for (const bool up : { false, true })
      {
        SizeValueType u = 0;
        if (Step<VDimension>(c.Size, v, axis, up, u) && in[u] != in[v])
        {
          labelsNextTo[component[v]].insert(in[u]);
        }
      }
    }
  }
  for (const auto & [root, size] : sizeOf)
  {
    sizesOfLabel[in[root]].push_back(size);
  }
  if (r.Output.size() != in.size() || r.Mask.size() != in.size())
  {
    return "output or mask has the wrong size";
  }
  std::map<TLabel, LabelReference::LabelStatistics> expected;
  for (const auto & [root, size] : sizeOf)
  {
    const bool removed = ShouldBeRemoved(c.Parameters, in[root], size, sizesOfLabel[in[root]]);
    auto &     s = expected[in[root]];
    ++s.Components;
    ++s.Histogram[size];
    s.RemovedComponents += removed ? 1 : 0;
    s.RemovedVoxels += removed ? size : 0;
    if (r.Mask[root] != (removed ? 1 : 0))
    {
      problem << "component of label " << +in[root] << " and size " << size << (removed ? " kept" : " removed");
      return problem.str();
    }
  }
  SizeValueType masked = 0;
  SizeValueType unrepairable = 0;
  for (SizeValueType v = 0; v < in.size(); ++v)
  {
    const bool removed = r.Mask[component[v]] == 1;
    masked += r.Mask[v];
    if (r.Mask[v] != r.Mask[component[v]])
    {
      problem << "the mask is not constant over the component of voxel " << v;
    }
    else if (!removed && r.Output[v] != in[v])
    {
      problem << "kept voxel " << v << " changed from " << +in[v] << " to " << +r.Output[v];
    }
    else if (removed && r.Output[v] == in[v])
    {
      ++unrepairable;
      for (unsigned int axis = 0; axis < VDimension; ++axis)
      {
        SizeValueType u = 0;
        if (WalkFrom(c, v, axis, false, u) || WalkFrom(c, v, axis, true, u))
        {
          problem << "voxel " << v << " left unrepaired though a walk along axis " << axis << " finds " << +in[u];
        }
      }
    }
    else if (removed)
    {
      ++expected[r.Output[v]].GainedVoxels;
      if (labelsNextTo[component[v]].count(r.Output[v]) == 0)
      {
        problem << "voxel " << v << " took label " << +r.Output[v] << ", which is not next to its component";
      }
      if (!WinsTheVote<TLabel, VDimension>(c, r, index, v))
      {
        problem << "voxel " << v << " took label " << +r.Output[v] << ", which does not win the vote";
      }
    }
    if (!problem.str().empty())
    {
      return problem.str();
    }
  }
  return StatisticsViolation(r, expected, masked, unrepairable);
}

/** A seeded random label map: regions of the label of the nearest of a few seeds (large
 * components), sprinkled with voxels of random labels (small ones); random parameters. */
template <typename TLabel, unsigned int VDimension>
Case<TLabel, VDimension>
MakeRandomCase(uint32_t seed, SizeValueType maximumExtent)
{
  std::mt19937             rng(seed);
  const auto               uniform = [&rng](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  Case<TLabel, VDimension> c;
  for (auto & extent : c.Size)
  {
    extent = uniform(1, static_cast<int>(maximumExtent));
  }
  const int        labelCount = std::array<int, 4>{ 2, 3, 5, 9 }[seed % 4];
  const double     density = std::array<double, 4>{ 0.03, 0.15, 0.4, 0.8 }[(seed / 4) % 4];
  const int        lowest = std::is_signed<TLabel>::value ? -20 : 0; // negative labels too when they exist
  std::set<TLabel> values;
  while (values.size() < static_cast<size_t>(labelCount))
  {
    values.insert(static_cast<TLabel>(uniform(lowest, lowest + 40)));
  }
  const std::vector<TLabel> labels(values.begin(), values.end());
  const auto                randomLabel = [&]() { return labels[uniform(0, labelCount - 1)]; };
  const auto                index = IndicesOf<VDimension>(c.Size);
  std::vector<std::pair<std::array<SizeValueType, VDimension>, TLabel>> seeds(uniform(1, 6));
  for (auto & [point, label] : seeds)
  {
    point = index[uniform(0, static_cast<int>(index.size()) - 1)];
    label = randomLabel();
  }
  for (const auto & voxel : index)
  {
    SizeValueType nearest = std::numeric_limits<SizeValueType>::max();
    TLabel        label{};
    for (const auto & [point, seedLabel] : seeds)
    {
      SizeValueType d = 0;
      for (unsigned int a = 0; a < VDimension; ++a)
      {
        d += voxel[a] > point[a] ? voxel[a] - point[a] : point[a] - voxel[a];
      }
      if (d < nearest)
      {
        nearest = d;
        label = seedLabel;
      }
    }
    c.Input.push_back(std::bernoulli_distribution(density)(rng) ? randomLabel() : label);
  }
  auto &                             p = c.Parameters;
  const std::array<SizeValueType, 8> sizes{ 0, 1, 2, 3, 5, 8, 20, 1000 };
  p.MaximumComponentSize = sizes[uniform(0, 7)];
  for (int named = uniform(0, 2); named > 0; --named)
  {
    p.MaximumSizePerLabel[randomLabel()] = sizes[uniform(0, 7)];
  }
  p.Selected = static_cast<Selection>(uniform(0, 3));
  for (const TLabel label : labels)
  {
    if (uniform(0, 1))
    {
      p.SelectedLabels.push_back(label);
    }
  }
  p.Background = uniform(0, 4) ? randomLabel() : static_cast<TLabel>(lowest + 41); // sometimes absent
  p.KeepLargest = std::array<SizeValueType, 5>{ 0, 0, 1, 2, 3 }[uniform(0, 4)];
  p.FullyConnected = uniform(0, 1) == 1;
  std::ostringstream description;
  description << "seed " << seed << ", " << VDimension << "-D, " << labelCount << " labels, density " << density
              << ", K " << p.MaximumComponentSize << " (" << p.MaximumSizePerLabel.size() << " per label), selection "
              << static_cast<int>(p.Selected) << ", background " << +p.Background << ", keep largest " << p.KeepLargest
              << (p.FullyConnected ? ", full" : ", face");
  c.Description = description.str();
  return c;
}

template <typename TLabel, unsigned int VDimension>
void
CheckRandomCases(uint32_t firstSeed, unsigned int count, SizeValueType maximumExtent)
{
  unsigned int failures = 0;
  for (uint32_t seed = firstSeed; seed < firstSeed + count && failures < 3; ++seed)
  {
    const auto        c = MakeRandomCase<TLabel, VDimension>(seed, maximumExtent);
    const std::string problem = Violation(c, LabelReference::Run<TLabel, VDimension>(c.Size, c.Input, c.Parameters));
    if (!problem.empty())
    {
      ADD_FAILURE() << c.Description << ": " << problem;
      ++failures;
    }
  }
}

/** A 2-D label map from rows of digits, the first row at y = 0. */
template <typename TLabel = uint8_t>
Case<TLabel, 2>
FromRows(const std::vector<std::string> & rows)
{
  Case<TLabel, 2> c;
  c.Size = { rows[0].size(), rows.size() };
  for (const auto & row : rows)
  {
    for (const char digit : row)
    {
      c.Input.push_back(static_cast<TLabel>(digit - '0'));
    }
  }
  return c;
}

template <typename TLabel>
LabelReference::Result<TLabel>
RunCase(const Case<TLabel, 2> & c)
{
  return LabelReference::Run<TLabel, 2>(c.Size, c.Input, c.Parameters);
}
/** The image with axes 0 and \a other swapped, or mirrored along axis 0 when other is 0. */
template <typename T, unsigned int VDimension>
std::vector<T>
Transformed(const SizeType<VDimension> & size, const std::vector<T> & image, unsigned int other)
{
  SizeType<VDimension> newSize = size;
  std::swap(newSize[0], newSize[other]);
  const auto     index = IndicesOf<VDimension>(size);
  std::vector<T> result(image.size());
  for (SizeValueType v = 0; v < image.size(); ++v)
  {
    auto i = index[v];
    std::swap(i[0], i[other]);
    i[0] = other == 0 ? size[0] - 1 - i[0] : i[0];
    SizeValueType linear = 0;
    for (unsigned int a = VDimension; a-- > 0;)
    {
      linear = linear * newSize[a] + i[a];
    }
    result[linear] = image[v];
  }
  return result;
}

/** The rule does not depend on position: flipping or transposing the input does the same
 * to the output, and leaves the statistics as they were. */
template <typename TLabel, unsigned int VDimension>
void
CheckSymmetry(uint32_t firstSeed, unsigned int count, SizeValueType maximumExtent)
{
  for (uint32_t seed = firstSeed; seed < firstSeed + count; ++seed)
  {
    const auto c = MakeRandomCase<TLabel, VDimension>(seed, maximumExtent);
    const auto r = LabelReference::Run<TLabel, VDimension>(c.Size, c.Input, c.Parameters);
    for (unsigned int other = 0; other < VDimension; ++other)
    {
      SizeType<VDimension> size = c.Size;
      std::swap(size[0], size[other]);
      const auto t = LabelReference::Run<TLabel, VDimension>(
        size, Transformed<TLabel, VDimension>(c.Size, c.Input, other), c.Parameters);
      const auto output = Transformed<TLabel, VDimension>(c.Size, r.Output, other);
      const auto mask = Transformed<uint8_t, VDimension>(c.Size, r.Mask, other);
      ASSERT_EQ(t.Output, output) << c.Description << ", axis " << other;
      ASSERT_EQ(t.Mask, mask) << c.Description << ", axis " << other;
      ASSERT_EQ(t.UnrepairableVoxels, r.UnrepairableVoxels) << c.Description << ", axis " << other;
      for (const auto & [label, s] : r.Labels)
      {
        ASSERT_EQ(t.Labels.at(label).GainedVoxels, s.GainedVoxels) << c.Description << ", axis " << other;
      }
    }
  }
}

/** Selecting only label 1 (0) of a {0, 1} image is the scalar rule's side Above (Below) at
 * 0.5: the same output and mask, except that the scalar rule gives its unrepairable voxels
 * the other side's value where the label rule leaves them as they were. */
template <unsigned int VDimension>
void
CheckScalarRelation(uint32_t firstSeed, unsigned int count, SizeValueType maximumExtent)
{
  namespace Scalar = itk::SmallIsoComponentReference;
  for (uint32_t seed = firstSeed; seed < firstSeed + count; ++seed)
  {
    std::mt19937         rng(seed);
    const auto           uniform = [&rng](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    SizeType<VDimension> size;
    for (auto & extent : size)
    {
      extent = uniform(1, static_cast<int>(maximumExtent));
    }
    const double         density = std::array<double, 5>{ 0.1, 0.3, 0.5, 0.7, 0.9 }[seed % 5];
    std::vector<uint8_t> input(IndicesOf<VDimension>(size).size());
    for (auto & voxel : input)
    {
      voxel = std::bernoulli_distribution(density)(rng) ? 1 : 0;
    }
    const std::array<SizeValueType, 7>  sizes{ 0, 1, 2, 3, 5, 10, 1000 };
    LabelReference::Parameters<uint8_t> p;
    p.MaximumComponentSize = sizes[uniform(0, 6)];
    p.FullyConnected = uniform(0, 1) == 1;
    p.Selected = Selection::Listed;
    Scalar::Parameters sp;
    sp.IsoValue = 0.5;
    sp.MaximumComponentSize = p.MaximumComponentSize;
    sp.FullyConnected = p.FullyConnected;
    for (const uint8_t selected : { 0, 1 })
    {
      std::ostringstream where;
      where << "seed " << seed << ", " << VDimension << "-D, density " << density << ", K " << p.MaximumComponentSize
            << (p.FullyConnected ? ", full" : ", face") << ", label " << +selected << " selected";
      p.SelectedLabels = { selected };
      sp.Side = selected == 1 ? Scalar::SideEnum::Above : Scalar::SideEnum::Below;
      const auto r = LabelReference::Run<uint8_t, VDimension>(size, input, p);
      const auto s = Scalar::Run<uint8_t, VDimension>(size, input, sp);
      for (SizeValueType v = 0; v < input.size(); ++v)
      {
        const bool    unrepairable = r.Mask[v] == 1 && r.Output[v] == input[v];
        const uint8_t expected = unrepairable ? 1 - selected : r.Output[v];
        ASSERT_EQ(+s.Output[v], +expected) << where.str() << ", voxel " << v;
        ASSERT_EQ(s.Mask[v] != 0, r.Mask[v] == 1) << where.str() << ", voxel " << v;
      }
      const auto & side = selected == 1 ? s.Above : s.Below;
      const auto   label = r.Labels.find(selected);
      const auto   none = LabelReference::LabelStatistics{};
      const auto & l = label != r.Labels.end() ? label->second : none;
      EXPECT_EQ(l.Components, side.Components) << where.str();
      EXPECT_EQ(l.RemovedComponents, side.RemovedComponents) << where.str();
      EXPECT_EQ(l.RemovedVoxels, side.RemovedVoxels) << where.str();
      EXPECT_EQ(l.Histogram, side.Histogram) << where.str();
      EXPECT_EQ(r.UnrepairableVoxels, s.FallbackVoxels) << where.str();
      EXPECT_EQ(r.UnrepairableVoxels, s.UnrepairableVoxels) << where.str();
    }
  }
}
} // namespace

TEST(SmallIsoComponentLabelReference, SpeckTakesTheEnclosingLabel)
{
  const auto c = FromRows({ "11111", "11111", "11211", "11111", "11111" });
  const auto r = RunCase(c);
  EXPECT_EQ(r.Output, std::vector<uint8_t>(25, 1));
  std::vector<uint8_t> mask(25, 0);
  mask[12] = 1;
  EXPECT_EQ(r.Mask, mask);
  EXPECT_EQ(r.Labels.at(2).RemovedComponents, 1u);
  EXPECT_EQ(r.Labels.at(1).RemovedComponents, 0u);
  EXPECT_EQ(r.Labels.at(1).GainedVoxels, 1u);
  EXPECT_EQ(r.Labels.at(1).Histogram, (LabelReference::HistogramType{ { 24, 1 } }));
  EXPECT_EQ(r.ModifiedVoxels, 1u);
  EXPECT_EQ(r.UnrepairableVoxels, 0u);
  EXPECT_EQ(Violation(c, r), "");
}

TEST(SmallIsoComponentLabelReference, EqualVotesAtEqualDistanceGoToTheSmallestLabel)
{
  auto c = FromRows({ "11111", "11311", "13951", "11511", "11111" });
  c.Parameters.Selected = Selection::Listed;
  c.Parameters.SelectedLabels = { 9 };
  EXPECT_EQ(RunCase(c).Output[12], 3);
  // Signed labels compare as numbers: -3 wins over 2.
  Case<int16_t, 2> s;
  s.Size = c.Size;
  s.Input.assign(c.Input.begin(), c.Input.end());
  std::replace(s.Input.begin(), s.Input.end(), int16_t{ 3 }, int16_t{ -3 });
  std::replace(s.Input.begin(), s.Input.end(), int16_t{ 5 }, int16_t{ 2 });
  s.Parameters.Selected = Selection::Listed;
  s.Parameters.SelectedLabels = { 9 };
  EXPECT_EQ(RunCase(s).Output[12], -3);
}

TEST(SmallIsoComponentLabelReference, EqualVotesGoToTheNearerLabel)
{
  // The component of 9s is an L; its corner sees 5 at one step twice and 3 at two steps twice.
  auto c = FromRows({ "1111111", "1111111", "1115111", "1159931", "1119111", "1113111", "1111111" });
  c.Parameters.Selected = Selection::Listed;
  c.Parameters.SelectedLabels = { 9 };
  const auto r = RunCase(c);
  EXPECT_EQ(r.Output[3 * 7 + 3], 5);
  EXPECT_EQ(r.Output[3 * 7 + 4], 1); // 1 twice, 5 and 3 once
  EXPECT_EQ(r.Output[4 * 7 + 3], 1);
  EXPECT_EQ(r.Labels.at(9).RemovedVoxels, 3u);
  EXPECT_EQ(Violation(c, r), "");
}

TEST(SmallIsoComponentLabelReference, KeptComponentsOutvoteRemovedOnes)
{
  // The 9 sees three removed single 7s and one kept 4; each 7 sees kept 1s (and 4) and the removed 9.
  auto c = FromRows({ "11144", "11744", "17944", "11744", "11144" });
  c.Parameters.MaximumComponentSize = 2;
  const auto r = RunCase(c);
  const auto e = FromRows({ "11144", "11144", "11444", "11144", "11144" });
  EXPECT_EQ(r.Output, e.Input);
  EXPECT_EQ(r.Labels.at(7).RemovedComponents, 3u);
  EXPECT_EQ(r.Labels.at(1).GainedVoxels, 3u);
  EXPECT_EQ(r.Labels.at(4).GainedVoxels, 1u);
  EXPECT_EQ(Violation(c, r), "");
}

TEST(SmallIsoComponentLabelReference, RemovalsAreDecidedOnceOnTheInput)
{
  // Every component is removed, so every voxel votes among all it finds: the labels swap.
  auto c = FromRows({ "121" });
  c.Parameters.MaximumComponentSize = 1;
  const auto r = RunCase(c);
  EXPECT_EQ(r.Output, (std::vector<uint8_t>{ 2, 1, 2 }));
  EXPECT_EQ(r.Mask, (std::vector<uint8_t>{ 1, 1, 1 }));
  EXPECT_EQ(r.Labels.at(2).GainedVoxels, 2u);
  EXPECT_EQ(Violation(c, r), "");
}

TEST(SmallIsoComponentLabelReference, ComponentFillingTheImageIsUnrepairable)
{
  const auto c = FromRows({ "44", "44" });
  const auto r = RunCase(c);
  EXPECT_EQ(r.Output, c.Input);
  EXPECT_EQ(r.Mask, (std::vector<uint8_t>{ 1, 1, 1, 1 }));
  EXPECT_EQ(r.UnrepairableVoxels, 4u);
  EXPECT_EQ(r.ModifiedVoxels, 0u);
  EXPECT_EQ(r.Labels.at(4).RemovedVoxels, 4u);
}

TEST(SmallIsoComponentLabelReference, KeepLargestKeepsTiesWithTheNthLargest)
{
  // Components of 1 with 3, 2, 2 and 1 voxels.
  auto c = FromRows({ "111011011010" });
  c.Parameters.MaximumComponentSize = 0;
  c.Parameters.Selected = Selection::Listed;
  c.Parameters.SelectedLabels = { 1 };
  const std::map<SizeValueType, SizeValueType> removedVoxels{ { 1, 5 }, { 2, 1 }, { 3, 1 }, { 4, 0 }, { 5, 0 } };
  for (const auto & [keep, removed] : removedVoxels)
  {
    c.Parameters.KeepLargest = keep;
    const auto r = RunCase(c);
    EXPECT_EQ(r.Labels.at(1).RemovedVoxels, removed) << "keep largest " << keep;
    EXPECT_EQ(r.Labels.at(0).RemovedVoxels, 0u);
    EXPECT_EQ(Violation(c, r), "") << "keep largest " << keep;
  }
}

TEST(SmallIsoComponentLabelReference, RandomLabelMapsHaveTheRuleProperties)
{
  CheckRandomCases<uint8_t, 2>(1, 200, 24);
  CheckRandomCases<int16_t, 2>(1001, 200, 24);
  CheckRandomCases<uint8_t, 3>(2001, 150, 10);
  CheckRandomCases<int16_t, 3>(3001, 150, 10);
  CheckRandomCases<int16_t, 4>(4001, 100, 5);
}

TEST(SmallIsoComponentLabelReference, FlipsAndTranspositionsCommuteWithTheRule)
{
  CheckSymmetry<uint8_t, 2>(5001, 100, 16);
  CheckSymmetry<int16_t, 3>(6001, 60, 8);
  CheckSymmetry<int16_t, 4>(7001, 30, 5);
}

TEST(SmallIsoComponentLabelReference, TwoLabelsMatchTheScalarRuleOneSideAtATime)
{
  CheckScalarRelation<2>(8001, 300, 24);
  CheckScalarRelation<3>(9001, 200, 10);
  CheckScalarRelation<4>(10001, 50, 5);
}
