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
#ifndef itkSmallIsoComponentRunEncoder_h
#define itkSmallIsoComponentRunEncoder_h

#include "itkSmallIsoComponentBitPositions.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentSideBits.h"
#include "itkSmallIsoComponentThreshold.h"
#include "itkSmallIsoComponentTuning.h"
#include <algorithm>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class RunEncoder
 * \brief Splits scanlines into the alternating runs of the two sides of an isovalue, for
 * RunLabeling. Internal to SmallIsoComponentImageFilter.
 *
 * A line is described by the start of each of its runs and the side of its first run.
 * For 8- and 16-bit integers and float, where SSE2 is available, 16 voxels are classified
 * per compare (SideBits) and a run starts where a voxel's bit differs from the one before;
 * the other types search for the next change of side (NextSideChange()). Where the
 * processor has AVX-512 (chosen at run time), those types are classified 64 bytes a
 * compare instead, and on dense lines (those whose boundary bits the labeling keeps) the
 * starts of each 64 voxels are written by compresses.
 *
 * \ingroup SmallIsoComponent
 */
template <typename TPixel>
class ITK_TEMPLATE_EXPORT RunEncoder
{
public:
  using CoordinateType = RunLabeling::CoordinateType;

  explicit RunEncoder(double isoValue)
    : m_Threshold(isoValue)
  {}

  /** Whether EncodeLine() classifies voxels with SSE2 compares. */
#if defined(__SSE2__)
  static constexpr bool UsesSimd = HasSideBits<TPixel>;
#else
  static constexpr bool UsesSimd = false;
#endif

  /** Calls append(start) for the start of every run of the \a length voxels at \a values,
   * in order (the first run's 0 included), and returns whether the first run is above. */
  template <typename TAppend>
  bool
  EncodeLine(const TPixel * values, SizeValueType length, TAppend && append) const;

  /** The same through the search for the next change of side: the path of the pixel types
   * without SIMD compares, here for every type, so that the two can be compared. */
  template <typename TAppend>
  bool
  EncodeLineBySearch(const TPixel * values, SizeValueType length, TAppend && append) const;

  /** Appends the starts to \a starts. */
  bool
  EncodeLine(const TPixel * values, SizeValueType length, std::vector<CoordinateType> & starts) const
  {
    return this->EncodeLine(values, length, [&starts](CoordinateType start) { starts.push_back(start); });
  }
  bool
  EncodeLineBySearch(const TPixel * values, SizeValueType length, std::vector<CoordinateType> & starts) const
  {
    return this->EncodeLineBySearch(values, length, [&starts](CoordinateType start) { starts.push_back(start); });
  }

  /** The number of runs of the \a length voxels at \a values (at least 1), by one
   * comparison per voxel without branches. */
  SizeValueType
  CountRuns(const TPixel * values, SizeValueType length) const;

  /** Encodes every line of \a buffer (the whole image, lines along axis 0) into
   * \a labeling, the slabs shared among the members of \a team: first the runs of every
   * line are counted, then the labeling makes room for all of them at once and each line
   * writes its starts in place, so the run array is neither grown nor copied.
   * prepareLines(first, end) is called for consecutive blocks of lines of a slab (about
   * Tuning::EncoderBlockBytes of voxels each) just before their lines are first read, so that the caller
   * can fill the buffer block by block while it is in cache; finishSlab() is called by the
   * work unit that counted a slab, after its last line. */
  template <typename TPrepareLines, typename TFinishSlab>
  void
  Encode(const TPixel *   buffer,
         RunLabeling &    labeling,
         WorkTeam &       team,
         TPrepareLines && prepareLines,
         TFinishSlab &&   finishSlab) const
  {
    const SizeValueType length = labeling.GetLineLength();
    const SizeValueType linesPerBlock =
      std::max<SizeValueType>(1, Tuning::EncoderBlockBytes / (length * sizeof(TPixel)));
    team.ForEach(labeling.GetNumberOfSlabs(), [&](SizeValueType slab) {
      const SizeValueType slabEnd = labeling.GetSlabBeginLine(slab + 1);
      for (SizeValueType block = labeling.GetSlabBeginLine(slab); block < slabEnd; block += linesPerBlock)
      {
        const SizeValueType blockEnd = std::min(slabEnd, block + linesPerBlock);
        prepareLines(block, blockEnd);
        for (SizeValueType line = block; line < blockEnd; ++line)
        {
          const TPixel * values = buffer + line * length;
          labeling.SetLineRuns(line, this->CountRuns(values, length), m_Threshold.IsAbove(values[0]));
        }
      }
      finishSlab();
    });
    labeling.ReserveRuns();
    team.ForEach(labeling.GetNumberOfSlabs(), [&](SizeValueType slab) {
      for (SizeValueType line = labeling.GetSlabBeginLine(slab); line < labeling.GetSlabBeginLine(slab + 1); ++line)
      {
        CoordinateType * starts = labeling.GetLineRunStarts(line);
        if (uint64_t * bits = labeling.GetKeptLineBits(line))
        {
          this->EncodeLineAndBits(buffer + line * length, length, starts, bits);
        }
        else
        {
          this->EncodeLine(buffer + line * length, length, [&starts](CoordinateType start) { *starts++ = start; });
        }
      }
    });
  }

  /** Encodes every line of \a buffer, with nothing to prepare or finish. */
  void
  Encode(const TPixel * buffer, RunLabeling & labeling, WorkTeam & team) const
  {
    this->Encode(
      buffer, labeling, team, [](SizeValueType, SizeValueType) {}, [] {});
  }

  /** Writes the starts of the runs of the \a length voxels at \a values at \a starts, and
   * the line's boundary bits (a bit per voxel where a run starts, 64 voxels a word) at
   * \a bits: on the SIMD path from the same words of changes of side, each word's starts
   * written by WriteBitPositionsCompressed() where GetAvx512(). Encode() encodes
   * so the lines whose bits the labeling keeps (dense lines). */
  void
  EncodeLineAndBits(const TPixel * values, SizeValueType length, CoordinateType * starts, uint64_t * bits) const;

  /** Whether the encoder uses AVX-512: where the processor has it (HasAvx512()), for the
   * classification of the voxels (64 bytes a compare) and for the starts of dense lines. */
  bool
  GetAvx512() const
  {
    return m_Avx512;
  }

protected:
  /** Turns AVX-512 off, or on again where the processor has it (elsewhere it stays off), so
   * that the tests, through a class derived for the purpose, compare the two ways: the
   * output is the same. */
  void
  SetAvx512(bool on)
  {
#if defined(SMALLISO_AVX512_DISPATCH)
    m_Avx512 = on && HasAvx512();
#else
    (void)on;
#endif
  }

private:
#if defined(__SSE2__)
  /** The SIMD path: calls addChanges(change, base) with the bits of the voxels base to
   * base + 63 at which a run starts (voxel 0 excluded; all the calls in order) and returns
   * whether the first run is above. */
  template <typename TChanges>
  bool
  ForEachSideChange(const TPixel * values, SizeValueType length, TChanges && addChanges) const;
  /** The same with SSE2: 16 voxels a compare. */
  template <typename TChanges>
  bool
  ForEachSideChangeSse2(const TPixel * values, SizeValueType length, TChanges && addChanges) const;
#endif
#if defined(SMALLISO_AVX512_DISPATCH)
  /** The same with AVX-512: 64 bytes a compare, the last voxels of the line by a masked
   * load. Only where HasAvx512(). */
  template <typename TChanges>
  bool
  ForEachSideChangeAvx512(const TPixel * values, SizeValueType length, TChanges && addChanges) const;
#endif

  Threshold<TPixel> m_Threshold;
#if defined(SMALLISO_AVX512_DISPATCH)
  bool m_Avx512{ HasAvx512() };
#else
  bool m_Avx512{ false };
#endif
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentRunEncoder.hxx"
#endif

#endif
