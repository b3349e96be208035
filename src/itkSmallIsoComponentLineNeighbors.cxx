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
#include "itkSmallIsoComponentLineNeighbors.h"
#include <algorithm>

namespace itk
{
namespace SmallIsoComponentDetail
{
LineNeighbors::LineNeighbors(const std::vector<SizeValueType> & size, bool fullyConnected)
  : m_Extent(size.begin() + (size.empty() ? 0 : 1), size.end())
  , m_FullyConnected(fullyConnected)
  , m_FaceIn3D(!fullyConnected && size.size() == 3)
{
  const auto    axes = static_cast<unsigned int>(m_Extent.size());
  SizeValueType stride = 1;
  for (unsigned int a = 0; a < axes; ++a)
  {
    m_Stride.push_back(stride);
    stride *= m_Extent[a];
  }
  if (!fullyConnected)
  {
    // One step back along the highest axis that has more than one line.
    for (unsigned int a = 0; a < axes; ++a)
    {
      m_FarthestEarlier = m_Extent[a] > 1 ? m_Stride[a] : m_FarthestEarlier;
    }
    return;
  }
  // Every combination of -1, 0, 1 along the axes but all 0. A neighbour is earlier when its
  // move along the highest axis it moves along is -1.
  SizeValueType combinations = 1;
  for (unsigned int a = 0; a < axes; ++a)
  {
    combinations *= 3;
  }
  for (SizeValueType code = 0; code < combinations; ++code)
  {
    Neighbor      neighbor;
    SizeValueType rest = code;
    int           highestMove = 0;
    for (unsigned int a = 0; a < axes; ++a)
    {
      const int move = static_cast<int>(rest % 3) - 1;
      rest /= 3;
      if (move != 0)
      {
        neighbor.LineOffset += move * static_cast<OffsetValueType>(m_Stride[a]);
        neighbor.Moves.emplace_back(a, move);
        highestMove = move;
      }
    }
    // A move along an axis of one line never stays inside; left in, its offset could even be
    // positive for an "earlier" neighbour, as that axis's stride equals the next one's.
    const bool alongSingleLine = std::any_of(
      neighbor.Moves.begin(), neighbor.Moves.end(), [this](const auto & m) { return m_Extent[m.first] == 1; });
    if (neighbor.Moves.empty() || alongSingleLine)
    {
      continue;
    }
    m_All.push_back(neighbor);
    if (highestMove < 0)
    {
      m_Earlier.push_back(neighbor);
      m_FarthestEarlier = std::max<SizeValueType>(m_FarthestEarlier, static_cast<SizeValueType>(-neighbor.LineOffset));
    }
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
