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
#ifndef itkSmallIsoComponentThreshold_h
#define itkSmallIsoComponentThreshold_h

#include "itkSmallIsoComponentRunLabeling.h"
#include <algorithm>
#include <type_traits>
#include <utility>
#include <vector>

namespace itk
{
/** \class SmallIsoComponentThreshold
 * \brief The isovalue σ seen through pixel type TPixel: which side a value is on, the
 * values closest to σ on each side, and the encoding of scanlines as runs.
 *
 * f >= σ holds exactly when f >= LowestAbove() (never for NaN); HighestBelow() is the
 * largest non-NaN value below σ. AnyAbove() / AnyBelow() tell whether the type has such a
 * value at all (for unsigned char, σ <= 0 leaves nothing below). Encode() splits every
 * line of a buffer into alternating runs of the two sides for
 * SmallIsoComponentRunLabeling, the slabs shared among the work units. The search for the next change of
 * side tests many voxels at once: 16 bytes per SSE2 compare for 8- and 16-bit integers and
 * float, blocks of 64 bytes (a reduction the compiler vectorises) for other types.
 *
 * \ingroup SmallIsoComponent
 */
template <typename TPixel>
class ITK_TEMPLATE_EXPORT SmallIsoComponentThreshold
{
public:
  using PixelType = TPixel;
  static_assert(std::is_arithmetic<TPixel>::value,
                "SmallIsoComponentThreshold needs a scalar pixel type (an integer or floating-point type).");

  explicit SmallIsoComponentThreshold(double isoValue);

  bool
  IsAbove(TPixel value) const
  {
    return m_AnyAbove && value >= m_LowestAbove;
  }
  bool
  AnyAbove() const
  {
    return m_AnyAbove;
  }
  bool
  AnyBelow() const
  {
    return m_AnyBelow;
  }
  TPixel
  LowestAbove() const
  {
    return m_LowestAbove;
  }
  TPixel
  HighestBelow() const
  {
    return m_HighestBelow;
  }

  /** The first x >= from where the side differs from \a above, or length. */
  SizeValueType
  NextSideChange(const TPixel * line, SizeValueType from, SizeValueType length, bool above) const;

  /** Encodes line number \a line, whose voxels start at \a values, appending its run
   * starts to \a starts and recording it in \a labeling. */
  void
  EncodeLine(const TPixel *                                              values,
             SizeValueType                                               line,
             SmallIsoComponentRunLabeling &                              labeling,
             std::vector<SmallIsoComponentRunLabeling::CoordinateType> & starts) const;

  /** Encodes every line of \a buffer (the whole image, lines along axis 0), the slabs of
   * \a labeling shared among the members of \a team. prepareLines(first, end) is called for consecutive blocks of
   * lines of a slab (about 32 KiB of voxels each) just before their lines are read, so
   * that the caller can fill the buffer block by block while it is in cache. */
  template <typename TPrepareLines>
  void
  Encode(const TPixel *                 buffer,
         SmallIsoComponentRunLabeling & labeling,
         SmallIsoComponentWorkTeam &    team,
         TPrepareLines &&               prepareLines) const
  {
    this->Encode(buffer, labeling, team, std::forward<TPrepareLines>(prepareLines), [] {});
  }

  /** The same; finishSlab() is called by the work unit that encoded a slab, after its
   * last line. */
  template <typename TPrepareLines, typename TFinishSlab>
  void
  Encode(const TPixel *                 buffer,
         SmallIsoComponentRunLabeling & labeling,
         SmallIsoComponentWorkTeam &    team,
         TPrepareLines &&               prepareLines,
         TFinishSlab &&                 finishSlab) const
  {
    const SizeValueType length = labeling.GetLineLength();
    const SizeValueType linesPerBlock = std::max<SizeValueType>(1, BlockBytes / (length * sizeof(TPixel)));
    team.ForEach(labeling.GetNumberOfSlabs(), [&](SizeValueType slab) {
      auto &              starts = labeling.GetSlabRunStarts(slab);
      const SizeValueType slabEnd = labeling.GetSlabBeginLine(slab + 1);
      for (SizeValueType block = labeling.GetSlabBeginLine(slab); block < slabEnd; block += linesPerBlock)
      {
        const SizeValueType blockEnd = std::min(slabEnd, block + linesPerBlock);
        prepareLines(block, blockEnd);
        for (SizeValueType line = block; line < blockEnd; ++line)
        {
          this->EncodeLine(buffer + line * length, line, labeling, starts);
        }
      }
      // AssembleRuns() holds these and the joined arrays at once: no spare capacity.
      starts.shrink_to_fit();
      finishSlab();
    });
  }

  /** Voxel bytes per block handed to prepareLines() in Encode(). */
  static constexpr SizeValueType BlockBytes = 32768;

private:
  template <SizeValueType VBlock>
  static bool
  BlockHasChange(const TPixel * block, TPixel lowestAbove, bool above);

  bool   m_AnyAbove{ false };
  TPixel m_LowestAbove{};
  bool   m_AnyBelow{ false };
  TPixel m_HighestBelow{};
};
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentThreshold.hxx"
#endif

#endif
