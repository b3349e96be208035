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
#ifndef itkSmallIsoComponentRepairMean_h
#define itkSmallIsoComponentRepairMean_h

#include "itkIntTypes.h"
#include "itkMath.h"
#include <cmath>
#include <limits>
#include <type_traits>

namespace itk
{
namespace SmallIsoComponentDetail
{
template <typename T>
bool
IsNaN(T value)
{
  if constexpr (std::is_floating_point<T>::value)
  {
    return std::isnan(value);
  }
  else
  {
    (void)value;
    return false;
  }
}

/** A mean of values of type T, as T: rounded half up for integers. */
template <typename T>
T
MeanToPixel(double mean)
{
  if constexpr (std::is_integral<T>::value)
  {
    return static_cast<T>(Math::Round<int64_t>(mean));
  }
  else
  {
    return static_cast<T>(mean);
  }
}

/** \class RepairMean
 * \brief The mean of the values that the walks of one removed voxel find, the repair
 * value of SmallIsoComponentImageFilter. Internal to the filter.
 *
 * A NaN is never a repair value and is not counted. The mean is the sum divided by the
 * number of values, in double. Only a sum of doubles near the limits of the type can
 * overflow (a bubble in samples of 1.7e308); then the mean is computed from the values
 * scaled by 1/16, which cannot overflow for up to 16 values, and scaled back, so that it
 * lies between the values as a mean does.
 *
 * \ingroup SmallIsoComponent
 */
class RepairMean
{
public:
  template <typename T>
  void
  Add(T value)
  {
    if (!IsNaN(value))
    {
      const auto v = static_cast<double>(value);
      m_Sum += v;
      m_ScaledSum += v * Scale;
      ++m_Count;
    }
  }

  /** The number of values added (NaN not counted). */
  unsigned int
  GetCount() const
  {
    return m_Count;
  }

  /** The mean as a pixel value; GetCount() must be positive. */
  template <typename TPixel>
  TPixel
  Get() const
  {
    if (std::isfinite(m_Sum) || !std::isfinite(m_ScaledSum))
    {
      return MeanToPixel<TPixel>(m_Sum / m_Count);
    }
    constexpr double largest = std::numeric_limits<double>::max();
    const double     mean = m_ScaledSum / m_Count / Scale;
    return MeanToPixel<TPixel>(std::max(-largest, std::min(largest, mean)));
  }

private:
  static constexpr double Scale = 1.0 / 16.0;

  double       m_Sum{ 0.0 };
  double       m_ScaledSum{ 0.0 };
  unsigned int m_Count{ 0 };
};

/** Adds to \a mean the value of the first voxel met along one direction that is not on the
 * side being removed. \a steps voxels lie that way before the image ends; sameSideAt(k,
 * value) sets \a value to the k-th of them (1 <= k <= steps) and tells whether it is on
 * the removed side. A walk that leaves the image adds nothing. */
template <typename TPixel, typename TSameSideAt>
inline void
AddFirstOtherSide(SizeValueType steps, TSameSideAt && sameSideAt, RepairMean & mean)
{
  for (SizeValueType k = 1; k <= steps; ++k)
  {
    TPixel value;
    if (!sameSideAt(k, value))
    {
      mean.Add(value);
      return;
    }
  }
}

/** Adds to \a mean the first values not on the removed side met walking both ways along one
 * axis from a voxel at coordinate \a at of \a extent along it. sameSideAt(offset, value)
 * sets \a value to the voxel \a offset steps away along the axis (negative: backwards) and
 * tells whether it is on the removed side. */
template <typename TPixel, typename TSameSideAt>
inline void
AddFirstOtherSideAlongAxis(SizeValueType at, SizeValueType extent, TSameSideAt && sameSideAt, RepairMean & mean)
{
  AddFirstOtherSide<TPixel>(
    at, [&](SizeValueType k, TPixel & value) { return sameSideAt(-static_cast<OffsetValueType>(k), value); }, mean);
  AddFirstOtherSide<TPixel>(
    extent - 1 - at,
    [&](SizeValueType k, TPixel & value) { return sameSideAt(static_cast<OffsetValueType>(k), value); },
    mean);
}

/** The walks of the removed voxels [start, end) of one line of \a length voxels, the repair
 * rule of both SmallIsoComponentImageFilter and its streaming form: calls emit(x, mean)
 * for each voxel x with the mean of the first values on the other side met along each of
 * the 2N axis directions. Along the line every voxel of the run meets the same two values,
 * found once. lineSameSide(x, value) classifies voxel x of the line as AddFirstOtherSide's
 * sameSideAt does; walkOtherAxes(x, mean) adds the values met along the other axes. */
template <typename TPixel, typename TLineSameSide, typename TWalkOtherAxes, typename TEmit>
inline void
RepairLineRun(SizeValueType     start,
              SizeValueType     end,
              SizeValueType     length,
              TLineSameSide &&  lineSameSide,
              TWalkOtherAxes && walkOtherAxes,
              TEmit &&          emit)
{
  RepairMean lineMean;
  AddFirstOtherSide<TPixel>(
    start, [&](SizeValueType k, TPixel & value) { return lineSameSide(start - k, value); }, lineMean);
  AddFirstOtherSide<TPixel>(
    length - end, [&](SizeValueType k, TPixel & value) { return lineSameSide(end - 1 + k, value); }, lineMean);
  for (SizeValueType x = start; x < end; ++x)
  {
    RepairMean mean = lineMean;
    walkOtherAxes(x, mean);
    emit(x, mean);
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
