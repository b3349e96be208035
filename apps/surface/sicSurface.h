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
#ifndef sicSurface_h
#define sicSurface_h

// Isosurfaces of the tools' images with VTK (built only when VTK is found): extraction with
// vtkFlyingEdges3D in index space, the mapping to ITK's physical (LPS) space, piece counts
// and surface files. The module itself never depends on VTK.

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

class vtkDataArray;
class vtkPolyData;

namespace sic
{
/** A 3-D scalar image seen by VTK: its buffer (x fastest), VTK scalar type and extent. */
struct SurfaceGrid
{
  const void *               Buffer{ nullptr };
  int                        ScalarType{ VTK_VOID };
  std::array<std::size_t, 3> Size{ { 0, 0, 0 } };
};

/** ITK's index-to-physical mapping of an image: p = Origin + Direction · diag(Spacing) · index. */
struct SurfaceGeometry
{
  std::array<double, 3> Origin{ { 0, 0, 0 } };
  std::array<double, 3> Spacing{ { 1, 1, 1 } };
  /** Row-major 3 × 3. */
  std::array<double, 9> Direction{ { 1, 0, 0, 0, 1, 0, 0, 0, 1 } };
};

template <typename TPixel>
constexpr int
VtkScalarTypeOf()
{
  if constexpr (std::is_same_v<TPixel, std::uint8_t>)
    return VTK_UNSIGNED_CHAR;
  else if constexpr (std::is_same_v<TPixel, std::int8_t>)
    return VTK_SIGNED_CHAR;
  else if constexpr (std::is_same_v<TPixel, std::uint16_t>)
    return VTK_UNSIGNED_SHORT;
  else if constexpr (std::is_same_v<TPixel, std::int16_t>)
    return VTK_SHORT;
  else if constexpr (std::is_same_v<TPixel, std::uint32_t>)
    return VTK_UNSIGNED_INT;
  else if constexpr (std::is_same_v<TPixel, std::int32_t>)
    return VTK_INT;
  else if constexpr (std::is_same_v<TPixel, std::int64_t>)
    return VTK_TYPE_INT64;
  else if constexpr (std::is_same_v<TPixel, std::uint64_t>)
    return VTK_TYPE_UINT64;
  else if constexpr (std::is_same_v<TPixel, float>)
    return VTK_FLOAT;
  else if constexpr (std::is_same_v<TPixel, double>)
    return VTK_DOUBLE;
  else
    static_assert(!sizeof(TPixel), "no VTK scalar type for this pixel type");
}

/** The grid of a 3-D itk::Image (its buffered region; the buffer must outlive the use). */
template <typename TImage>
SurfaceGrid
SurfaceGridOf(const TImage & image)
{
  static_assert(TImage::ImageDimension == 3, "isosurfaces are extracted from 3-D images");
  SurfaceGrid grid;
  grid.Buffer = image.GetBufferPointer();
  grid.ScalarType = VtkScalarTypeOf<typename TImage::PixelType>();
  const auto & size = image.GetBufferedRegion().GetSize();
  grid.Size = { { size[0], size[1], size[2] } };
  return grid;
}

/** The index-to-physical mapping of a 3-D itk::Image, with its buffered region's start folded
 * into the origin so that buffer index (0, 0, 0) maps to the first voxel. */
template <typename TImage>
SurfaceGeometry
SurfaceGeometryOf(const TImage & image)
{
  SurfaceGeometry            geometry;
  typename TImage::PointType first;
  image.TransformIndexToPhysicalPoint(image.GetBufferedRegion().GetIndex(), first);
  for (unsigned int row = 0; row < 3; ++row)
  {
    geometry.Origin[row] = first[row];
    geometry.Spacing[row] = image.GetSpacing()[row];
    for (unsigned int column = 0; column < 3; ++column)
    {
      geometry.Direction[3 * row + column] = image.GetDirection()[row][column];
    }
  }
  return geometry;
}

/** The isosurface of \a grid at \a isoValue by vtkFlyingEdges3D, in index coordinates
 * (voxel (i, j, k) at point (i, j, k)), triangles only, without normals. Each point lies on
 * one grid edge and is shared by every triangle that uses that edge. A grid with an extent
 * below 2 has no cells and gives an empty surface. */
vtkSmartPointer<vtkPolyData>
ExtractIsosurface(const SurfaceGrid & grid, double isoValue);

/** The name of the cell-data array that gives each triangle of a label surface its label. */
constexpr const char * LabelArrayName = "label";
/** The cell-data array of ColourLabels(): each triangle's RGB colour (vtkUnsignedCharArray). */
constexpr const char * SurfaceColourArrayName = "colour";

/** The surfaces of the labels of \a ordinals, a VTK_UNSIGNED_INT grid numbering the labels 1 to \a labels (0 for
 * voxels without a surface, the background), by vtkDiscreteFlyingEdges3D: one closed surface per label between its
 * voxels and all others, in index coordinates. Each label has its own points, so pieces never join two labels. The
 * cell data array LabelArrayName (vtkUnsignedIntArray) holds each triangle's label number. */
vtkSmartPointer<vtkPolyData>
ExtractLabelSurfaces(const SurfaceGrid & ordinals, std::uint32_t labels);

/** The connected pieces of each label of a surface from ExtractLabelSurfaces(), indexed by label number (0 unused). */
std::vector<std::uint64_t>
CountSurfacePiecesPerLabel(vtkPolyData & surface, std::uint32_t labels);

/** Gives the triangles of a surface from ExtractLabelSurfaces() the RGB colour of their label number (index 0
 * unused) as cell scalars, which RenderPanels() then shows. */
void
ColourLabels(vtkPolyData & surface, const std::vector<std::array<unsigned char, 3>> & colours);

/** Replaces the label numbers of a surface from ExtractLabelSurfaces() by the label ids \a ids (entry n - 1 for
 * number n), an array of the label map's own type so that every id is exact. */
void
NameLabels(vtkPolyData & surface, vtkDataArray & ids);

/** Moves the points of \a surface from index to physical coordinates. Where the mapping
 * mirrors space (a negative determinant, e.g. a flipped axis), every triangle's vertex order
 * is reversed so that its orientation (and normal) keeps pointing the same way relative to
 * the surface. */
void
TransformToPhysical(vtkPolyData & surface, const SurfaceGeometry & geometry);

/** The connected pieces of \a surface: triangles that share a point belong to one piece. */
std::uint64_t
CountSurfacePieces(vtkPolyData & surface);

/** The triangles of an isosurface (in index coordinates) that lie in grid cells with a corner
 * the filter changed. Each triangle lies in one cell (its points are on that cell's edges);
 * it counts as a speck's when a corner of the cell has mask value 1 (removed with an above
 * component), otherwise as a bubble's (value 2). Triangles of unchanged cells are bit for bit
 * the same before and after filtering, so these are exactly the triangles filtering changed.
 * With \a wholePiecesOnly, only the pieces of \a surface all of whose triangles changed are
 * kept: the pieces filtering took away, not the places where a surviving piece changed
 * shape. The three surfaces share \a surface's points, and take its cell data (a label surface's labels and
 * colours). */
struct RemovedTriangles
{
  vtkSmartPointer<vtkPolyData> Specks;
  vtkSmartPointer<vtkPolyData> Bubbles;
  vtkSmartPointer<vtkPolyData> All;
};

RemovedTriangles
TrianglesOfChangedCells(vtkPolyData &                      surface,
                        const std::uint8_t *               mask,
                        const std::array<std::size_t, 3> & size,
                        bool                               wholePiecesOnly = false);

/** The surface file formats by extension (.vtp, .stl, .ply, .obj), as a list for messages. */
std::string
SupportedSurfaceExtensions();

/** Throws sic::ToolError unless \a path ends in a supported surface extension. */
void
CheckSurfaceFileFormat(const std::string & path, const std::string & what);

/** Writes \a surface to \a stagedPath in the format \a finalPath's extension names (the
 * staged path may lack it), then reads the file back: it must hold every triangle (and, in a .vtp file, every
 * cell-data array with all its values), as the
 * PLY and OBJ writers do not notice a failed write. Throws sic::ToolError, naming
 * \a finalPath, on failure, in one line (VTK's own messages are not shown). */
void
WriteSurface(vtkPolyData &       surface,
             const std::string & stagedPath,
             const std::string & finalPath,
             const std::string & what);
} // namespace sic

#endif
