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
#ifndef sicLabelSurfaces_h
#define sicLabelSurfaces_h

// The surfaces of a label map's labels (tools built with VTK only): every label but the background gets a closed
// surface from the discrete Flying Edges, written with a cell-data array of each triangle's label and drawn in the
// four panels of --render in its label's colour.

#include "sicFilterReport.h"
#include "sicHeadlessDisplay.h"
#include "sicProgressReporter.h"
#include "sicRender.h"
#include "sicSurface.h"
#include "sicToolError.h"

#include "vtkAOSDataArrayTemplate.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

namespace sic
{
/** The labels of \a image but \a background, ascending; label i is numbered i + 1 on the surfaces. */
template <typename TImage>
std::vector<typename TImage::PixelType>
SurfaceLabels(const TImage & image, typename TImage::PixelType background)
{
  using LabelType = typename TImage::PixelType;
  std::set<LabelType> labels;
  const LabelType *   values = image.GetBufferPointer();
  const std::size_t   count = image.GetBufferedRegion().GetNumberOfPixels();
  // Segmentations hold long runs of one label: only a change of label needs a look-up.
  for (std::size_t voxel = 0; voxel < count; ++voxel)
  {
    if (values[voxel] != background && (voxel == 0 || values[voxel] != values[voxel - 1]))
    {
      labels.insert(values[voxel]);
    }
  }
  return { labels.begin(), labels.end() };
}

/** The surfaces of \a labels in \a image, in index coordinates (ExtractLabelSurfaces()); other voxels have none. */
template <typename TImage>
vtkSmartPointer<vtkPolyData>
LabelSurfacesOf(const TImage & image, const std::vector<typename TImage::PixelType> & labels)
{
  if (labels.size() >= std::numeric_limits<std::uint32_t>::max())
  {
    throw ToolError("the label map has too many labels for surfaces; expected fewer than 2^32 labels");
  }
  const auto *               values = image.GetBufferPointer();
  std::vector<std::uint32_t> numbers(image.GetBufferedRegion().GetNumberOfPixels(), 0);
  for (std::size_t voxel = 0; voxel < numbers.size(); ++voxel)
  {
    if (voxel > 0 && values[voxel] == values[voxel - 1])
    {
      numbers[voxel] = numbers[voxel - 1];
      continue;
    }
    const auto found = std::lower_bound(labels.begin(), labels.end(), values[voxel]);
    numbers[voxel] = found != labels.end() && *found == values[voxel] ? std::uint32_t(found - labels.begin()) + 1 : 0;
  }
  SurfaceGrid grid = SurfaceGridOf(image);
  grid.Buffer = numbers.data();
  grid.ScalarType = VTK_UNSIGNED_INT;
  return ExtractLabelSurfaces(grid, static_cast<std::uint32_t>(labels.size()));
}

/** The fixed palette of the labels: label L takes entry L mod 12, so a label keeps its colour in every picture. */
constexpr std::array<std::array<unsigned char, 3>, 12> LabelPalette{ { { { 78, 121, 167 } },
                                                                       { { 242, 142, 43 } },
                                                                       { { 225, 87, 89 } },
                                                                       { { 118, 183, 178 } },
                                                                       { { 89, 161, 79 } },
                                                                       { { 237, 201, 72 } },
                                                                       { { 176, 122, 161 } },
                                                                       { { 255, 157, 167 } },
                                                                       { { 156, 117, 95 } },
                                                                       { { 186, 176, 172 } },
                                                                       { { 141, 211, 199 } },
                                                                       { { 190, 186, 218 } } } };

template <typename TLabel>
std::array<unsigned char, 3>
LabelColour(TLabel label)
{
  const auto size = static_cast<long long>(LabelPalette.size());
  if constexpr (std::is_floating_point_v<TLabel>)
  {
    const double entry = std::fmod(static_cast<double>(label), static_cast<double>(size));
    return LabelPalette[static_cast<std::size_t>(entry < 0 ? entry + static_cast<double>(size) : entry)];
  }
  else if constexpr (std::is_signed_v<TLabel>)
  {
    return LabelPalette[static_cast<std::size_t>((static_cast<long long>(label) % size + size) % size)];
  }
  else
  {
    return LabelPalette[static_cast<std::size_t>(static_cast<unsigned long long>(label) % LabelPalette.size())];
  }
}

/** Renders the four panels of --render for label surfaces coloured by ColourLabels(), in physical coordinates. */
inline void
RenderLabelPanels(const FilterSettings & settings,
                  const StagedPaths &    staged,
                  vtkPolyData &          before,
                  vtkPolyData &          after,
                  vtkPolyData &          removed,
                  const FilterReport &   report)
{
  const auto pieces = [](std::uint64_t count) { return std::to_string(count) + (count == 1 ? " piece" : " pieces"); };
  // The removed pieces keep their labels' colours: the panel of bubbles stays empty.
  auto        none = vtkSmartPointer<vtkPolyData>::New();
  RenderScene scene;
  scene.Before = &before;
  scene.After = &after;
  scene.RemovedSpecks = &removed;
  scene.RemovedBubbles = none;
  scene.Labels = { "Original: " + pieces(*report.SurfacePiecesBefore),
                   "Filtered: " + pieces(*report.SurfacePiecesAfter),
                   "Removed: " + pieces(*report.RemovedSurfacePieces) + " (in their old labels' colours)",
                   "Filtered + removed: " + std::to_string(*report.SurfacePiecesAfter) + " + " +
                     pieces(*report.RemovedSurfacePieces) };
  const HeadlessDisplay display;
  RenderPanels(scene, staged.Render, settings.Render);
}

/** The pieces of each label's surface before and after filtering, and those removed (indexed by label number; empty
 * when that surface was not extracted). */
struct LabelSurfacePieces
{
  std::vector<std::uint64_t> Before;
  std::vector<std::uint64_t> After;
  std::vector<std::uint64_t> Removed;
};

/** The pieces of a surface, from its pieces per label: the labels share no points, so every piece has one label. */
inline std::uint64_t
TotalPieces(const std::vector<std::uint64_t> & perLabel)
{
  return std::accumulate(perLabel.begin(), perLabel.end(), std::uint64_t{ 0 });
}

/** Extracts the output's label surfaces, counts the pieces, and writes the surfaces and the picture the settings ask
 * for; \a before is the input's surfaces (null when none is asked for). The filter must have made its removed mask
 * when \a before is given. */
template <typename TFilter>
LabelSurfacePieces
WriteLabelSurfaces(const FilterSettings &                           settings,
                   const StagedPaths &                              staged,
                   vtkSmartPointer<vtkPolyData>                     before,
                   const std::vector<typename TFilter::LabelType> & labels,
                   TFilter &                                        filter,
                   ProgressReporter &                               progress,
                   FilterReport &                                   report)
{
  const auto                   count = static_cast<std::uint32_t>(labels.size());
  LabelSurfacePieces           pieces;
  vtkSmartPointer<vtkPolyData> after;
  if (!settings.Surface.empty() || !settings.Render.empty())
  {
    progress.Stage("extracting the filtered label surfaces", 0.85, 0.87);
    after = LabelSurfacesOf(*filter.GetOutput(), labels);
    pieces.After = CountSurfacePiecesPerLabel(*after, count);
    report.SurfacePiecesAfter = TotalPieces(pieces.After);
  }
  std::vector<std::array<unsigned char, 3>> colours(1, std::array<unsigned char, 3>{ { 0, 0, 0 } });
  for (const auto label : labels)
  {
    colours.push_back(LabelColour(label));
  }
  // Coloured before the removed triangles are cut out, which so keep their old label's colour.
  for (vtkPolyData * surface : { before.Get(), after.Get() })
  {
    if (surface != nullptr)
    {
      ColourLabels(*surface, colours);
    }
  }
  RemovedTriangles removed;
  if (before)
  {
    pieces.Before = CountSurfacePiecesPerLabel(*before, count);
    report.SurfacePiecesBefore = TotalPieces(pieces.Before);
    const auto & size = filter.GetOutput()->GetBufferedRegion().GetSize();
    removed = TrianglesOfChangedCells(
      *before, filter.GetRemovedMask()->GetBufferPointer(), { { size[0], size[1], size[2] } }, true);
    pieces.Removed = CountSurfacePiecesPerLabel(*removed.All, count);
    report.RemovedSurfacePieces = TotalPieces(pieces.Removed);
  }
  const SurfaceGeometry geometry = SurfaceGeometryOf(*filter.GetOutput());
  auto                  ids = vtkSmartPointer<vtkAOSDataArrayTemplate<typename TFilter::LabelType>>::New();
  for (const auto label : labels)
  {
    ids->InsertNextValue(label);
  }
  for (vtkPolyData * surface : { before.Get(), after.Get(), removed.All.Get() })
  {
    if (surface != nullptr)
    {
      TransformToPhysical(*surface, geometry);
      NameLabels(*surface, *ids);
    }
  }
  if (!settings.SurfaceBefore.empty())
  {
    progress.Stage("writing " + settings.SurfaceBefore, 0.87, 0.88);
    WriteSurface(*before, staged.SurfaceBefore, settings.SurfaceBefore, "input's label surfaces");
  }
  if (!settings.Surface.empty())
  {
    progress.Stage("writing " + settings.Surface, 0.88, 0.89);
    WriteSurface(*after, staged.Surface, settings.Surface, "label surfaces");
  }
  if (!settings.Render.empty())
  {
    progress.Stage("rendering " + settings.Render, 0.89, 0.9);
    RenderLabelPanels(settings, staged, *before, *after, *removed.All, report);
  }
  return pieces;
}
} // namespace sic

#endif
