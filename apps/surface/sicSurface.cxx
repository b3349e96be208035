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
#include "sicSurface.h"

#include "sicPlatform.h"
#include "sicStagedOutputs.h"
#include "sicStrings.h"
#include "sicToolError.h"
#include "sicVtkErrors.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDiscreteFlyingEdges3D.h"
#include "vtkFlyingEdges3D.h"
#include "vtkIdList.h"
#include "vtkImageData.h"
#include "vtkOBJReader.h"
#include "vtkOBJWriter.h"
#include "vtkPLYWriter.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSTLReader.h"
#include "vtkSTLWriter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedIntArray.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace sic
{
namespace
{
/** NaN samples are below every isovalue for the filter; for vtkFlyingEdges3D they would give
 * points with NaN coordinates. A copy with NaN replaced by the lowest finite value classifies
 * the same way and puts the crossing next to the other end of the edge. */
template <typename T>
std::vector<T>
WithoutNaN(const T * values, std::size_t count)
{
  std::vector<T> copy(values, values + count);
  std::replace_if(
    copy.begin(), copy.end(), [](T value) { return std::isnan(value); }, std::numeric_limits<T>::lowest());
  return copy;
}

template <typename T>
bool
HasNaN(const T * values, std::size_t count)
{
  return std::any_of(values, values + count, [](T value) { return std::isnan(value); });
}

std::string
LowerExtension(const std::string & path)
{
  return Lowercase(std::filesystem::path(path).extension().string());
}

/** The pieces of a surface as a union-find over its points: the points of each triangle are
 * in one set, so two points share a root exactly when they belong to one piece. */
class PointPieces
{
public:
  explicit PointPieces(vtkPolyData & surface)
    : m_Parent(static_cast<std::size_t>(surface.GetNumberOfPoints()))
    , m_Used(m_Parent.size(), false)
  {
    std::iota(m_Parent.begin(), m_Parent.end(), std::size_t{ 0 });
    if (surface.GetPolys() == nullptr)
    {
      return;
    }
    auto cells = vtk::TakeSmartPointer(surface.GetPolys()->NewIterator());
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
    {
      vtkIdType         count = 0;
      const vtkIdType * ids = nullptr;
      cells->GetCurrentCell(count, ids);
      for (vtkIdType corner = 0; corner < count; ++corner)
      {
        m_Used[static_cast<std::size_t>(ids[corner])] = true;
        const std::size_t a = Root(ids[0]);
        const std::size_t b = Root(ids[corner]);
        m_Parent[std::max(a, b)] = std::min(a, b);
      }
    }
  }

  std::size_t
  Root(vtkIdType point)
  {
    auto node = static_cast<std::size_t>(point);
    while (m_Parent[node] != node)
    {
      m_Parent[node] = m_Parent[m_Parent[node]];
      node = m_Parent[node];
    }
    return node;
  }

  /** Points are numbered 0 to Size() - 1; a piece has one root among its points. */
  std::size_t
  Size() const
  {
    return m_Parent.size();
  }

  /** Whether a triangle uses \a point (only used points belong to a piece). */
  bool
  Used(std::size_t point) const
  {
    return m_Used[point];
  }

private:
  std::vector<std::size_t> m_Parent;
  std::vector<bool>        m_Used;
};
} // namespace

vtkSmartPointer<vtkPolyData>
ExtractIsosurface(const SurfaceGrid & grid, double isoValue)
{
  const std::size_t count = grid.Size[0] * grid.Size[1] * grid.Size[2];
  if (grid.Size[0] < 2 || grid.Size[1] < 2 || grid.Size[2] < 2)
  {
    auto empty = vtkSmartPointer<vtkPolyData>::New();
    empty->SetPoints(vtkSmartPointer<vtkPoints>::New());
    empty->SetPolys(vtkSmartPointer<vtkCellArray>::New());
    return empty;
  }

  // The image only borrows the buffer (or the NaN-free copy, which lives until the end).
  std::vector<float>  floatCopy;
  std::vector<double> doubleCopy;
  const void *        buffer = grid.Buffer;
  if (grid.ScalarType == VTK_FLOAT && HasNaN(static_cast<const float *>(buffer), count))
  {
    floatCopy = WithoutNaN(static_cast<const float *>(buffer), count);
    buffer = floatCopy.data();
  }
  else if (grid.ScalarType == VTK_DOUBLE && HasNaN(static_cast<const double *>(buffer), count))
  {
    doubleCopy = WithoutNaN(static_cast<const double *>(buffer), count);
    buffer = doubleCopy.data();
  }

  vtkSmartPointer<vtkDataArray> scalars = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(grid.ScalarType));
  scalars->SetNumberOfComponents(1);
  scalars->SetVoidArray(const_cast<void *>(buffer), static_cast<vtkIdType>(count), 1);
  scalars->SetName("values");
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(static_cast<int>(grid.Size[0]), static_cast<int>(grid.Size[1]), static_cast<int>(grid.Size[2]));
  image->SetOrigin(0.0, 0.0, 0.0);
  image->SetSpacing(1.0, 1.0, 1.0);
  image->GetPointData()->SetScalars(scalars);

  auto contour = vtkSmartPointer<vtkFlyingEdges3D>::New();
  contour->SetInputData(image);
  contour->SetValue(0, isoValue);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->InterpolateAttributesOff();
  auto errors = vtkSmartPointer<VtkErrorCollector>::New();
  contour->AddObserver(vtkCommand::ErrorEvent, errors);
  contour->Update();
  if (errors->Raised)
  {
    throw std::runtime_error("isosurface extraction failed: " + errors->Message);
  }
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->ShallowCopy(contour->GetOutput());
  if (surface->GetPoints() == nullptr)
  {
    surface->SetPoints(vtkSmartPointer<vtkPoints>::New());
  }
  if (surface->GetPolys() == nullptr)
  {
    surface->SetPolys(vtkSmartPointer<vtkCellArray>::New());
  }
  return surface;
}

vtkSmartPointer<vtkPolyData>
ExtractLabelSurfaces(const SurfaceGrid & ordinals, std::uint32_t labels)
{
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->SetPoints(vtkSmartPointer<vtkPoints>::New());
  surface->SetPolys(vtkSmartPointer<vtkCellArray>::New());
  auto numbers = vtkSmartPointer<vtkUnsignedIntArray>::New();
  numbers->SetName(LabelArrayName);
  const std::size_t count = ordinals.Size[0] * ordinals.Size[1] * ordinals.Size[2];
  if (labels > 0 && ordinals.Size[0] >= 2 && ordinals.Size[1] >= 2 && ordinals.Size[2] >= 2)
  {
    auto scalars = vtkSmartPointer<vtkUnsignedIntArray>::New();
    scalars->SetVoidArray(const_cast<void *>(ordinals.Buffer), static_cast<vtkIdType>(count), 1);
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(
      static_cast<int>(ordinals.Size[0]), static_cast<int>(ordinals.Size[1]), static_cast<int>(ordinals.Size[2]));
    image->GetPointData()->SetScalars(scalars);

    auto contour = vtkSmartPointer<vtkDiscreteFlyingEdges3D>::New();
    contour->SetInputData(image);
    contour->GenerateValues(static_cast<int>(labels), 1.0, static_cast<double>(labels));
    contour->ComputeNormalsOff();
    contour->ComputeGradientsOff();
    // Each point's scalar is the label whose surface it is on: it gives the triangles their labels.
    contour->ComputeScalarsOn();
    contour->InterpolateAttributesOff();
    auto errors = vtkSmartPointer<VtkErrorCollector>::New();
    contour->AddObserver(vtkCommand::ErrorEvent, errors);
    contour->Update();
    if (errors->Raised)
    {
      throw std::runtime_error("label surface extraction failed: " + errors->Message);
    }
    vtkPolyData * output = contour->GetOutput();
    if (output->GetPolys() != nullptr && output->GetPoints() != nullptr)
    {
      vtkDataArray * pointLabels = output->GetPointData()->GetScalars();
      auto           cells = vtk::TakeSmartPointer(output->GetPolys()->NewIterator());
      for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
      {
        vtkIdType         size = 0;
        const vtkIdType * ids = nullptr;
        cells->GetCurrentCell(size, ids);
        numbers->InsertNextValue(static_cast<std::uint32_t>(pointLabels->GetTuple1(ids[0])));
      }
      surface->SetPoints(output->GetPoints());
      surface->SetPolys(output->GetPolys());
    }
  }
  surface->GetCellData()->AddArray(numbers);
  return surface;
}

namespace
{
vtkUnsignedIntArray &
LabelNumbers(vtkPolyData & surface)
{
  auto * numbers = vtkUnsignedIntArray::SafeDownCast(surface.GetCellData()->GetArray(LabelArrayName));
  if (numbers == nullptr || numbers->GetNumberOfTuples() != surface.GetNumberOfPolys())
  {
    throw std::logic_error("a label surface lacks its label numbers");
  }
  return *numbers;
}
} // namespace

std::vector<std::uint64_t>
CountSurfacePiecesPerLabel(vtkPolyData & surface, std::uint32_t labels)
{
  std::vector<std::uint64_t> counts(std::size_t{ labels } + 1, 0);
  vtkUnsignedIntArray &      numbers = LabelNumbers(surface);
  PointPieces                pieces(surface);
  // A piece's label: that of a triangle holding its root (the labels share no points).
  std::vector<bool> counted(pieces.Size(), false);
  auto              cells = vtk::TakeSmartPointer(surface.GetPolys()->NewIterator());
  vtkIdType         triangle = 0;
  for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell(), ++triangle)
  {
    vtkIdType         size = 0;
    const vtkIdType * ids = nullptr;
    cells->GetCurrentCell(size, ids);
    const std::size_t root = pieces.Root(ids[0]);
    if (!counted[root])
    {
      counted[root] = true;
      ++counts.at(numbers.GetValue(triangle));
    }
  }
  return counts;
}

void
ColourLabels(vtkPolyData & surface, const std::vector<std::array<unsigned char, 3>> & colours)
{
  vtkUnsignedIntArray & numbers = LabelNumbers(surface);
  auto                  rgb = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgb->SetName(SurfaceColourArrayName);
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(numbers.GetNumberOfTuples());
  for (vtkIdType triangle = 0; triangle < numbers.GetNumberOfTuples(); ++triangle)
  {
    const auto & colour = colours.at(numbers.GetValue(triangle));
    rgb->SetTypedTuple(triangle, colour.data());
  }
  surface.GetCellData()->SetScalars(rgb);
}

void
NameLabels(vtkPolyData & surface, vtkDataArray & ids)
{
  vtkUnsignedIntArray &         numbers = LabelNumbers(surface);
  vtkSmartPointer<vtkDataArray> labels = vtk::TakeSmartPointer(ids.NewInstance());
  labels->SetName(LabelArrayName);
  labels->SetNumberOfTuples(numbers.GetNumberOfTuples());
  for (vtkIdType triangle = 0; triangle < numbers.GetNumberOfTuples(); ++triangle)
  {
    labels->SetTuple(triangle, numbers.GetValue(triangle) - 1, &ids);
  }
  surface.GetCellData()->RemoveArray(LabelArrayName);
  surface.GetCellData()->AddArray(labels);
}

void
TransformToPhysical(vtkPolyData & surface, const SurfaceGeometry & geometry)
{
  // M = Direction · diag(Spacing), so that p = Origin + M · index, as ITK maps indices.
  double matrix[9];
  for (int row = 0; row < 3; ++row)
  {
    for (int column = 0; column < 3; ++column)
    {
      matrix[3 * row + column] = geometry.Direction[3 * row + column] * geometry.Spacing[column];
    }
  }
  vtkPoints * points = surface.GetPoints();
  if (points == nullptr)
  {
    return;
  }
  // Double precision keeps the physical coordinates as exact as ITK's own mapping.
  auto physical = vtkSmartPointer<vtkPoints>::New();
  physical->SetDataTypeToDouble();
  physical->SetNumberOfPoints(points->GetNumberOfPoints());
  for (vtkIdType id = 0; id < points->GetNumberOfPoints(); ++id)
  {
    double index[3];
    points->GetPoint(id, index);
    double point[3];
    for (int row = 0; row < 3; ++row)
    {
      point[row] = geometry.Origin[row] + matrix[3 * row] * index[0] + matrix[3 * row + 1] * index[1] +
                   matrix[3 * row + 2] * index[2];
    }
    physical->SetPoint(id, point);
  }
  surface.SetPoints(physical);

  const double determinant = matrix[0] * (matrix[4] * matrix[8] - matrix[5] * matrix[7]) -
                             matrix[1] * (matrix[3] * matrix[8] - matrix[5] * matrix[6]) +
                             matrix[2] * (matrix[3] * matrix[7] - matrix[4] * matrix[6]);
  if (determinant < 0.0 && surface.GetPolys() != nullptr)
  {
    vtkCellArray * polys = surface.GetPolys();
    for (vtkIdType cell = 0; cell < polys->GetNumberOfCells(); ++cell)
    {
      polys->ReverseCellAtId(cell);
    }
  }
}

std::uint64_t
CountSurfacePieces(vtkPolyData & surface)
{
  PointPieces   pieces(surface);
  std::uint64_t count = 0;
  for (std::size_t point = 0; point < pieces.Size(); ++point)
  {
    count += pieces.Used(point) && pieces.Root(static_cast<vtkIdType>(point)) == point;
  }
  return count;
}

RemovedTriangles
TrianglesOfChangedCells(vtkPolyData &                      surface,
                        const std::uint8_t *               mask,
                        const std::array<std::size_t, 3> & size,
                        bool                               wholePiecesOnly)
{
  RemovedTriangles removed;
  // Per triangle: 0 unchanged, 1 a speck's, 2 a bubble's.
  std::vector<std::uint8_t> kind;
  auto                      specks = vtkSmartPointer<vtkCellArray>::New();
  auto                      bubbles = vtkSmartPointer<vtkCellArray>::New();
  auto                      all = vtkSmartPointer<vtkCellArray>::New();
  // The triangles of surface that each of the three keeps, to copy their cell data.
  std::array<std::vector<vtkIdType>, 3> kept;
  vtkCellArray *                        polys = surface.GetPolys();
  vtkPoints *                           points = surface.GetPoints();
  if (polys != nullptr && points != nullptr && size[0] >= 2 && size[1] >= 2 && size[2] >= 2)
  {
    const std::size_t strideY = size[0];
    const std::size_t strideZ = size[0] * size[1];
    auto              cells = vtk::TakeSmartPointer(polys->NewIterator());
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
    {
      vtkIdType         count = 0;
      const vtkIdType * ids = nullptr;
      cells->GetCurrentCell(count, ids);
      // The cell holding the triangle: per axis the lowest coordinate of its points, rounded
      // down (a triangle flat on a cell face may take either cell: both hold that face).
      double lowest[3] = { std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::max() };
      for (vtkIdType corner = 0; corner < count; ++corner)
      {
        double point[3];
        points->GetPoint(ids[corner], point);
        for (int axis = 0; axis < 3; ++axis)
        {
          lowest[axis] = std::min(lowest[axis], point[axis]);
        }
      }
      std::size_t cell[3];
      for (int axis = 0; axis < 3; ++axis)
      {
        const double low = std::floor(std::max(lowest[axis], 0.0));
        cell[axis] = std::min(static_cast<std::size_t>(low), size[axis] - 2);
      }
      bool speck = false;
      bool bubble = false;
      for (int corner = 0; corner < 8; ++corner)
      {
        const std::size_t offset = (cell[0] + (corner & 1)) + (cell[1] + ((corner >> 1) & 1)) * strideY +
                                   (cell[2] + ((corner >> 2) & 1)) * strideZ;
        speck = speck || mask[offset] == 1;
        bubble = bubble || mask[offset] == 2;
      }
      kind.push_back(speck ? 1 : bubble ? 2 : 0);
    }
    // A piece is taken away whole when none of its triangles is unchanged.
    std::optional<PointPieces> pieces;
    std::vector<bool>          keptPiece;
    if (wholePiecesOnly)
    {
      pieces.emplace(surface);
      keptPiece.assign(pieces->Size(), false);
      std::size_t triangle = 0;
      for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell(), ++triangle)
      {
        vtkIdType         count = 0;
        const vtkIdType * ids = nullptr;
        cells->GetCurrentCell(count, ids);
        if (kind[triangle] == 0)
        {
          keptPiece[pieces->Root(ids[0])] = true;
        }
      }
    }
    std::size_t triangle = 0;
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell(), ++triangle)
    {
      vtkIdType         count = 0;
      const vtkIdType * ids = nullptr;
      cells->GetCurrentCell(count, ids);
      if (kind[triangle] == 0 || (pieces && keptPiece[pieces->Root(ids[0])]))
      {
        continue;
      }
      (kind[triangle] == 1 ? specks : bubbles)->InsertNextCell(count, ids);
      all->InsertNextCell(count, ids);
      kept[kind[triangle] - 1].push_back(static_cast<vtkIdType>(triangle));
      kept[2].push_back(static_cast<vtkIdType>(triangle));
    }
  }
  const auto make = [&surface](vtkCellArray * triangles, const std::vector<vtkIdType> & from) {
    auto result = vtkSmartPointer<vtkPolyData>::New();
    result->SetPoints(surface.GetPoints() != nullptr ? surface.GetPoints() : vtkSmartPointer<vtkPoints>::New().Get());
    result->SetPolys(triangles);
    result->GetCellData()->CopyAllocate(surface.GetCellData(), static_cast<vtkIdType>(from.size()));
    for (std::size_t to = 0; to < from.size(); ++to)
    {
      result->GetCellData()->CopyData(surface.GetCellData(), from[to], static_cast<vtkIdType>(to));
    }
    return result;
  };
  removed.Specks = make(specks, kept[0]);
  removed.Bubbles = make(bubbles, kept[1]);
  removed.All = make(all, kept[2]);
  return removed;
}

namespace
{
/** Bytes of a PLY scalar type, 0 for an unknown one. */
std::size_t
PlyTypeBytes(const std::string & type)
{
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8")
    return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16")
    return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" || type == "float32")
    return 4;
  if (type == "double" || type == "float64")
    return 8;
  return 0;
}

/** Whether \a path is a complete binary PLY file with \a points vertices and \a polygons faces: every element's
 * every property, lists included, is there, walking the data as the header declares it. */
bool
IsCompleteBinaryPly(const std::string & path, vtkIdType points, vtkIdType polygons)
{
  struct Property
  {
    std::size_t Bytes{ 0 };
    /** For a list, the bytes of its count; 0 for a scalar. */
    std::size_t CountBytes{ 0 };
  };
  struct Element
  {
    std::string           Name;
    std::uint64_t         Count{ 0 };
    std::vector<Property> Properties;
  };
  std::ifstream        file(path, std::ios::binary);
  std::string          line;
  std::vector<Element> elements;
  bool                 littleEndian = true;
  while (std::getline(file, line) && line != "end_header")
  {
    std::istringstream words(line);
    std::string        keyword;
    words >> keyword;
    if (keyword == "format")
    {
      std::string format;
      words >> format;
      littleEndian = format == "binary_little_endian";
      if (!littleEndian && format != "binary_big_endian")
      {
        return false;
      }
    }
    else if (keyword == "element")
    {
      Element element;
      words >> element.Name >> element.Count;
      elements.push_back(element);
    }
    else if (keyword == "property" && !elements.empty())
    {
      std::string type;
      words >> type;
      Property property;
      if (type == "list")
      {
        std::string countType;
        words >> countType >> type;
        property.CountBytes = PlyTypeBytes(countType);
        if (property.CountBytes == 0)
        {
          return false;
        }
      }
      property.Bytes = PlyTypeBytes(type);
      if (property.Bytes == 0)
      {
        return false;
      }
      elements.back().Properties.push_back(property);
    }
  }
  if (!file)
  {
    return false;
  }
  for (const Element & element : elements)
  {
    if ((element.Name == "vertex" && element.Count != static_cast<std::uint64_t>(points)) ||
        (element.Name == "face" && element.Count != static_cast<std::uint64_t>(polygons)))
    {
      return false;
    }
    for (std::uint64_t record = 0; record < element.Count; ++record)
    {
      for (const Property & property : element.Properties)
      {
        std::uint64_t values = 1;
        if (property.CountBytes > 0)
        {
          unsigned char count[8] = {};
          if (!file.read(reinterpret_cast<char *>(count), static_cast<std::streamsize>(property.CountBytes)))
          {
            return false;
          }
          values = 0;
          for (std::size_t i = 0; i < property.CountBytes; ++i)
          {
            const std::size_t byte = littleEndian ? property.CountBytes - 1 - i : i;
            values = (values << 8) | count[byte];
          }
        }
        file.seekg(static_cast<std::streamoff>(values * property.Bytes), std::ios::cur);
      }
    }
  }
  // Seeking past the end succeeds: the position reached must be within the file.
  const std::streamoff reached = file.tellg();
  file.seekg(0, std::ios::end);
  return file && reached >= 0 && reached <= file.tellg();
}
} // namespace

std::string
SupportedSurfaceExtensions()
{
  return ".vtp, .stl, .ply or .obj";
}

void
CheckSurfaceFileFormat(const std::string & path, const std::string & what)
{
  const std::string extension = LowerExtension(path);
  if (extension != ".vtp" && extension != ".stl" && extension != ".ply" && extension != ".obj")
  {
    throw ToolError("cannot write the " + what + " '" + path + "': " +
                    (extension.empty() ? std::string("it has no extension")
                                       : "the extension '" + extension + "' is not a surface format") +
                    "; expected " + SupportedSurfaceExtensions());
  }
}

void
WriteSurface(vtkPolyData &       surface,
             const std::string & stagedPath,
             const std::string & finalPath,
             const std::string & what)
{
  const std::string failure = "cannot write the " + what + " to '" + finalPath + "'";
  // VTK and its writers print their own lines (a pipeline dump) about a failure: the error says it in one.
  StandardErrorCapture messages;
  const auto           write = [&](auto writer) {
    auto errors = vtkSmartPointer<VtkErrorCollector>::New();
    writer->AddObserver(vtkCommand::ErrorEvent, errors);
    writer->SetInputData(&surface);
    writer->SetFileName(stagedPath.c_str());
    const int       written = writer->Write();
    std::error_code error;
    if (written != 1 || writer->GetErrorCode() != 0 || errors->Raised || !std::filesystem::exists(stagedPath, error))
    {
      throw ToolError(failure + (errors->Message.empty()
                                             ? std::string()
                                             : ": " + ShowFinalPaths(errors->Message, stagedPath, finalPath)));
    }
  };
  // Some writers (PLY, OBJ) do not notice a failed write, e.g. on a full disk: the surface is read back, and must
  // have every triangle.
  const std::string extension = LowerExtension(finalPath);
  const auto        readBack = [&](auto reader) {
    auto errors = vtkSmartPointer<VtkErrorCollector>::New();
    reader->AddObserver(vtkCommand::ErrorEvent, errors);
    reader->SetFileName(stagedPath.c_str());
    reader->Update();
    vtkPolyData * written = reader->GetOutput();
    bool          arrays = written != nullptr;
    for (int array = 0; arrays && extension == ".vtp" && array < surface.GetCellData()->GetNumberOfArrays(); ++array)
    {
      vtkDataArray * read = written->GetCellData()->GetArray(surface.GetCellData()->GetArrayName(array));
      arrays = read != nullptr && read->GetNumberOfTuples() == surface.GetNumberOfPolys();
    }
    if (errors->Raised || !arrays || written->GetNumberOfPolys() != surface.GetNumberOfPolys() ||
        written->GetPolys()->GetNumberOfConnectivityIds() != surface.GetPolys()->GetNumberOfConnectivityIds())
    {
      throw ToolError(failure + ": the file written does not read back as the surface (is the disk full?)");
    }
  };
  if (extension == ".vtp")
  {
    auto writer = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToZLib();
    write(writer);
    readBack(vtkSmartPointer<vtkXMLPolyDataReader>::New());
  }
  else if (extension == ".stl")
  {
    auto writer = vtkSmartPointer<vtkSTLWriter>::New();
    writer->SetFileTypeToBinary();
    write(writer);
    // Merging points would drop the triangles whose corners coincide.
    auto reader = vtkSmartPointer<vtkSTLReader>::New();
    reader->MergingOff();
    readBack(reader);
  }
  else if (extension == ".ply")
  {
    auto writer = vtkSmartPointer<vtkPLYWriter>::New();
    writer->SetFileTypeToBinary();
    // A label surface's triangles keep their labels' colours, as the faces' red, green and blue.
    if (surface.GetCellData()->GetArray(SurfaceColourArrayName) != nullptr)
    {
      writer->SetArrayName(SurfaceColourArrayName);
    }
    write(writer);
    // VTK's PLY reader crashes on a cut PLY file: its size is checked against its header instead.
    if (!IsCompleteBinaryPly(stagedPath, surface.GetNumberOfPoints(), surface.GetNumberOfPolys()))
    {
      throw ToolError(failure + ": the file written is incomplete (is the disk full?)");
    }
  }
  else if (extension == ".obj")
  {
    write(vtkSmartPointer<vtkOBJWriter>::New());
    readBack(vtkSmartPointer<vtkOBJReader>::New());
  }
  else
  {
    CheckSurfaceFileFormat(finalPath, what);
  }
  messages.Replay();
}
} // namespace sic
