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
#ifndef itkSmallIsoComponentRunLinking_h
#define itkSmallIsoComponentRunLinking_h

#include "itkIntTypes.h"
#include "itkSmallIsoComponentLargeArray.h"
#include "itkSmallIsoComponentLineNeighbors.h"
#include "SmallIsoComponentExport.h"
#include "itkSmallIsoComponentTuning.h"
#include <memory>
#include <mutex>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class RunLinking
 * \brief Links the runs of neighbouring lines that touch, for RunLabeling's union-find.
 * Internal to RunLabeling, which holds the runs and lends this class its run arrays.
 *
 * Two neighbouring lines are linked by a merge of their runs, or, where runs are dense,
 * from the lines' boundary bits (a bit per voxel where a run starts), which finds the
 * touching pairs by bit counts without a branch per run. Where the lines are dense on
 * average the bits of every line are kept (the encoder writes them beside the starts);
 * otherwise each work unit keeps those of the lines a line reaches back to in a ring of
 * at most Tuning::BitsCacheBytes, and writes a line's again from its starts when it fell out.
 *
 * The union-find is Rem's algorithm with splicing over the runs' parents, linking towards
 * the smaller run index. The runs inside a slab are linked by whoever handles the slab,
 * without locks (only the slab's runs are touched); the seams between slabs afterwards.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT RunLinking
{
public:
  using RunIndexType = uint32_t;
  using CoordinateType = uint32_t;

  /** How two neighbouring lines have their runs linked (the tests choose; the result is
   * the same). */
  enum class LineLinking : uint8_t
  {
    /** By their boundary bits where the two lines have at least Tuning::BitsRunsPerWord runs per
     * 64 voxels of line, else by a merge. */
    Automatic,
    /** Always by a merge of their runs. */
    Merge,
    /** By their boundary bits whenever both lines' bits can be held at once. */
    Bits
  };
  /** Chooses how lines are linked and how many bytes of boundary bits a work unit keeps,
   * from the next Initialize() on. */
  void
  SetLineLinking(LineLinking linking, SizeValueType bitsCacheBytes)
  {
    m_LineLinking = linking;
    m_BitsCacheBytes = bitsCacheBytes;
  }
  LineLinking
  GetLineLinking() const
  {
    return m_LineLinking;
  }
  SizeValueType
  GetBitsCacheBytes() const
  {
    return m_BitsCacheBytes;
  }

  /** Sets the image extent (axis 0 along the lines) and the connectivity, and sizes the
   * rings of boundary bits. The runs are those of the next SetRuns(). */
  void
  Initialize(const std::vector<SizeValueType> & size, bool fullyConnected);

  /** The neighbouring lines of each line under the connectivity. */
  const LineNeighbors &
  GetLineNeighbors() const
  {
    return m_LineNeighbors;
  }

  /** The runs to link: RunLabeling's arrays once they have room for all \a numberOfRuns
   * runs, valid until they are made room for again. \a parent is each run's parent, set by
   * the caller to the run itself before its slab is linked. Decides whether every line's
   * boundary bits are kept, and makes room for them. */
  void
  SetRuns(const CoordinateType * start,
          RunIndexType *         parent,
          const SizeValueType *  lineBegin,
          const uint8_t *        lineFirstAbove,
          SizeValueType          numberOfRuns);

  /** Where \a line's boundary bits go (after SetRuns()), or nullptr when they are not kept
   * (see RunLabeling::GetKeptLineBits()). */
  uint64_t *
  GetKeptLineBits(SizeValueType line)
  {
    return m_KeepLineBits ? m_KeptLineBits.data() + line * m_BitsWords : nullptr;
  }
  /** The boundary bits of every line, GetBitsWords() words a line, where they are kept,
   * else nullptr. */
  const uint64_t *
  GetKeptBits() const
  {
    return m_KeepLineBits ? m_KeptLineBits.data() : nullptr;
  }
  /** Words of boundary bits per line. */
  SizeValueType
  GetBitsWords() const
  {
    return m_BitsWords;
  }

  /** Makes a ring of boundary bits for each of \a numberOfWorkUnits work units. */
  void
  MakeLineBits(SizeValueType numberOfWorkUnits);
  /** Links the runs of the lines [begin, end) (a slab of whole planes) with each other;
   * slabs may be linked concurrently. */
  void
  LinkInsideSlab(SizeValueType begin, SizeValueType end);
  /** Links the runs of the first plane of each slab (which begins at a line of
   * \a slabBeginLine, the last entry ending the last slab) with those of the planes before. */
  void
  LinkSeams(const std::vector<SizeValueType> & slabBeginLine);

  /** Bytes held by the boundary bits (with what they keep from an earlier, larger image). */
  SizeValueType
  GetMemoryInBytes() const;

private:
  /** The boundary bits of recent lines: one bit per voxel, set where a run starts (64
   * voxels a word), in a ring of slots indexed by line number. */
  struct LineBits
  {
    std::vector<uint64_t>      Words;
    std::vector<SizeValueType> Lines;
  };
  /** The rings not in use, kept for the next slab and the next image. */
  struct LineBitsPool
  {
    std::mutex                             Mutex;
    std::vector<std::unique_ptr<LineBits>> Free;
  };

  void
  Union(RunIndexType a, RunIndexType b);
  /** Joins, for each set bit of \a starts in a word of two lines' boundary bits \a a and
   * \a b, the runs of the two lines holding that voxel (\a baseA and \a baseB: each line's
   * last run before the word). The pairs are listed first, and those whose runs already
   * share a parent left out without a branch. */
  void
  UnionAt(uint64_t starts, uint64_t a, RunIndexType baseA, uint64_t b, RunIndexType baseB);
  /** Links the runs of two neighbouring lines, \a lineA after \a lineB, from their boundary
   * bits or (\a byBits false) by a merge. */
  void
  LinkLines(SizeValueType lineA, SizeValueType lineB, LineBits & bits, bool byBits);
  /** The same by a merge of the two lines' runs. */
  void
  MergeLines(SizeValueType lineA, SizeValueType lineB);
  /** The same from the lines' boundary bits. */
  void
  LinkLineBits(SizeValueType lineA, const uint64_t * bitsA, SizeValueType lineB, const uint64_t * bitsB);
  /** The same, compiled for a processor with a bit-count instruction (x86 with GCC or
   * Clang, chosen at run time). */
  void
  LinkLineBitsWithPopcount(SizeValueType lineA, const uint64_t * bitsA, SizeValueType lineB, const uint64_t * bitsB);
  /** Whether two neighbouring lines are linked from their boundary bits (else by a merge). */
  bool
  LinksByBits(SizeValueType lineA, SizeValueType lineB) const;
  /** Face connectivity in 3-D: links \a lineA with the line before it along axis 1 (lineA - 1),
   * whose runs it is linked with first, and with the line a plane before it
   * (lineA - \a linesPerRow), both from boundary bits (LinksByBits() for both pairs), in one
   * pass. */
  void
  LinkSquare(SizeValueType lineA, SizeValueType linesPerRow, LineBits & bits);
  /** The same from the boundary bits of the four lines of the square: \a bitsA, of the line
   * before it (\a bitsB), of the line a plane before (\a bitsC) and of the line before that
   * one (\a bitsD). */
  void
  LinkSquareBits(SizeValueType    lineA,
                 SizeValueType    linesPerRow,
                 const uint64_t * bitsA,
                 const uint64_t * bitsB,
                 const uint64_t * bitsC,
                 const uint64_t * bitsD);
  void
  LinkSquareBitsWithPopcount(SizeValueType    lineA,
                             SizeValueType    linesPerRow,
                             const uint64_t * bitsA,
                             const uint64_t * bitsB,
                             const uint64_t * bitsC,
                             const uint64_t * bitsD);
  /** Writes \a line's boundary bits at \a bits from its starts. */
  void
  SetLineBitsFromStarts(SizeValueType line, uint64_t * bits) const;
  /** The boundary bits of \a line, from \a bits or written into it. */
  const uint64_t *
  BitsOf(LineBits & bits, SizeValueType line) const;
  std::unique_ptr<LineBits>
  TakeLineBits();
  /** Bytes held by the rings not in use (all of them between the loops). */
  SizeValueType
  GetLineBitsBytes() const;
  void
  GiveBackLineBits(std::unique_ptr<LineBits> bits);

  /** RunLabeling's run arrays (see SetRuns()): plain pointers, so that the loops reach the
   * runs as directly as through the arrays themselves. */
  const CoordinateType * m_RunStart{ nullptr };
  RunIndexType *         m_RunParent{ nullptr };
  const SizeValueType *  m_LineRunBegin{ nullptr };
  const uint8_t *        m_LineFirstAbove{ nullptr };

  SizeValueType m_LineLength{ 0 };
  SizeValueType m_NumberOfLines{ 0 };
  bool          m_FullyConnected{ false };
  /** Lines per row along axis 1 in 3-D (0 otherwise: no squares), and per plane. */
  SizeValueType m_LinesPerRow{ 0 };
  SizeValueType m_LinesPerPlane{ 0 };
  LineNeighbors m_LineNeighbors;
  /** Words of boundary bits per line, and slots of a ring. */
  SizeValueType m_BitsWords{ 0 };
  SizeValueType m_BitsSlots{ 0 };
  /** The boundary bits of every line, when kept (dense images), instead of rings. */
  bool                          m_KeepLineBits{ false };
  LargeArray<uint64_t>          m_KeptLineBits;
  LineLinking                   m_LineLinking{ LineLinking::Automatic };
  SizeValueType                 m_BitsCacheBytes{ Tuning::BitsCacheBytes };
  std::unique_ptr<LineBitsPool> m_BitsPool{ std::make_unique<LineBitsPool>() };
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
