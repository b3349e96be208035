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
#ifndef itkSmallIsoComponentLineNeighbors_h
#define itkSmallIsoComponentLineNeighbors_h

#include "itkIntTypes.h"
#include "itkSmallIsoComponentBitCount.h"
#include "itkNumericTraits.h"
#include "SmallIsoComponentExport.h"
#include <utility>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class LineNeighbors
 * \brief The lines next to a line, whose runs the runs of that line can touch. Internal to
 * SmallIsoComponentImageFilter.
 *
 * The image is seen as lines along axis 0, numbered with axis 1 varying fastest. Face
 * connectivity makes neighbours of the lines one step away along one of the axes 1..N-1,
 * full connectivity also of the diagonal ones (diagonals that involve axis 0 are a
 * one-voxel overlap of runs, which is the caller's business). A Position is a line with
 * its coordinates, stepped through the lines in order with Next() or set to any line with
 * MoveTo(); ForEachEarlier() and ForEachNeighbor() call a function for the neighbouring
 * lines of a position inside the image. Face connectivity in 3-D, the common case, takes
 * a path of its own without the neighbour tables.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT LineNeighbors
{
public:
  LineNeighbors() = default;
  /** Neighbours in an image of extent \a size (axis 0 along the lines). */
  LineNeighbors(const std::vector<SizeValueType> & size, bool fullyConnected);

  /** A line and its coordinates along axes 1..N-1, read by LineNeighbors only. */
  class Position
  {
    friend class LineNeighbors;
    SizeValueType              m_Line{ NumericTraits<SizeValueType>::max() };
    std::vector<SizeValueType> m_Coordinates;
  };

  /** Sets \a position to \a line. */
  void
  MoveTo(Position & position, SizeValueType line) const
  {
    if (position.m_Line == line)
    {
      return;
    }
    position.m_Line = line;
    position.m_Coordinates.resize(m_Extent.size());
    if (m_Extent.empty())
    {
      return;
    }
    const auto last = static_cast<unsigned int>(m_Extent.size() - 1);
    for (unsigned int a = 0; a < last; ++a)
    {
      position.m_Coordinates[a] = line % m_Extent[a];
      line /= m_Extent[a];
    }
    position.m_Coordinates[last] = line;
  }

  /** A position at \a line. */
  Position
  At(SizeValueType line) const
  {
    Position position;
    this->MoveTo(position, line);
    return position;
  }

  /** Moves \a position to the next line. */
  void
  Next(Position & position) const
  {
    ++position.m_Line;
    for (unsigned int a = 0; a < m_Extent.size(); ++a)
    {
      if (++position.m_Coordinates[a] < m_Extent[a])
      {
        return;
      }
      position.m_Coordinates[a] = 0;
    }
  }

  /** Calls function(neighbor) for every neighbouring line of \a position inside the image
   * that has a lower line number than it (so that a walk over the lines meets each pair of
   * neighbours once). */
  template <typename TFunction>
  void
  ForEachEarlier(const Position & position, TFunction && function) const
  {
    this->ForEach<false>(position, function);
  }

  /** The most lines between a line and the earliest of its earlier neighbours (0 when
   * lines have no neighbours): how far back a walk over the lines in order reaches. */
  SizeValueType
  GetFarthestEarlier() const
  {
    return m_FarthestEarlier;
  }

  /** Calls function(neighbor) for every neighbouring line of \a position inside the
   * image. */
  template <typename TFunction>
  SMALLISO_ALWAYS_INLINE void
  ForEachNeighbor(const Position & position, TFunction && function) const
  {
    this->ForEach<true>(position, function);
  }

private:
  /** The walk of ForEachEarlier() (earlier lines only) and ForEachNeighbor() (\a VLater). */
  template <bool VLater, typename TFunction>
  SMALLISO_ALWAYS_INLINE void
  ForEach(const Position & position, TFunction && function) const
  {
    const SizeValueType                line = position.m_Line;
    const std::vector<SizeValueType> & coordinates = position.m_Coordinates;
    if (m_FaceIn3D)
    {
      if (coordinates[0] > 0)
      {
        function(line - 1);
      }
      if (VLater && coordinates[0] + 1 < m_Extent[0])
      {
        function(line + 1);
      }
      if (coordinates[1] > 0)
      {
        function(line - m_Stride[1]);
      }
      if (VLater && coordinates[1] + 1 < m_Extent[1])
      {
        function(line + m_Stride[1]);
      }
    }
    else if (!m_FullyConnected)
    {
      for (unsigned int a = 0; a < m_Extent.size(); ++a)
      {
        if (coordinates[a] > 0)
        {
          function(line - m_Stride[a]);
        }
        if (VLater && coordinates[a] + 1 < m_Extent[a])
        {
          function(line + m_Stride[a]);
        }
      }
    }
    else
    {
      for (const Neighbor & neighbor : VLater ? m_All : m_Earlier)
      {
        if (this->Inside(coordinates, neighbor))
        {
          function(line + neighbor.LineOffset);
        }
      }
    }
  }

  /** A neighbouring line under full connectivity: its offset in line numbers, and the
   * axes (index into the coordinates) along which it moves, with the direction. */
  struct Neighbor
  {
    OffsetValueType                           LineOffset{ 0 };
    std::vector<std::pair<unsigned int, int>> Moves;
  };

  bool
  Inside(const std::vector<SizeValueType> & coordinates, const Neighbor & neighbor) const
  {
    for (const auto & move : neighbor.Moves)
    {
      if (move.second < 0 ? coordinates[move.first] == 0 : coordinates[move.first] + 1 >= m_Extent[move.first])
      {
        return false;
      }
    }
    return true;
  }

  /** Extent along axes 1..N-1, and the line numbers between neighbours along each. */
  std::vector<SizeValueType> m_Extent;
  std::vector<SizeValueType> m_Stride;
  bool                       m_FullyConnected{ false };
  bool                       m_FaceIn3D{ false };
  SizeValueType              m_FarthestEarlier{ 0 };
  /** Under full connectivity: the neighbours with lower line numbers, and all. */
  std::vector<Neighbor> m_Earlier;
  std::vector<Neighbor> m_All;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
