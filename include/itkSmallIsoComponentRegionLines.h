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
#ifndef itkSmallIsoComponentRegionLines_h
#define itkSmallIsoComponentRegionLines_h

#include "itkImageRegion.h"
#include "itkSmallIsoComponentLineSlabs.h"
#include <algorithm>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \name The lines of a buffer of an image region
 * A buffer of a region holds its voxels in lines along axis 0, the lines in order along the
 * other axes. These functions are the one place a line number or an offset in such a buffer
 * becomes an index, and back.
 * \ingroup SmallIsoComponent */
/** @{ */
/** The number of lines of a buffer of \a region. */
template <unsigned int VDimension>
SizeValueType
NumberOfLines(const ImageRegion<VDimension> & region)
{
  SizeValueType lines = 1;
  for (unsigned int a = 1; a < VDimension; ++a)
  {
    lines *= region.GetSize(a);
  }
  return lines;
}

/** The index of the first voxel of line \a line of a buffer of \a region. */
template <unsigned int VDimension>
Index<VDimension>
IndexOfLine(const ImageRegion<VDimension> & region, SizeValueType line)
{
  Index<VDimension> index = region.GetIndex();
  for (unsigned int a = 1; a < VDimension; ++a)
  {
    index[a] += static_cast<IndexValueType>(line % region.GetSize(a));
    line /= region.GetSize(a);
  }
  return index;
}

/** The index of voxel \a offset of a buffer of \a region. */
template <unsigned int VDimension>
Index<VDimension>
IndexOf(const ImageRegion<VDimension> & region, SizeValueType offset)
{
  Index<VDimension> index = IndexOfLine(region, offset / region.GetSize(0));
  index[0] += static_cast<IndexValueType>(offset % region.GetSize(0));
  return index;
}

/** The offset of \a index, inside \a region, in a buffer of \a region. */
template <unsigned int VDimension>
SizeValueType
OffsetOf(const ImageRegion<VDimension> & region, const Index<VDimension> & index)
{
  SizeValueType offset = 0;
  SizeValueType stride = 1;
  for (unsigned int a = 0; a < VDimension; ++a)
  {
    offset += static_cast<SizeValueType>(index[a] - region.GetIndex(a)) * stride;
    stride *= region.GetSize(a);
  }
  return offset;
}

/** Copies \a region from \a source, a buffer of \a sourceRegion, into \a target, a buffer of
 * \a targetRegion, line by line, shared among the members of \a team when given. */
template <typename TPixel, unsigned int VDimension>
void
CopyLines(const TPixel *                  source,
          const ImageRegion<VDimension> & sourceRegion,
          TPixel *                        target,
          const ImageRegion<VDimension> & targetRegion,
          const ImageRegion<VDimension> & region,
          WorkTeam *                      team = nullptr)
{
  const SizeValueType lines = NumberOfLines(region);
  const auto          copyLine = [&](SizeValueType line) {
    const Index<VDimension> first = IndexOfLine(region, line);
    std::copy_n(source + OffsetOf(sourceRegion, first), region.GetSize(0), target + OffsetOf(targetRegion, first));
  };
  if (team == nullptr || lines < 2)
  {
    for (SizeValueType line = 0; line < lines; ++line)
    {
      copyLine(line);
    }
    return;
  }
  ForEachLineInSlabs(*team, lines, copyLine);
}
/** @} */
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
