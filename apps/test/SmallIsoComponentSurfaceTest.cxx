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
// Mesh tests of the tools' isosurfaces (built with VTK only): piece counts against VTK's own
// connectivity filter and against the voxel components, point coordinates against the grid
// and against ITK's index-to-physical mapping, the surface files, and what filtering does to
// the surface. Run one case per CTest test: SmallIsoComponentSurfaceTest CASE.

#include "itkSmallIsoComponentImageFilter.h"
#include "itkSmallIsoComponentReference.h"
#include "sicPlatform.h"
#include "sicSplitMix64.h"
#include "sicSurface.h"

#include "itkImage.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkOBJReader.h"
#include "vtkPLYReader.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataConnectivityFilter.h"
#include "vtkSTLReader.h"
#include "vtkXMLPolyDataReader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <vector>

namespace
{
int failures = 0;

#define CHECK(condition, message)                                                                          \
  do                                                                                                       \
  {                                                                                                        \
    if (!(condition))                                                                                      \
    {                                                                                                      \
      ++failures;                                                                                          \
      if (failures <= 20)                                                                                  \
      {                                                                                                    \
        std::cerr << __FILE__ << ':' << __LINE__ << ": CHECK(" #condition ") failed: " << message << '\n'; \
      }                                                                                                    \
    }                                                                                                      \
  } while (false)

using ImageType = itk::Image<short, 3>;

/** Uniform in [0, n). */
std::size_t
Below(sic::SplitMix64 & random, std::size_t n)
{
  return static_cast<std::size_t>(random.Next() % n);
}
using FloatImageType = itk::Image<float, 3>;

template <typename TImage = ImageType>
typename TImage::Pointer
MakeImage(std::size_t nx, std::size_t ny, std::size_t nz, typename TImage::PixelType value = 0)
{
  auto                        image = TImage::New();
  typename TImage::RegionType region;
  region.SetSize({ { nx, ny, nz } });
  image->SetRegions(region);
  image->Allocate();
  image->FillBuffer(value);
  return image;
}

/** A random volume: white noise, or blocks of a random value (bigger structures). */
ImageType::Pointer
RandomVolume(sic::SplitMix64 & random, std::size_t maxExtent)
{
  const auto                                  extent = [&] { return 2 + Below(random, maxExtent - 1); };
  const std::size_t                           nx = extent(), ny = extent(), nz = extent();
  auto                                        image = MakeImage(nx, ny, nz);
  const std::size_t                           block = 1 + Below(random, 3);
  const std::size_t                           fill = 20 + Below(random, 60);
  std::map<std::array<std::size_t, 3>, short> blocks;
  short *                                     buffer = image->GetBufferPointer();
  for (std::size_t z = 0; z < nz; ++z)
    for (std::size_t y = 0; y < ny; ++y)
      for (std::size_t x = 0; x < nx; ++x)
      {
        const std::array<std::size_t, 3> key{ { x / block, y / block, z / block } };
        auto                             found = blocks.find(key);
        if (found == blocks.end())
        {
          found = blocks.emplace(key, static_cast<short>(Below(random, 100) < fill ? 100 : 0)).first;
        }
        // Noise within each block so the crossings are not all at the same place.
        buffer[x + nx * (y + ny * z)] = static_cast<short>(found->second + Below(random, 10));
      }
  return image;
}

std::uint64_t
VtkPieces(vtkPolyData * surface)
{
  auto connectivity = vtkSmartPointer<vtkPolyDataConnectivityFilter>::New();
  connectivity->SetInputData(surface);
  connectivity->SetExtractionModeToAllRegions();
  connectivity->Update();
  return static_cast<std::uint64_t>(connectivity->GetNumberOfExtractedRegions());
}

std::uint64_t
TriangleCount(vtkPolyData * surface)
{
  return surface->GetPolys() == nullptr ? 0 : static_cast<std::uint64_t>(surface->GetPolys()->GetNumberOfCells());
}

/** Every triangle as its three points' coordinates, sorted: a multiset to compare surfaces. */
std::vector<std::array<float, 9>>
Triangles(vtkPolyData * surface)
{
  std::vector<std::array<float, 9>> triangles;
  if (surface->GetPolys() == nullptr)
  {
    return triangles;
  }
  auto cells = vtk::TakeSmartPointer(surface->GetPolys()->NewIterator());
  for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
  {
    vtkIdType         count = 0;
    const vtkIdType * ids = nullptr;
    cells->GetCurrentCell(count, ids);
    std::array<float, 9> triangle{};
    for (vtkIdType corner = 0; corner < std::min<vtkIdType>(count, 3); ++corner)
    {
      double point[3];
      surface->GetPoints()->GetPoint(ids[corner], point);
      for (int axis = 0; axis < 3; ++axis)
      {
        triangle[static_cast<std::size_t>(3 * corner + axis)] = static_cast<float>(point[axis]);
      }
    }
    triangles.push_back(triangle);
  }
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

/** The pieces of a triangle list, with points identified by their coordinates. */
std::uint64_t
PiecesOfTriangles(const std::vector<std::array<float, 9>> & triangles)
{
  std::map<std::array<float, 3>, std::size_t>   pointIds;
  std::vector<std::size_t>                      parent;
  const std::function<std::size_t(std::size_t)> find = [&](std::size_t p) {
    while (parent[p] != p)
      p = parent[p] = parent[parent[p]];
    return p;
  };
  for (const auto & triangle : triangles)
  {
    std::size_t ids[3];
    for (int corner = 0; corner < 3; ++corner)
    {
      const std::array<float, 3> point{ { triangle[3 * corner], triangle[3 * corner + 1], triangle[3 * corner + 2] } };
      const auto                 inserted = pointIds.emplace(point, parent.size());
      if (inserted.second)
        parent.push_back(parent.size());
      ids[corner] = inserted.first->second;
    }
    parent[find(ids[1])] = find(ids[0]);
    parent[find(ids[2])] = find(ids[0]);
  }
  std::uint64_t pieces = 0;
  for (std::size_t p = 0; p < parent.size(); ++p)
    pieces += find(p) == p;
  return pieces;
}

template <typename TImage>
vtkSmartPointer<vtkPolyData>
Surface(const TImage & image, double isoValue)
{
  return sic::ExtractIsosurface(sic::SurfaceGridOf(image), isoValue);
}

// --- the cases ---------------------------------------------------------------------------

/** Our piece count (triangles sharing a point) equals vtkPolyDataConnectivityFilter's. */
void
PiecesMatchVtkConnectivity()
{
  sic::SplitMix64 random(11);
  for (int volume = 0; volume < 150; ++volume)
  {
    const auto          image = RandomVolume(random, 14);
    const double        isoValue = 49.5 + static_cast<double>(Below(random, 3)) * 10.0;
    const auto          surface = Surface(*image, isoValue);
    const std::uint64_t ours = sic::CountSurfacePieces(*surface);
    CHECK(ours == VtkPieces(surface), "volume " << volume << ": " << ours << " vs " << VtkPieces(surface));
  }
  // Hand-made: one voxel is one closed piece; two voxels apart are two.
  auto image = MakeImage(7, 7, 7);
  image->SetPixel({ { 2, 2, 2 } }, 100);
  CHECK(sic::CountSurfacePieces(*Surface(*image, 50.0)) == 1, "one voxel");
  CHECK(TriangleCount(Surface(*image, 50.0)) == 8, "a voxel's surface is an octahedron of 8 triangles");
  image->SetPixel({ { 4, 4, 4 } }, 100);
  CHECK(sic::CountSurfacePieces(*Surface(*image, 50.0)) == 2, "two voxels apart");
}

/** Every point lies on a grid edge between a voxel >= S and one < S, where the linear
 * interpolation of the two values crosses S; NaN samples count as below and give no NaN point. */
void
PointsLieOnCrossingEdges()
{
  sic::SplitMix64 random(12);
  for (int volume = 0; volume < 60; ++volume)
  {
    const bool withNaN = volume % 3 == 0;
    const auto source = RandomVolume(random, 12);
    const auto size = source->GetBufferedRegion().GetSize();
    auto       image = MakeImage<FloatImageType>(size[0], size[1], size[2]);
    for (std::size_t i = 0; i < source->GetBufferedRegion().GetNumberOfPixels(); ++i)
    {
      const bool nan = withNaN && Below(random, 10) == 0;
      image->GetBufferPointer()[i] =
        nan ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(source->GetBufferPointer()[i]);
    }
    const double isoValue = 50.5;
    const auto   surface = Surface(*image, isoValue);
    const auto   value = [&](const std::array<long, 3> & index) {
      return image->GetPixel({ { index[0], index[1], index[2] } });
    };
    for (vtkIdType id = 0; id < surface->GetNumberOfPoints(); ++id)
    {
      double point[3];
      surface->GetPoints()->GetPoint(id, point);
      int axis = -1;
      for (int a = 0; a < 3; ++a)
      {
        CHECK(std::isfinite(point[a]), "point " << id << " is not finite");
        if (point[a] != std::floor(point[a]))
        {
          CHECK(axis == -1, "point " << id << " is not on a grid edge");
          axis = a;
        }
      }
      if (axis == -1)
      {
        continue; // exactly on a voxel: only when a value is S or next to NaN, checked below
      }
      std::array<long, 3> low{ { static_cast<long>(std::floor(point[0])),
                                 static_cast<long>(std::floor(point[1])),
                                 static_cast<long>(std::floor(point[2])) } };
      std::array<long, 3> high = low;
      ++high[static_cast<std::size_t>(axis)];
      const float a = value(low);
      const float b = value(high);
      const bool  aAbove = a >= isoValue;
      const bool  bAbove = b >= isoValue;
      CHECK(aAbove != bAbove, "point " << id << " on an edge that does not cross S");
      if (!std::isnan(a) && !std::isnan(b))
      {
        const double t = (isoValue - a) / (static_cast<double>(b) - a);
        const double expected = static_cast<double>(low[static_cast<std::size_t>(axis)]) + t;
        CHECK(std::abs(point[axis] - expected) < 1e-5,
              "point " << id << " at " << point[axis] << ", expected " << expected);
      }
    }
    // Every crossing edge has its point: count crossing edges by brute force.
    std::uint64_t crossings = 0;
    for (long z = 0; z < static_cast<long>(size[2]); ++z)
      for (long y = 0; y < static_cast<long>(size[1]); ++y)
        for (long x = 0; x < static_cast<long>(size[0]); ++x)
          for (int a = 0; a < 3; ++a)
          {
            std::array<long, 3> next{ { x, y, z } };
            if (++next[static_cast<std::size_t>(a)] >= static_cast<long>(size[static_cast<std::size_t>(a)]))
              continue;
            crossings += (value({ { x, y, z } }) >= isoValue) != (value(next) >= isoValue);
          }
    if (!withNaN)
    {
      CHECK(static_cast<std::uint64_t>(surface->GetNumberOfPoints()) == crossings,
            "volume " << volume << ": " << surface->GetNumberOfPoints() << " points, " << crossings
                      << " crossing edges");
    }
  }
}

/** Physical coordinates are ITK's TransformContinuousIndexToPhysicalPoint of the index
 * coordinates, for any spacing, origin, direction and buffered-region start; a mirroring
 * direction reverses every triangle. */
void
PhysicalCoordinatesMatchITK()
{
  sic::SplitMix64 random(13);
  for (int volume = 0; volume < 12; ++volume)
  {
    auto image = RandomVolume(random, 10);
    // A start index other than 0 and a non-trivial geometry.
    ImageType::RegionType region = image->GetBufferedRegion();
    region.SetIndex({ { 3, -2, 7 } });
    image->SetRegions(region);
    const double spacing[3] = { 0.4 + 0.1 * volume, 1.3, 2.5 };
    image->SetSpacing(spacing);
    const double origin[3] = { -12.5, 4.25, 30.0 + volume };
    image->SetOrigin(origin);
    const double             angle = 0.3 * volume;
    ImageType::DirectionType direction;
    direction.SetIdentity();
    direction[0][0] = std::cos(angle);
    direction[0][1] = -std::sin(angle);
    direction[1][0] = std::sin(angle);
    direction[1][1] = std::cos(angle);
    const bool mirrored = volume % 2 == 1;
    if (mirrored)
    {
      direction[2][2] = -1.0; // as in an LPS image whose slices run from head to feet
    }
    image->SetDirection(direction);

    const auto indexSurface = Surface(*image, 49.5);
    auto       physical = vtkSmartPointer<vtkPolyData>::New();
    physical->DeepCopy(indexSurface);
    sic::TransformToPhysical(*physical, sic::SurfaceGeometryOf(*image));
    CHECK(physical->GetNumberOfPoints() == indexSurface->GetNumberOfPoints(), "point count changed");
    for (vtkIdType id = 0; id < indexSurface->GetNumberOfPoints(); ++id)
    {
      double index[3];
      indexSurface->GetPoints()->GetPoint(id, index);
      itk::ContinuousIndex<double, 3> continuous;
      for (int a = 0; a < 3; ++a)
      {
        continuous[a] = index[a] + static_cast<double>(region.GetIndex()[a]);
      }
      ImageType::PointType expected;
      image->TransformContinuousIndexToPhysicalPoint(continuous, expected);
      double point[3];
      physical->GetPoints()->GetPoint(id, point);
      for (int a = 0; a < 3; ++a)
      {
        CHECK(std::abs(point[a] - expected[a]) <= 1e-9 * (1.0 + std::abs(expected[a])),
              "volume " << volume << " point " << id << " axis " << a << ": " << point[a] << " vs " << expected[a]);
      }
    }
    // Triangles keep their points; with a mirroring direction their order is reversed.
    auto before = vtk::TakeSmartPointer(indexSurface->GetPolys()->NewIterator());
    auto after = vtk::TakeSmartPointer(physical->GetPolys()->NewIterator());
    for (before->GoToFirstCell(), after->GoToFirstCell(); !before->IsDoneWithTraversal();
         before->GoToNextCell(), after->GoToNextCell())
    {
      vtkIdType         n = 0, m = 0;
      const vtkIdType * a = nullptr;
      const vtkIdType * b = nullptr;
      before->GetCurrentCell(n, a);
      after->GetCurrentCell(m, b);
      std::vector<vtkIdType> expected(a, a + n);
      if (mirrored)
      {
        std::reverse(expected.begin(), expected.end());
      }
      CHECK(std::vector<vtkIdType>(b, b + m) == expected, "volume " << volume << ": triangle order");
    }
  }
}

/** Each surface format written by the tools reads back with VTK's reader as the same mesh. */
void
FilesReadBack()
{
  sic::SplitMix64 random(14);
  auto            image = RandomVolume(random, 12);
  image->SetSpacing(std::array<double, 3>{ { 0.5, 0.75, 1.25 } }.data());
  auto surface = Surface(*image, 49.5);
  sic::TransformToPhysical(*surface, sic::SurfaceGeometryOf(*image));
  const std::uint64_t pieces = sic::CountSurfacePieces(*surface);
  const auto          triangles = TriangleCount(surface);
  CHECK(triangles > 0, "the test volume has a surface");
  double bounds[6];
  surface->GetBounds(bounds);

  std::error_code             created;
  const std::filesystem::path directory =
    sic::CreateUniqueDirectory(std::filesystem::temp_directory_path(), "sic-surface-test-", created);
  CHECK(!directory.empty(), "a scratch directory: " << created.message());
  const auto check = [&](const std::string & extension, vtkPolyData * read, bool indexed) {
    CHECK(TriangleCount(read) == triangles,
          extension << ": " << TriangleCount(read) << " triangles, expected " << triangles);
    double readBounds[6];
    read->GetBounds(readBounds);
    for (int i = 0; i < 6; ++i)
    {
      CHECK(std::abs(readBounds[i] - bounds[i]) < 1e-4, extension << ": bounds differ");
    }
    if (indexed)
    {
      CHECK(sic::CountSurfacePieces(*read) == pieces, extension << ": pieces differ");
    }
  };
  for (const std::string extension : { ".vtp", ".stl", ".ply", ".obj" })
  {
    const std::string path = (directory / ("surface" + extension)).string();
    sic::WriteSurface(*surface, path, path, "surface");
    if (extension == ".vtp")
    {
      auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
      reader->SetFileName(path.c_str());
      reader->Update();
      check(extension, reader->GetOutput(), true);
    }
    else if (extension == ".stl")
    {
      // STL stores every triangle's corners on their own; the reader merges equal points.
      auto reader = vtkSmartPointer<vtkSTLReader>::New();
      reader->SetFileName(path.c_str());
      reader->Update();
      check(extension, reader->GetOutput(), true);
    }
    else if (extension == ".ply")
    {
      auto reader = vtkSmartPointer<vtkPLYReader>::New();
      reader->SetFileName(path.c_str());
      reader->Update();
      check(extension, reader->GetOutput(), true);
    }
    else
    {
      auto reader = vtkSmartPointer<vtkOBJReader>::New();
      reader->SetFileName(path.c_str());
      reader->Update();
      check(extension, reader->GetOutput(), true);
    }
  }
  bool refused = false;
  try
  {
    sic::CheckSurfaceFileFormat("surface.vtk", "surface");
  }
  catch (const std::exception &)
  {
    refused = true;
  }
  CHECK(refused, "an unsupported extension is refused");
  std::filesystem::remove_all(directory);
}

/** A volume of a large object with specks outside it and bubbles inside it, each at least two
 * voxels away from everything else: filtering with Both removes exactly their pieces. */
void
BothRemovesThePiecesOfRemovedComponents()
{
  sic::SplitMix64 random(15);
  for (int volume = 0; volume < 40; ++volume)
  {
    const std::size_t n = 24 + Below(random, 12);
    auto              image = MakeImage(n, n, n, 10);
    // The object: a box in the middle third, with noise that keeps it on its side.
    const std::size_t low = n / 3, high = 2 * n / 3;
    for (std::size_t z = low; z < high; ++z)
      for (std::size_t y = low; y < high; ++y)
        for (std::size_t x = low; x < high; ++x)
          image->SetPixel({ { static_cast<long>(x), static_cast<long>(y), static_cast<long>(z) } },
                          static_cast<short>(100 + Below(random, 20)));
    // Cells of the volume already taken (by anything plus a two-voxel margin).
    std::vector<bool> taken(n * n * n, false);
    const auto        at = [n](long x, long y, long z) { return static_cast<std::size_t>(x + n * (y + n * z)); };
    const auto        inside = [n](long c) { return c >= 0 && c < static_cast<long>(n); };
    const auto        mark = [&](long x0, long y0, long z0, long x1, long y1, long z1) {
      for (long z = z0 - 2; z <= z1 + 2; ++z)
        for (long y = y0 - 2; y <= y1 + 2; ++y)
          for (long x = x0 - 2; x <= x1 + 2; ++x)
            if (inside(x) && inside(y) && inside(z))
              taken[at(x, y, z)] = true;
    };
    // The object's surface layer is taken for both kinds: bubbles stay inside, specks outside.
    const long l = static_cast<long>(low), h = static_cast<long>(high) - 1;
    for (long z = 0; z < static_cast<long>(n); ++z)
      for (long y = 0; y < static_cast<long>(n); ++y)
        for (long x = 0; x < static_cast<long>(n); ++x)
        {
          const long outside = std::max({ l - x, x - h, l - y, y - h, l - z, z - h });
          if (outside >= -2 && outside <= 2)
            taken[at(x, y, z)] = true;
        }
    // Small clusters: random walks of 1 to 6 voxels, face-connected, away from the border.
    int specks = 0, bubbles = 0;
    for (int attempt = 0; attempt < 60; ++attempt)
    {
      std::vector<std::array<long, 3>> cluster{ { { 2 + static_cast<long>(Below(random, n - 4)),
                                                    2 + static_cast<long>(Below(random, n - 4)),
                                                    2 + static_cast<long>(Below(random, n - 4)) } } };
      const std::size_t                size = 1 + Below(random, 6);
      while (cluster.size() < size)
      {
        auto next = cluster[Below(random, cluster.size())];
        next[Below(random, 3)] += Below(random, 2) ? 1 : -1;
        if (std::find(cluster.begin(), cluster.end(), next) == cluster.end())
          cluster.push_back(next);
      }
      long lo[3] = { 1 << 20, 1 << 20, 1 << 20 }, hi[3] = { -1, -1, -1 };
      for (const auto & v : cluster)
        for (int a = 0; a < 3; ++a)
        {
          lo[a] = std::min(lo[a], v[static_cast<std::size_t>(a)]);
          hi[a] = std::max(hi[a], v[static_cast<std::size_t>(a)]);
        }
      bool free = lo[0] >= 2 && lo[1] >= 2 && lo[2] >= 2 && hi[0] < static_cast<long>(n) - 2 &&
                  hi[1] < static_cast<long>(n) - 2 && hi[2] < static_cast<long>(n) - 2;
      for (const auto & v : cluster)
        free = free && !taken[at(v[0], v[1], v[2])];
      if (!free)
        continue;
      const bool inObject = image->GetPixel({ { cluster[0][0], cluster[0][1], cluster[0][2] } }) >= 50;
      for (const auto & v : cluster)
        image->SetPixel({ { v[0], v[1], v[2] } },
                        static_cast<short>(inObject ? 0 + Below(random, 20) : 100 + Below(random, 20)));
      (inObject ? bubbles : specks) += 1;
      mark(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    }

    using FilterType = itk::SmallIsoComponentImageFilter<ImageType>;
    auto filter = FilterType::New();
    filter->SetInput(image);
    filter->SetIsoValue(50.5);
    filter->SetMaximumComponentSize(6);
    filter->SetSide(itk::SmallIsoComponentEnums::Side::Both);
    filter->GenerateRemovedMaskOn();
    filter->Update();
    const auto removedAbove = filter->GetNumberOfRemovedComponents(itk::SmallIsoComponentEnums::Side::Above);
    const auto removedBelow = filter->GetNumberOfRemovedComponents(itk::SmallIsoComponentEnums::Side::Below);
    CHECK(removedAbove == static_cast<std::uint64_t>(specks) && removedBelow == static_cast<std::uint64_t>(bubbles),
          "volume " << volume << ": removed " << removedAbove << " + " << removedBelow << ", placed " << specks << " + "
                    << bubbles);

    const auto before = Surface(*image, 50.5);
    const auto after = Surface(*filter->GetOutput(), 50.5);
    const auto piecesBefore = sic::CountSurfacePieces(*before);
    const auto piecesAfter = sic::CountSurfacePieces(*after);
    CHECK(piecesBefore == piecesAfter + removedAbove + removedBelow,
          "volume " << volume << ": " << piecesBefore << " pieces before, " << piecesAfter << " after, "
                    << removedAbove + removedBelow << " components removed");
    CHECK(piecesAfter == 1, "volume " << volume << ": the object is one piece, found " << piecesAfter);

    const auto removed =
      sic::TrianglesOfChangedCells(*before, filter->GetRemovedMask()->GetBufferPointer(), { { n, n, n } });
    CHECK(sic::CountSurfacePieces(*removed.Specks) == removedAbove, "volume " << volume << ": speck pieces");
    CHECK(sic::CountSurfacePieces(*removed.Bubbles) == removedBelow, "volume " << volume << ": bubble pieces");
    const auto whole =
      sic::TrianglesOfChangedCells(*before, filter->GetRemovedMask()->GetBufferPointer(), { { n, n, n } }, true);
    CHECK(Triangles(whole.All) == Triangles(removed.All), "volume " << volume << ": isolated pieces go whole");
    // The surface after is the surface before without the removed triangles, bit for bit.
    std::vector<std::array<float, 9>> kept = Triangles(before);
    const auto                        gone = Triangles(removed.All);
    std::vector<std::array<float, 9>> difference;
    std::set_difference(kept.begin(), kept.end(), gone.begin(), gone.end(), std::back_inserter(difference));
    CHECK(difference == Triangles(after), "volume " << volume << ": the remaining triangles changed");
  }
}

/** On any volume, filtering changes only the triangles of cells with a changed corner: all
 * other triangles are the same before and after, bit for bit. */
void
UnchangedCellsKeepTheirTriangles()
{
  sic::SplitMix64 random(16);
  for (int volume = 0; volume < 80; ++volume)
  {
    const auto image = RandomVolume(random, 16);
    const auto size = image->GetBufferedRegion().GetSize();
    using FilterType = itk::SmallIsoComponentImageFilter<ImageType>;
    auto filter = FilterType::New();
    filter->SetInput(image);
    filter->SetIsoValue(49.5);
    filter->SetMaximumComponentSize(1 + Below(random, 10));
    filter->SetFullyConnected(Below(random, 2) == 1);
    filter->SetSide(static_cast<itk::SmallIsoComponentEnums::Side>(Below(random, 3)));
    filter->GenerateRemovedMaskOn();
    filter->Update();
    const std::array<std::size_t, 3> extent{ { size[0], size[1], size[2] } };
    const auto                       before = Surface(*image, 49.5);
    const auto                       after = Surface(*filter->GetOutput(), 49.5);
    const std::uint8_t *             mask = filter->GetRemovedMask()->GetBufferPointer();
    const auto                       changedBefore = Triangles(sic::TrianglesOfChangedCells(*before, mask, extent).All);
    const auto                       changedAfter = Triangles(sic::TrianglesOfChangedCells(*after, mask, extent).All);
    std::vector<std::array<float, 9>> keptBefore;
    std::vector<std::array<float, 9>> keptAfter;
    const auto                        all = Triangles(before);
    const auto                        allAfter = Triangles(after);
    std::set_difference(
      all.begin(), all.end(), changedBefore.begin(), changedBefore.end(), std::back_inserter(keptBefore));
    std::set_difference(
      allAfter.begin(), allAfter.end(), changedAfter.begin(), changedAfter.end(), std::back_inserter(keptAfter));
    CHECK(keptBefore == keptAfter, "volume " << volume << ": triangles of unchanged cells differ");
    // The pieces taken away whole are among the changed triangles, and are whole pieces.
    const auto whole = sic::TrianglesOfChangedCells(*before, mask, extent, true);
    const auto wholeTriangles = Triangles(whole.All);
    CHECK(std::includes(changedBefore.begin(), changedBefore.end(), wholeTriangles.begin(), wholeTriangles.end()),
          "volume " << volume << ": a removed piece has an unchanged triangle");
    CHECK(sic::CountSurfacePieces(*before) ==
            sic::CountSurfacePieces(*whole.All) + (all.size() == wholeTriangles.size() ? 0 : [&] {
              // The pieces left: those of the triangles not taken away whole.
              std::vector<std::array<float, 9>> rest;
              std::set_difference(all.begin(), all.end(), wholeTriangles.begin(), wholeTriangles.end(),
                                  std::back_inserter(rest));
              return PiecesOfTriangles(rest);
            }()),
          "volume " << volume << ": removed pieces are not whole pieces");
    if (filter->GetNumberOfModifiedVoxels() == 0)
    {
      CHECK(all == allAfter, "volume " << volume << ": nothing removed but the surface changed");
    }
  }
}

/** How voxel components relate to Marching Cubes pieces (the README's explanation), checked
 * on random volumes: every piece separates one face-connected (6) component of the voxels
 * >= S from one fully connected (26) component of the voxels < S; each such touching pair
 * gives at least one piece, and more only where the pair meets in separate places. */
void
PiecesSeparateAboveFaceAndBelowFullComponents()
{
  sic::SplitMix64 random(17);
  std::uint64_t   pairs = 0;
  std::uint64_t   pieces = 0;
  for (int volume = 0; volume < 200; ++volume)
  {
    const auto   image = RandomVolume(random, 12);
    const auto   size = image->GetBufferedRegion().GetSize();
    const double isoValue = 49.5;
    const auto   surface = Surface(*image, isoValue);
    // Label above with face and below with full connectivity, by the brute-force reference.
    namespace reference = itk::SmallIsoComponentReference;
    const auto                      values = reference::BufferOf(image.GetPointer());
    std::vector<itk::SizeValueType> above;
    std::vector<itk::SizeValueType> below;
    std::vector<itk::SizeValueType> sizes;
    reference::LabelSide(
      reference::Grid<3>(reference::SizeOf(image.GetPointer()), false), values, isoValue, true, above, sizes);
    reference::LabelSide(
      reference::Grid<3>(reference::SizeOf(image.GetPointer()), true), values, isoValue, false, below, sizes);
    // Each point lies on an edge between an above and a below voxel: its piece gets that pair.
    std::vector<vtkIdType> parent(static_cast<std::size_t>(surface->GetNumberOfPoints()));
    std::iota(parent.begin(), parent.end(), vtkIdType{ 0 });
    const std::function<vtkIdType(vtkIdType)> find = [&](vtkIdType p) {
      while (parent[static_cast<std::size_t>(p)] != p)
        p = parent[static_cast<std::size_t>(p)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(p)])];
      return p;
    };
    auto cells = vtk::TakeSmartPointer(surface->GetPolys()->NewIterator());
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
    {
      vtkIdType         count = 0;
      const vtkIdType * ids = nullptr;
      cells->GetCurrentCell(count, ids);
      for (vtkIdType c = 1; c < count; ++c)
        parent[static_cast<std::size_t>(find(ids[c]))] = find(ids[0]);
    }
    std::map<vtkIdType, std::set<std::pair<std::size_t, std::size_t>>> pairsOfPiece;
    for (vtkIdType id = 0; id < surface->GetNumberOfPoints(); ++id)
    {
      double point[3];
      surface->GetPoints()->GetPoint(id, point);
      std::size_t low[3], high[3];
      for (int a = 0; a < 3; ++a)
      {
        low[a] = static_cast<std::size_t>(std::floor(point[a]));
        high[a] = static_cast<std::size_t>(std::ceil(point[a]));
      }
      const std::size_t p = low[0] + size[0] * (low[1] + size[1] * low[2]);
      const std::size_t q = high[0] + size[0] * (high[1] + size[1] * high[2]);
      const bool        pAbove = above[p] != itk::SmallIsoComponentReference::NoComponent;
      pairsOfPiece[find(id)].insert(pAbove ? std::make_pair(above[p], below[q]) : std::make_pair(above[q], below[p]));
    }
    std::set<std::pair<std::size_t, std::size_t>> touching;
    for (const auto & [piece, pairsHere] : pairsOfPiece)
    {
      CHECK(pairsHere.size() == 1,
            "volume " << volume << ": a piece separates " << pairsHere.size() << " pairs of components");
      touching.insert(pairsHere.begin(), pairsHere.end());
    }
    // Every above (face) component touching a below (full) component across a grid edge
    // has a piece between them.
    std::set<std::pair<std::size_t, std::size_t>> adjacent;
    for (std::size_t z = 0; z < size[2]; ++z)
      for (std::size_t y = 0; y < size[1]; ++y)
        for (std::size_t x = 0; x < size[0]; ++x)
          for (int a = 0; a < 3; ++a)
          {
            std::size_t next[3] = { x, y, z };
            if (++next[a] >= size[a])
              continue;
            const std::size_t p = x + size[0] * (y + size[1] * z);
            const std::size_t q = next[0] + size[0] * (next[1] + size[1] * next[2]);
            const bool        pAbove = above[p] != itk::SmallIsoComponentReference::NoComponent;
            const bool        qAbove = above[q] != itk::SmallIsoComponentReference::NoComponent;
            if (pAbove != qAbove)
              adjacent.insert(pAbove ? std::make_pair(above[p], below[q]) : std::make_pair(above[q], below[p]));
          }
    CHECK(adjacent == touching, "volume " << volume << ": touching pairs without a piece between them");
    pairs += adjacent.size();
    pieces += pairsOfPiece.size();
  }
  std::cout << pieces << " pieces for " << pairs << " touching pairs of components over 200 volumes\n";
}

const std::map<std::string, void (*)()> Cases = {
  { "PiecesMatchVtkConnectivity", PiecesMatchVtkConnectivity },
  { "PointsLieOnCrossingEdges", PointsLieOnCrossingEdges },
  { "PhysicalCoordinatesMatchITK", PhysicalCoordinatesMatchITK },
  { "FilesReadBack", FilesReadBack },
  { "BothRemovesThePiecesOfRemovedComponents", BothRemovesThePiecesOfRemovedComponents },
  { "UnchangedCellsKeepTheirTriangles", UnchangedCellsKeepTheirTriangles },
  { "PiecesSeparateAboveFaceAndBelowFullComponents", PiecesSeparateAboveFaceAndBelowFullComponents },
};
} // namespace

int
main(int argc, char * argv[])
{
  if (argc != 2 || Cases.find(argv[1]) == Cases.end())
  {
    std::cerr << "usage: SmallIsoComponentSurfaceTest CASE, with CASE one of:";
    for (const auto & [name, function] : Cases)
    {
      std::cerr << ' ' << name;
    }
    std::cerr << '\n';
    return 2;
  }
  Cases.at(argv[1])();
  if (failures > 0)
  {
    std::cerr << argv[1] << ": " << failures << " checks failed\n";
    return 1;
  }
  std::cout << argv[1] << ": passed\n";
  return 0;
}
