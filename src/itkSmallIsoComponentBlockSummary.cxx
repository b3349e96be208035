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
#include "itkSmallIsoComponentBlockSummary.h"
#include "itkMacro.h"
#include "itkSmallIsoComponentUnionFind.h"
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace itk
{
namespace SmallIsoComponentDetail
{
uint64_t
ComponentRules::MaximumSizeForVolume(double volume, double voxelVolume)
{
  const double voxels = volume / voxelVolume * (1.0 + 1e-12);
  return voxels >= static_cast<double>(std::numeric_limits<uint64_t>::max())
           ? std::numeric_limits<uint64_t>::max()
           : static_cast<uint64_t>(std::floor(voxels));
}

void
SideTally::Add(uint64_t size, bool removed)
{
  ++m_Components;
  if (removed)
  {
    ++m_RemovedComponents;
    m_RemovedVoxels += size;
  }
  if (size < SmallSizes)
  {
    if (m_Small.empty())
    {
      m_Small.assign(SmallSizes, 0);
    }
    ++m_Small[size];
  }
  else
  {
    ++m_Large[size];
  }
}

void
SideTally::Add(const SideTally & other)
{
  m_Components += other.m_Components;
  m_RemovedComponents += other.m_RemovedComponents;
  m_RemovedVoxels += other.m_RemovedVoxels;
  if (!other.m_Small.empty())
  {
    if (m_Small.empty())
    {
      m_Small.assign(SmallSizes, 0);
    }
    for (uint64_t size = 0; size < SmallSizes; ++size)
    {
      m_Small[size] += other.m_Small[size];
    }
  }
  for (const auto & entry : other.m_Large)
  {
    m_Large[entry.first] += entry.second;
  }
}

std::map<uint64_t, uint64_t>
SideTally::GetHistogram() const
{
  std::map<uint64_t, uint64_t> histogram = m_Large;
  for (uint64_t size = 0; size < m_Small.size(); ++size)
  {
    if (m_Small[size] > 0)
    {
      histogram[size] += m_Small[size];
    }
  }
  return histogram;
}

void
ComponentTally::Add(const ComponentTally & other)
{
  Above.Add(other.Above);
  Below.Add(other.Below);
  ModifiedVoxels += other.ModifiedVoxels;
  UnrepairableVoxels += other.UnrepairableVoxels;
}

namespace
{
using NodeType = BlockSummary::NodeType;

template <typename T>
std::vector<T>
Concatenate(std::vector<T> a, const std::vector<T> & b)
{
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
} // namespace

BlockSummary::BlockSummary(const IndexType &      imageSize,
                           const IndexType &      begin,
                           const IndexType &      end,
                           const ComponentRules & rules)
  : m_ImageSize(imageSize)
  , m_Begin(begin)
  , m_End(end)
  , m_Rules(rules)
{
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    if (!(begin[axis] < end[axis] && end[axis] <= imageSize[axis]))
    {
      itkGenericExceptionMacro("BlockSummary: the box [" << begin[axis] << ", " << end[axis] << ") along axis " << axis
                                                         << " is empty or outside the image of " << imageSize[axis]
                                                         << " voxels");
    }
  }
}

auto
BlockSummary::AddComponent(bool above, uint64_t size) -> NodeType
{
  if (m_Size.size() >= NoNode)
  {
    itkGenericExceptionMacro("BlockSummary: a box holds at most " << NoNode - 1 << " components");
  }
  m_Size.push_back(size);
  m_Above.push_back(above ? 1 : 0);
  m_Flipped.push_back(0);
  return static_cast<NodeType>(m_Size.size() - 1);
}

bool
BlockSummary::HasFace(unsigned int axis, bool upper) const
{
  return upper ? m_End[axis] < m_ImageSize[axis] : m_Begin[axis] > 0;
}

std::array<unsigned int, 2>
BlockSummary::FaceAxes(unsigned int axis)
{
  return axis == 0 ? std::array<unsigned int, 2>{ 1, 2 }
                   : (axis == 1 ? std::array<unsigned int, 2>{ 0, 2 } : std::array<unsigned int, 2>{ 0, 1 });
}

SizeValueType
BlockSummary::FaceLayerSize(unsigned int axis) const
{
  const auto axes = FaceAxes(axis);
  return this->Extent(axes[0]) * this->Extent(axes[1]);
}

SizeValueType
BlockSummary::FaceRowWidth(unsigned int axis) const
{
  return this->Extent(FaceAxes(axis)[0]);
}

SizeValueType
BlockSummary::FaceRows(unsigned int axis) const
{
  return this->Extent(FaceAxes(axis)[1]);
}

void
BlockSummary::SetFaceLayer(unsigned int axis, bool upper, const std::vector<NodeType> & layer)
{
  if (!this->HasFace(axis, upper) || layer.size() != this->FaceLayerSize(axis))
  {
    itkGenericExceptionMacro("BlockSummary: a face layer of axis " << axis << " needs " << this->FaceLayerSize(axis)
                                                                   << " entries and a face inside the image");
  }
  const SizeValueType width = this->FaceRowWidth(axis);
  const SizeValueType rows = this->FaceRows(axis);
  FaceLayer           runs;
  runs.RowBegin.reserve(rows + 1);
  for (SizeValueType row = 0; row < rows; ++row)
  {
    runs.BeginRow();
    for (SizeValueType column = 0; column < width; ++column)
    {
      runs.AddVoxels(column, layer[row * width + column]);
    }
  }
  runs.EndLayer();
  this->SetFaceLayer(axis, upper, std::move(runs));
}

void
BlockSummary::SetFaceLayer(unsigned int axis, bool upper, FaceLayer layer)
{
  if (!this->HasFace(axis, upper) || !this->IsValidFaceLayer(axis, layer, NoNode))
  {
    itkGenericExceptionMacro("BlockSummary: a face layer of axis " << axis << " needs " << this->FaceRows(axis)
                                                                   << " rows of runs over " << this->FaceRowWidth(axis)
                                                                   << " voxels and a face inside the image");
  }
  m_Face[FaceIndex(axis, upper)] = std::move(layer);
}

bool
BlockSummary::IsValidFaceLayer(unsigned int axis, const FaceLayer & layer, SizeValueType nodes) const
{
  const SizeValueType width = this->FaceRowWidth(axis);
  const SizeValueType rows = this->FaceRows(axis);
  if (width > std::numeric_limits<uint32_t>::max() || layer.RowBegin.size() != rows + 1 || layer.RowBegin[0] != 0 ||
      layer.RowBegin[rows] != layer.Runs.size())
  {
    return false;
  }
  for (SizeValueType row = 0; row < rows; ++row)
  {
    const SizeValueType first = layer.RowBegin[row];
    const SizeValueType last = layer.RowBegin[row + 1];
    if (first >= last || last > layer.Runs.size() || layer.Runs[first].Column != 0)
    {
      return false;
    }
    for (SizeValueType run = first; run < last; ++run)
    {
      const FaceRun & r = layer.Runs[run];
      if (r.Node >= nodes || r.Column >= width || (run > first && r.Column <= layer.Runs[run - 1].Column))
      {
        return false;
      }
    }
  }
  return true;
}

bool
BlockSummary::NeedsTouching(uint64_t aboveSize) const
{
  return m_Rules.Side == SmallIsoComponentEnums::Side::Both && m_Rules.AnyBelow &&
         aboveSize <= m_Rules.MaximumComponentSize;
}

void
BlockSummary::AddTouching(NodeType above, NodeType below)
{
  m_Touching.emplace_back(above, below);
}

void
BlockSummary::Settle(std::vector<Resolution> * resolutions)
{
  std::vector<NodeType> parent(m_Size.size());
  for (NodeType node = 0; node < parent.size(); ++node)
  {
    parent[node] = node;
  }
  std::vector<std::pair<NodeType, NodeType>> touching;
  touching.swap(m_Touching);
  this->SettleNodes(parent, touching, resolutions);
}

struct BlockSummary::Settling
{
  Settling(std::vector<NodeType> & parentOfNode, std::vector<std::pair<NodeType, NodeType>> & touchingPairs)
    : parent(parentOfNode)
    , touching(touchingPairs)
    , nodes(parentOfNode.size())
    , root(nodes)
    , aboveState(nodes, State::NotAbove)
    , belowState(nodes, State::Open)
    , blocked(nodes, 0)
    , newNode(nodes, NoNode)
  {}

  NodeType
  Root(NodeType node)
  {
    return FindRoot(parent.data(), node);
  }

  /** Marks the roots of the nodes on a face: their components may still grow. */
  void
  MarkOpen(const std::array<FaceLayer, 6> & faces)
  {
    // The faces hold many voxels per node: the roots are found once per node, not once per voxel.
    for (NodeType node = 0; node < nodes; ++node)
    {
      root[node] = this->Root(node);
    }
    open.assign(nodes, 0);
    for (const auto & layer : faces)
    {
      for (const FaceRun & run : layer.Runs)
      {
        open[root[run.Node]] = 1;
      }
    }
  }

  std::vector<NodeType> &                      parent;
  std::vector<std::pair<NodeType, NodeType>> & touching;
  const SizeValueType                          nodes;
  std::vector<NodeType>                        root;
  std::vector<uint8_t>                         open;
  std::vector<State>                           aboveState;
  std::vector<State>                           belowState;
  /** Below roots that an above component which may still be removed touches. */
  std::vector<uint8_t> blocked;
  /** Whether Side Both's below pass sees any removed above component as below. */
  bool anyFlipped{ false };
  /** Per root that stays, its node in the rebuilt summary; NoNode for the others. */
  std::vector<NodeType> newNode;
  /** The rebuilt summary's arrays, put in place once the resolutions are read. */
  std::vector<uint64_t>                      keptSize;
  std::vector<uint8_t>                       keptAbove;
  std::vector<uint64_t>                      keptFlipped;
  std::vector<std::pair<NodeType, NodeType>> keptTouching;
};

void
BlockSummary::SettleNodes(std::vector<NodeType> &                      parent,
                          std::vector<std::pair<NodeType, NodeType>> & touching,
                          std::vector<Resolution> *                    resolutions)
{
  Settling                   settling(parent, touching);
  const std::vector<uint8_t> wasAbove(m_Above.begin(), m_Above.end());
  settling.MarkOpen(m_Face);
  this->DecideAbovePass(settling);
  if (settling.anyFlipped)
  {
    this->JoinFlippedToTouching(settling);
    settling.MarkOpen(m_Face);
  }
  this->DecideBelowPass(settling);
  this->KeepOpenNodes(settling);
  if (resolutions != nullptr)
  {
    this->Resolve(settling, wasAbove, *resolutions);
  }
  m_Size.swap(settling.keptSize);
  m_Above.swap(settling.keptAbove);
  m_Flipped.swap(settling.keptFlipped);
  m_Touching.swap(settling.keptTouching);
}

void
BlockSummary::DecideAbovePass(Settling & settling)
{
  // Complete above components are final; open ones may still grow.
  const bool aboveProcessed = m_Rules.Side != SmallIsoComponentEnums::Side::Below;
  const bool both = m_Rules.Side == SmallIsoComponentEnums::Side::Both;
  for (NodeType node = 0; node < settling.nodes; ++node)
  {
    if (settling.parent[node] != node || !m_Above[node])
    {
      continue;
    }
    const uint64_t size = m_Size[node];
    const bool     small = aboveProcessed && size <= m_Rules.MaximumComponentSize;
    if (settling.open[node])
    {
      settling.aboveState[node] = small && m_Rules.AnyBelow ? State::Open : State::Kept;
      continue;
    }
    const bool removed = small && m_Rules.AnyBelow;
    m_Tally.Above.Add(size, removed);
    settling.aboveState[node] = removed ? State::Removed : State::Kept;
    if (removed)
    {
      m_Tally.ModifiedVoxels += size;
      if (both)
      {
        // As the below pass sees it, the component is below now.
        m_Above[node] = 0;
        m_Flipped[node] = size;
        settling.anyFlipped = true;
      }
    }
    else if (small)
    {
      m_Tally.UnrepairableVoxels += size;
    }
  }
}

void
BlockSummary::JoinFlippedToTouching(Settling & settling)
{
  // A removed above component joins the below components it touches.
  std::vector<std::pair<NodeType, NodeType>> joins;
  for (const auto & pair : settling.touching)
  {
    const NodeType above = settling.Root(pair.first);
    if (settling.aboveState[above] == State::Removed)
    {
      joins.emplace_back(above, pair.second);
    }
  }
  for (auto [a, b] : joins)
  {
    if (JoinRoots(settling.parent.data(), a, b))
    {
      m_Size[a] += m_Size[b];
      m_Flipped[a] += m_Flipped[b];
    }
  }
}

void
BlockSummary::DecideBelowPass(Settling & settling)
{
  // A below component (with the removed above ones joined to it) is final when it is complete
  // and no above component that may still be removed touches it.
  for (const auto & pair : settling.touching)
  {
    const NodeType above = settling.Root(pair.first);
    if (m_Above[above] && settling.aboveState[above] == State::Open)
    {
      settling.blocked[settling.Root(pair.second)] = 1;
    }
  }
  const bool belowProcessed = m_Rules.Side != SmallIsoComponentEnums::Side::Above;
  for (NodeType node = 0; node < settling.nodes; ++node)
  {
    if (settling.parent[node] != node || m_Above[node])
    {
      continue;
    }
    const uint64_t size = m_Size[node];
    const bool     small = belowProcessed && size <= m_Rules.MaximumComponentSize;
    if (settling.open[node] || settling.blocked[node])
    {
      settling.belowState[node] = small && m_Rules.AnyAbove ? State::Open : State::Kept;
      continue;
    }
    const bool removed = small && m_Rules.AnyAbove;
    m_Tally.Below.Add(size, removed);
    settling.belowState[node] = removed ? State::Removed : State::Kept;
    if (removed)
    {
      m_Tally.ModifiedVoxels += size - m_Flipped[node];
    }
    else if (small)
    {
      m_Tally.UnrepairableVoxels += size;
    }
  }
}

void
BlockSummary::KeepOpenNodes(Settling & settling)
{
  // What stays: open above components, and below components that are open or waiting.
  for (NodeType node = 0; node < settling.nodes; ++node)
  {
    if (settling.parent[node] != node)
    {
      continue;
    }
    const bool open = settling.open[node] != 0;
    if (m_Above[node] ? open : (open || settling.blocked[node] != 0))
    {
      settling.newNode[node] = static_cast<NodeType>(settling.keptSize.size());
      settling.keptSize.push_back(m_Size[node]);
      settling.keptAbove.push_back(m_Above[node]);
      settling.keptFlipped.push_back(m_Flipped[node]);
    }
  }
  for (NodeType node = 0; node < settling.nodes; ++node)
  {
    settling.root[node] = settling.newNode[settling.Root(node)];
  }
  // The faces in the new numbering; runs of one component that are now side by side are one.
  for (auto & layer : m_Face)
  {
    if (layer.RowBegin.empty())
    {
      continue;
    }
    SizeValueType kept = 0;
    const auto    rows = layer.RowBegin.size() - 1;
    for (SizeValueType row = 0; row < rows; ++row)
    {
      const SizeValueType first = layer.RowBegin[row];
      const SizeValueType last = layer.RowBegin[row + 1];
      layer.RowBegin[row] = kept;
      for (SizeValueType run = first; run < last; ++run)
      {
        const NodeType node = settling.root[layer.Runs[run].Node];
        if (run == first || layer.Runs[kept - 1].Node != node)
        {
          layer.Runs[kept++] = { layer.Runs[run].Column, node };
        }
      }
    }
    layer.RowBegin[rows] = kept;
    layer.Runs.resize(kept);
  }
  auto & kept = settling.keptTouching;
  for (const auto & pair : settling.touching)
  {
    const NodeType a = settling.Root(pair.first);
    if (m_Above[a] && settling.aboveState[a] == State::Open)
    {
      kept.emplace_back(settling.newNode[a], settling.newNode[settling.Root(pair.second)]);
    }
  }
  std::sort(kept.begin(), kept.end());
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
}

void
BlockSummary::Resolve(Settling &                   settling,
                      const std::vector<uint8_t> & wasAbove,
                      std::vector<Resolution> &    resolutions) const
{
  resolutions.resize(settling.nodes);
  for (NodeType node = 0; node < settling.nodes; ++node)
  {
    const NodeType root = settling.Root(node);
    Resolution &   resolution = resolutions[node];
    if (wasAbove[node])
    {
      // The above component's root before any join into a below component.
      if (m_Above[root])
      {
        resolution.AbovePass = settling.aboveState[root];
        resolution.BelowPass = State::Kept;
        resolution.Node = settling.aboveState[root] == State::Open ? settling.newNode[root] : NoNode;
        continue;
      }
      resolution.AbovePass = State::Removed;
    }
    else
    {
      resolution.AbovePass = State::NotAbove;
    }
    resolution.BelowPass = settling.belowState[root];
    resolution.Node = settling.belowState[root] == State::Open ? settling.newNode[root] : NoNode;
  }
}

BlockSummary
BlockSummary::Merge(const BlockSummary &      lower,
                    const BlockSummary &      upper,
                    std::vector<Resolution> * lowerResolutions,
                    std::vector<Resolution> * upperResolutions)
{
  if (lower.m_ImageSize != upper.m_ImageSize)
  {
    itkGenericExceptionMacro("BlockSummary::Merge: the two boxes belong to images of different sizes");
  }
  const unsigned int axis = SharedFaceAxis(lower, upper);

  BlockSummary merged;
  merged.m_ImageSize = lower.m_ImageSize;
  merged.m_Begin = lower.m_Begin;
  merged.m_End = upper.m_End;
  merged.m_Rules = lower.m_Rules;
  merged.m_Tally = lower.m_Tally;
  merged.m_Tally.Add(upper.m_Tally);
  const auto offset = static_cast<NodeType>(lower.m_Size.size());
  if (SizeValueType{ offset } + upper.m_Size.size() >= NoNode)
  {
    itkGenericExceptionMacro("BlockSummary::Merge: the merged boxes hold too many open components");
  }
  merged.m_Size = Concatenate(lower.m_Size, upper.m_Size);
  merged.m_Above = Concatenate(lower.m_Above, upper.m_Above);
  merged.m_Flipped = Concatenate(lower.m_Flipped, upper.m_Flipped);
  const SizeValueType   nodes = merged.m_Size.size();
  std::vector<NodeType> parent(nodes);
  for (NodeType node = 0; node < nodes; ++node)
  {
    parent[node] = node;
  }
  std::vector<std::pair<NodeType, NodeType>> touching = lower.m_Touching;
  for (const auto & pair : upper.m_Touching)
  {
    touching.emplace_back(pair.first + offset, pair.second + offset);
  }
  merged.SetUnionFaces(lower, upper, axis);
  merged.JoinAcrossFace(lower, upper, axis, parent, touching);

  std::vector<Resolution> resolutions;
  merged.SettleNodes(
    parent, touching, lowerResolutions != nullptr || upperResolutions != nullptr ? &resolutions : nullptr);
  if (lowerResolutions != nullptr)
  {
    lowerResolutions->assign(resolutions.begin(), resolutions.begin() + offset);
  }
  if (upperResolutions != nullptr)
  {
    upperResolutions->assign(resolutions.begin() + offset, resolutions.end());
  }
  return merged;
}

unsigned int
BlockSummary::SharedFaceAxis(const BlockSummary & lower, const BlockSummary & upper)
{
  unsigned int axis = 3;
  for (unsigned int a = 0; a < 3; ++a)
  {
    if (lower.m_End[a] == upper.m_Begin[a] && lower.m_Begin[a] < upper.m_Begin[a])
    {
      bool othersMatch = true;
      for (unsigned int b = 0; b < 3; ++b)
      {
        othersMatch =
          othersMatch && (b == a || (lower.m_Begin[b] == upper.m_Begin[b] && lower.m_End[b] == upper.m_End[b]));
      }
      if (othersMatch)
      {
        axis = a;
      }
    }
  }
  if (axis == 3)
  {
    itkGenericExceptionMacro("BlockSummary::Merge: the upper box does not start where the lower one ends along one "
                             "axis with the same range along the others");
  }
  return axis;
}

void
BlockSummary::SetUnionFaces(const BlockSummary & lower, const BlockSummary & upper, unsigned int axis)
{
  const auto offset = static_cast<NodeType>(lower.m_Size.size());
  // The faces of the union: along the merge axis the outer faces of the two boxes, along the
  // others the two layers side by side.
  const auto upperLayer = [offset](FaceLayer layer) {
    for (FaceRun & run : layer.Runs)
    {
      run.Node += offset;
    }
    return layer;
  };
  m_Face[FaceIndex(axis, false)] = lower.m_Face[FaceIndex(axis, false)];
  m_Face[FaceIndex(axis, true)] = upperLayer(upper.m_Face[FaceIndex(axis, true)]);
  for (unsigned int b = 0; b < 3; ++b)
  {
    if (b == axis)
    {
      continue;
    }
    const auto faceAxes = FaceAxes(b);
    for (const bool side : { false, true })
    {
      const FaceLayer & low = lower.m_Face[FaceIndex(b, side)];
      if (low.RowBegin.empty())
      {
        continue;
      }
      const FaceLayer high = upperLayer(upper.m_Face[FaceIndex(b, side)]);
      FaceLayer       layer;
      if (faceAxes[1] == axis)
      {
        // The merge axis runs across the rows: the rows of the upper box follow.
        layer.RowBegin = low.RowBegin;
        for (SizeValueType row = 1; row < high.RowBegin.size(); ++row)
        {
          layer.RowBegin.push_back(low.Runs.size() + high.RowBegin[row]);
        }
        layer.Runs = Concatenate(low.Runs, high.Runs);
      }
      else
      {
        // The merge axis runs along the rows: each row of the upper box follows its row of the
        // lower one.
        const SizeValueType lowRow = lower.Extent(axis);
        if (lowRow + upper.Extent(axis) > std::numeric_limits<uint32_t>::max())
        {
          itkGenericExceptionMacro("BlockSummary::Merge: a face row of the union is longer than "
                                   << std::numeric_limits<uint32_t>::max() << " voxels");
        }
        const SizeValueType rows = low.RowBegin.size() - 1;
        layer.RowBegin.reserve(rows + 1);
        layer.Runs.reserve(low.Runs.size() + high.Runs.size());
        for (SizeValueType row = 0; row < rows; ++row)
        {
          layer.BeginRow();
          layer.Runs.insert(
            layer.Runs.end(), low.Runs.begin() + low.RowBegin[row], low.Runs.begin() + low.RowBegin[row + 1]);
          for (SizeValueType run = high.RowBegin[row]; run < high.RowBegin[row + 1]; ++run)
          {
            layer.Runs.push_back({ static_cast<uint32_t>(high.Runs[run].Column + lowRow), high.Runs[run].Node });
          }
        }
        layer.EndLayer();
      }
      m_Face[FaceIndex(b, side)] = std::move(layer);
    }
  }
}

void
BlockSummary::JoinAcrossFace(const BlockSummary &                         lower,
                             const BlockSummary &                         upper,
                             unsigned int                                 axis,
                             std::vector<NodeType> &                      parent,
                             std::vector<std::pair<NodeType, NodeType>> & touching)
{
  const auto offset = static_cast<NodeType>(lower.m_Size.size());
  // Join the components that touch across the shared face; note which above components that
  // may be small touch which below ones there.
  const FaceLayer &   lowFace = lower.m_Face[FaceIndex(axis, true)];
  const FaceLayer &   highFace = upper.m_Face[FaceIndex(axis, false)];
  const SizeValueType width = lower.FaceRowWidth(axis);
  const SizeValueType height = lower.FaceRows(axis);
  const int           reach = m_Rules.FullyConnected ? 1 : 0;
  NodeType            lastA = NoNode;
  NodeType            lastB = NoNode;
  const auto          link = [&](NodeType a, NodeType b) {
    if (a == lastA && b == lastB)
    {
      return;
    }
    lastA = a;
    lastB = b;
    if (m_Above[a] == m_Above[b])
    {
      NodeType ra = a;
      NodeType rb = b;
      if (JoinRoots(parent.data(), ra, rb))
      {
        m_Size[ra] += m_Size[rb];
        m_Flipped[ra] += m_Flipped[rb];
      }
    }
    else
    {
      const NodeType above = m_Above[a] ? a : b;
      const NodeType below = m_Above[a] ? b : a;
      if (this->NeedsTouching(m_Size[above]))
      {
        touching.emplace_back(above, below);
      }
    }
  };
  // Voxel i of a row touches voxels i - reach .. i + reach of the rows reach or fewer away: two
  // runs [s, e) and [s', e') touch when s' < e + reach and s < e' + reach.
  const auto runEnd = [width](const FaceLayer & layer, SizeValueType row, SizeValueType run) {
    return run + 1 < layer.RowBegin[row + 1] ? SizeValueType{ layer.Runs[run + 1].Column } : width;
  };
  for (SizeValueType j = 0; j < height; ++j)
  {
    const SizeValueType firstRow = j >= SizeValueType(reach) ? j - reach : 0;
    const SizeValueType lastRow = std::min(height - 1, j + reach);
    for (SizeValueType jj = firstRow; jj <= lastRow; ++jj)
    {
      SizeValueType       q = highFace.RowBegin[jj];
      const SizeValueType qEnd = highFace.RowBegin[jj + 1];
      for (SizeValueType p = lowFace.RowBegin[j]; p < lowFace.RowBegin[j + 1]; ++p)
      {
        const SizeValueType s = lowFace.Runs[p].Column;
        const SizeValueType e = runEnd(lowFace, j, p);
        while (q < qEnd && runEnd(highFace, jj, q) + reach <= s)
        {
          ++q;
        }
        for (SizeValueType r = q; r < qEnd && highFace.Runs[r].Column < e + reach; ++r)
        {
          link(lowFace.Runs[p].Node, highFace.Runs[r].Node + offset);
        }
      }
    }
  }
}

namespace
{
/** Native byte order: summaries move between processes of one kind of machine. */
class Writer
{
public:
  template <typename T>
  void
  Put(const T & value)
  {
    const auto * bytes = reinterpret_cast<const uint8_t *>(&value);
    m_Data.insert(m_Data.end(), bytes, bytes + sizeof(T));
  }
  template <typename T>
  void
  PutVector(const std::vector<T> & values)
  {
    this->Put<uint64_t>(values.size());
    const auto * bytes = reinterpret_cast<const uint8_t *>(values.data());
    m_Data.insert(m_Data.end(), bytes, bytes + values.size() * sizeof(T));
  }
  std::vector<uint8_t> &
  Data()
  {
    return m_Data;
  }

private:
  std::vector<uint8_t> m_Data;
};

class Reader
{
public:
  Reader(const uint8_t * data, SizeValueType bytes)
    : m_Data(data)
    , m_Bytes(bytes)
  {}
  template <typename T>
  T
  Get()
  {
    this->Need(sizeof(T));
    T value;
    std::memcpy(&value, m_Data + m_Position, sizeof(T));
    m_Position += sizeof(T);
    return value;
  }
  template <typename T>
  std::vector<T>
  GetVector()
  {
    const auto     count = this->Get<uint64_t>();
    std::vector<T> values;
    if (count > (m_Bytes - m_Position) / sizeof(T))
    {
      this->Fail();
    }
    values.resize(count);
    if (count > 0) // an empty vector's data() may be null, which memcpy may not be given
    {
      std::memcpy(static_cast<void *>(values.data()), m_Data + m_Position, count * sizeof(T));
    }
    m_Position += count * sizeof(T);
    return values;
  }
  bool
  AtEnd() const
  {
    return m_Position == m_Bytes;
  }

private:
  void
  Need(SizeValueType bytes) const
  {
    if (bytes > m_Bytes - m_Position)
    {
      this->Fail();
    }
  }
  [[noreturn]] void
  Fail() const
  {
    itkGenericExceptionMacro("BlockSummary::Deserialize: the data is truncated or not a block summary");
  }
  const uint8_t * m_Data;
  SizeValueType   m_Bytes;
  SizeValueType   m_Position{ 0 };
};

constexpr uint32_t SummaryMagic = 0x32424953; // "SIB2": faces as runs

void
PutTally(Writer & writer, const SideTally & tally, const std::vector<std::pair<uint64_t, uint64_t>> & histogram)
{
  writer.Put(tally.GetComponents());
  writer.Put(tally.GetRemovedComponents());
  writer.Put(tally.GetRemovedVoxels());
  writer.PutVector(histogram);
}
} // namespace

std::vector<uint8_t>
BlockSummary::Serialize() const
{
  Writer writer;
  writer.Put(SummaryMagic);
  for (const auto * index : { &m_ImageSize, &m_Begin, &m_End })
  {
    for (const uint64_t value : *index)
    {
      writer.Put(value);
    }
  }
  writer.Put(m_Rules.MaximumComponentSize);
  writer.Put(static_cast<uint8_t>(m_Rules.Side));
  writer.Put(static_cast<uint8_t>(m_Rules.FullyConnected));
  writer.Put(static_cast<uint8_t>(m_Rules.AnyAbove));
  writer.Put(static_cast<uint8_t>(m_Rules.AnyBelow));
  writer.PutVector(m_Size);
  writer.PutVector(m_Above);
  writer.PutVector(m_Flipped);
  for (const auto & layer : m_Face)
  {
    writer.PutVector(layer.RowBegin);
    writer.PutVector(layer.Runs);
  }
  writer.PutVector(m_Touching);
  for (const SideTally * tally : { &m_Tally.Above, &m_Tally.Below })
  {
    const auto                                 map = tally->GetHistogram();
    std::vector<std::pair<uint64_t, uint64_t>> histogram(map.begin(), map.end());
    PutTally(writer, *tally, histogram);
  }
  writer.Put(m_Tally.ModifiedVoxels);
  writer.Put(m_Tally.UnrepairableVoxels);
  return std::move(writer.Data());
}

BlockSummary
BlockSummary::Deserialize(const uint8_t * data, SizeValueType bytes)
{
  Reader reader(data, bytes);
  if (reader.Get<uint32_t>() != SummaryMagic)
  {
    itkGenericExceptionMacro("BlockSummary::Deserialize: the data is not a block summary");
  }
  BlockSummary summary;
  for (auto * index : { &summary.m_ImageSize, &summary.m_Begin, &summary.m_End })
  {
    for (uint64_t & value : *index)
    {
      value = reader.Get<uint64_t>();
    }
  }
  summary.m_Rules.MaximumComponentSize = reader.Get<uint64_t>();
  summary.m_Rules.Side = static_cast<SmallIsoComponentEnums::Side>(reader.Get<uint8_t>());
  summary.m_Rules.FullyConnected = reader.Get<uint8_t>() != 0;
  summary.m_Rules.AnyAbove = reader.Get<uint8_t>() != 0;
  summary.m_Rules.AnyBelow = reader.Get<uint8_t>() != 0;
  summary.m_Size = reader.GetVector<uint64_t>();
  summary.m_Above = reader.GetVector<uint8_t>();
  summary.m_Flipped = reader.GetVector<uint64_t>();
  for (auto & layer : summary.m_Face)
  {
    layer.RowBegin = reader.GetVector<SizeValueType>();
    layer.Runs = reader.GetVector<FaceRun>();
  }
  summary.m_Touching = reader.GetVector<std::pair<NodeType, NodeType>>();
  for (SideTally * tally : { &summary.m_Tally.Above, &summary.m_Tally.Below })
  {
    tally->m_Components = reader.Get<uint64_t>();
    tally->m_RemovedComponents = reader.Get<uint64_t>();
    tally->m_RemovedVoxels = reader.Get<uint64_t>();
    for (const auto & entry : reader.GetVector<std::pair<uint64_t, uint64_t>>())
    {
      tally->m_Large[entry.first] += entry.second;
    }
  }
  summary.m_Tally.ModifiedVoxels = reader.Get<uint64_t>();
  summary.m_Tally.UnrepairableVoxels = reader.Get<uint64_t>();
  const SizeValueType nodes = summary.m_Size.size();
  bool                valid = reader.AtEnd() && summary.m_Above.size() == nodes && summary.m_Flipped.size() == nodes;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    for (const bool upper : { false, true })
    {
      const auto & layer = summary.m_Face[FaceIndex(axis, upper)];
      if (summary.HasFace(axis, upper))
      {
        valid = valid && summary.IsValidFaceLayer(axis, layer, nodes);
      }
      else
      {
        valid = valid && layer.RowBegin.empty() && layer.Runs.empty();
      }
    }
  }
  for (const auto & pair : summary.m_Touching)
  {
    valid = valid && pair.first < nodes && pair.second < nodes;
  }
  if (!valid)
  {
    itkGenericExceptionMacro("BlockSummary::Deserialize: the data is inconsistent (not a block summary)");
  }
  return summary;
}

SizeValueType
BlockSummary::GetMemoryInBytes() const
{
  SizeValueType bytes = m_Size.capacity() * sizeof(uint64_t) + m_Above.capacity() +
                        m_Flipped.capacity() * sizeof(uint64_t) +
                        m_Touching.capacity() * sizeof(std::pair<NodeType, NodeType>);
  for (const auto & layer : m_Face)
  {
    bytes += layer.RowBegin.capacity() * sizeof(SizeValueType) + layer.Runs.capacity() * sizeof(FaceRun);
  }
  return bytes;
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
