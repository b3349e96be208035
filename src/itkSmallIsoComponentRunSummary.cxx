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
#include "itkSmallIsoComponentRunSummary.h"

namespace itk
{
namespace SmallIsoComponentDetail
{
uint64_t
BoxHalo(uint64_t maximumComponentSize, SmallIsoComponentEnums::Side side)
{
  return side == SmallIsoComponentEnums::Side::Both ? 2 * maximumComponentSize : maximumComponentSize;
}

namespace
{
using NodeType = BlockSummary::NodeType;

/** The faces of the block inside the image: the components of the voxels along them. */
void
AddFaceLayers(BlockSummary & summary, const RunLabeling & labeling, const BlockSummary::IndexType & extent)
{
  const SizeValueType         ny = extent[1];
  const SizeValueType         nz = extent[2];
  const RunLabeling::RunTable table = labeling.GetRunTable();
  const auto componentOf = [&](SizeValueType run) { return static_cast<NodeType>(table.Component[run]); };
  // Appends line \a line as a row of runs (the runs of a line are its runs in the table).
  const auto addLine = [&](BlockSummary::FaceLayer & layer, SizeValueType line) {
    layer.BeginRow();
    for (SizeValueType run = table.LineBegin[line]; run < table.LineBegin[line + 1]; ++run)
    {
      layer.AddVoxels(table.Start[run], componentOf(run));
    }
  };
  for (const bool upper : { false, true })
  {
    if (summary.HasFace(0, upper))
    {
      // Rows along y, one voxel of each line.
      BlockSummary::FaceLayer layer;
      layer.RowBegin.reserve(nz + 1);
      for (SizeValueType z = 0; z < nz; ++z)
      {
        layer.BeginRow();
        for (SizeValueType y = 0; y < ny; ++y)
        {
          const SizeValueType line = y + ny * z;
          layer.AddVoxels(y, componentOf(upper ? table.LineBegin[line + 1] - 1 : table.LineBegin[line]));
        }
      }
      layer.EndLayer();
      summary.SetFaceLayer(0, upper, std::move(layer));
    }
    if (summary.HasFace(1, upper))
    {
      BlockSummary::FaceLayer layer;
      layer.RowBegin.reserve(nz + 1);
      const SizeValueType y = upper ? ny - 1 : 0;
      for (SizeValueType z = 0; z < nz; ++z)
      {
        addLine(layer, y + ny * z);
      }
      layer.EndLayer();
      summary.SetFaceLayer(1, upper, std::move(layer));
    }
    if (summary.HasFace(2, upper))
    {
      BlockSummary::FaceLayer layer;
      layer.RowBegin.reserve(ny + 1);
      const SizeValueType z = upper ? nz - 1 : 0;
      for (SizeValueType y = 0; y < ny; ++y)
      {
        addLine(layer, y + ny * z);
      }
      layer.EndLayer();
      summary.SetFaceLayer(2, upper, std::move(layer));
    }
  }
}

/** For Side Both: the below components that each possibly small above component touches. All
 * the runs of a component of at most K voxels are candidates. */
void
AddTouchingOfSmallAbove(BlockSummary & summary, const RunLabeling & labeling)
{
  const SizeValueType  components = labeling.GetComponents().GetNumberOfComponents();
  std::vector<uint8_t> possiblySmall(components, 0);
  bool                 any = false;
  for (SizeValueType c = 0; c < components; ++c)
  {
    const auto component = static_cast<RunLabeling::ComponentIndexType>(c);
    possiblySmall[c] = labeling.GetComponents().IsComponentAbove(component) &&
                       summary.NeedsTouching(labeling.GetComponents().GetComponentSize(component));
    any = any || possiblySmall[c];
  }
  if (!any)
  {
    return;
  }
  const RunLabeling::RunTable table = labeling.GetRunTable();
  for (const auto & candidate : labeling.GetComponents().CollectCandidateRuns(possiblySmall))
  {
    const auto above = static_cast<NodeType>(table.Component[candidate.Run]);
    NodeType   last = BlockSummary::NoNode;
    ForEachTouchingRunOfOtherSide(labeling, candidate.Run, candidate.Line, [&](SizeValueType other) {
      const auto below = static_cast<NodeType>(table.Component[other]);
      if (below != last)
      {
        summary.AddTouching(above, below);
        last = below;
      }
    });
  }
}
} // namespace

BlockSummary
SummarizeLabeling(const RunLabeling &             labeling,
                  const BlockSummary::IndexType & extent,
                  const BlockSummary::IndexType & imageSize,
                  const BlockSummary::IndexType & begin,
                  const ComponentRules &          rules)
{
  const BlockSummary::IndexType end{ begin[0] + extent[0], begin[1] + extent[1], begin[2] + extent[2] };
  BlockSummary                  summary(imageSize, begin, end, rules);
  const SizeValueType           components = labeling.GetComponents().GetNumberOfComponents();
  for (SizeValueType c = 0; c < components; ++c)
  {
    const auto component = static_cast<RunLabeling::ComponentIndexType>(c);
    summary.AddComponent(labeling.GetComponents().IsComponentAbove(component),
                         labeling.GetComponents().GetComponentSize(component));
  }
  AddFaceLayers(summary, labeling, extent);
  AddTouchingOfSmallAbove(summary, labeling);
  return summary;
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
