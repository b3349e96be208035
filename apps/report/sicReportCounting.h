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
#ifndef sicReportCounting_h
#define sicReportCounting_h

#include "sicReportTable.h"

#include "itkMultiThreaderBase.h"
#include "itkSmallIsoComponentRunEncoder.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentThreshold.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

namespace sic
{
/** Counts the active cubes of an image (the cells of 2^N corners with corners on both
 * sides of an isovalue, those Marching Cubes turns into triangles) for any number of
 * isovalues.
 *
 * A cell has a corner >= S and a corner < S exactly when min < S <= max over its
 * corners, with NaN (never >= S) read as -infinity. The constructor finds every cell's
 * minimum and maximum once and sorts both lists (a counting sort for 8- and 16-bit
 * integers); the count at S is then (cells with min < S) - (cells with max < S), two
 * binary searches. Memory: two pixel values per cell. */
template <typename TPixel>
class ActiveCubeCounter
{
public:
  ActiveCubeCounter(const TPixel *                          buffer,
                    const std::vector<itk::SizeValueType> & size,
                    itk::MultiThreaderBase *                threader)
  {
    itk::SizeValueType cellLines = 1;
    for (size_t axis = 1; axis < size.size(); ++axis)
    {
      cellLines *= size[axis] - 1;
    }
    const itk::SizeValueType cellLength = size[0] - 1;
    m_Minima.resize(cellLength * cellLines);
    m_Maxima.resize(cellLength * cellLines);

    // The 2^(N-1) lines holding a cell line's corners, as offsets from its first one.
    std::vector<itk::SizeValueType> cornerLines{ 0 };
    itk::SizeValueType              lineStride = 1;
    for (size_t axis = 1; axis < size.size(); ++axis)
    {
      const size_t count = cornerLines.size();
      for (size_t i = 0; i < count; ++i)
      {
        cornerLines.push_back(cornerLines[i] + lineStride);
      }
      lineStride *= size[axis];
    }

    threader->ParallelizeArray(
      0,
      cellLines,
      [&](itk::SizeValueType cellLine) {
        // The image line of the cell line's first corner line.
        itk::SizeValueType rest = cellLine;
        itk::SizeValueType line = 0;
        itk::SizeValueType stride = 1;
        for (size_t axis = 1; axis < size.size(); ++axis)
        {
          line += (rest % (size[axis] - 1)) * stride;
          rest /= size[axis] - 1;
          stride *= size[axis];
        }
        TPixel * minima = m_Minima.data() + cellLine * cellLength;
        TPixel * maxima = m_Maxima.data() + cellLine * cellLength;
        for (itk::SizeValueType x = 0; x < cellLength; ++x)
        {
          TPixel low = Key(buffer[line * size[0] + x]);
          TPixel high = low;
          for (const itk::SizeValueType corner : cornerLines)
          {
            const TPixel * values = buffer + (line + corner) * size[0] + x;
            low = std::min({ low, Key(values[0]), Key(values[1]) });
            high = std::max({ high, Key(values[0]), Key(values[1]) });
          }
          minima[x] = low;
          maxima[x] = high;
        }
      },
      nullptr);
    Sort(m_Minima);
    Sort(m_Maxima);
  }

  itk::SizeValueType
  Count(double isoValue) const
  {
    const itk::SmallIsoComponentDetail::Threshold<TPixel> threshold(isoValue);
    const auto below = [&](TPixel value) { return !threshold.IsAbove(value); };
    const auto minimaBelow = std::partition_point(m_Minima.begin(), m_Minima.end(), below) - m_Minima.begin();
    const auto maximaBelow = std::partition_point(m_Maxima.begin(), m_Maxima.end(), below) - m_Maxima.begin();
    return static_cast<itk::SizeValueType>(minimaBelow - maximaBelow);
  }

private:
  /** The value a corner counts as: NaN is below every isovalue, like -infinity. */
  static TPixel
  Key(TPixel value)
  {
    if constexpr (std::is_floating_point<TPixel>::value)
    {
      return std::isnan(value) ? -std::numeric_limits<TPixel>::infinity() : value;
    }
    return value;
  }

  static void
  Sort(std::vector<TPixel> & values)
  {
    if constexpr (std::is_integral<TPixel>::value && sizeof(TPixel) <= 2)
    {
      constexpr auto                  lowest = std::numeric_limits<TPixel>::lowest();
      std::vector<itk::SizeValueType> counts(size_t{ 1 } << (8 * sizeof(TPixel)), 0);
      for (const TPixel value : values)
      {
        ++counts[static_cast<size_t>(static_cast<long>(value) - lowest)];
      }
      auto out = values.begin();
      for (size_t i = 0; i < counts.size(); ++i)
      {
        out = std::fill_n(out, counts[i], static_cast<TPixel>(static_cast<long>(i) + lowest));
      }
    }
    else
    {
      std::sort(values.begin(), values.end());
    }
  }

  std::vector<TPixel> m_Minima;
  std::vector<TPixel> m_Maxima;
};

/** Labels the components of both sides of \a isoValue in \a buffer (an image of extent
 * \a size, axis 0 fastest) with the module's run labelling, and histograms their sizes up
 * to \a largestSize.
 *
 * The run labelling is internal to SmallIsoComponentImageFilter; this is its one user
 * outside the filter. Counting for many isovalues needs only the labelling: the filter
 * would also copy the image to its output and clear a mask for every isovalue. */
template <typename TPixel>
void
LabelSides(const TPixel *                          buffer,
           const std::vector<itk::SizeValueType> & size,
           bool                                    fullyConnected,
           double                                  isoValue,
           itk::SizeValueType                      largestSize,
           itk::MultiThreaderBase *                threader,
           SideHistogram &                         above,
           SideHistogram &                         below)
{
  itk::SmallIsoComponentDetail::WorkTeam    team(threader, threader->GetNumberOfWorkUnits());
  itk::SmallIsoComponentDetail::RunLabeling labeling;
  labeling.Initialize(size, fullyConnected, threader->GetNumberOfWorkUnits());
  itk::SmallIsoComponentDetail::RunEncoder<TPixel>(isoValue).Encode(buffer, labeling, team);
  labeling.AssembleRuns(team);
  labeling.LinkRuns();
  labeling.LabelComponents(0, 0);

  above = SideHistogram();
  below = SideHistogram();
  above.CountOfSize.assign(largestSize + 1, 0);
  below.CountOfSize.assign(largestSize + 1, 0);
  for (itk::SizeValueType c = 0; c < labeling.GetComponents().GetNumberOfComponents(); ++c)
  {
    const auto      component = static_cast<itk::SmallIsoComponentDetail::RunLabeling::ComponentIndexType>(c);
    SideHistogram & side = labeling.GetComponents().IsComponentAbove(component) ? above : below;
    ++side.Components;
    const itk::SizeValueType componentSize = labeling.GetComponents().GetComponentSize(component);
    if (componentSize <= largestSize)
    {
      ++side.CountOfSize[componentSize];
    }
  }
}
} // namespace sic

#endif
