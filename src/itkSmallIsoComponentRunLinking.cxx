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
#include "itkSmallIsoComponentRunLinking.h"
#include "itkSmallIsoComponentTouchingRuns.h"
#include "itkNumericTraits.h"
#include "itkSmallIsoComponentBitCount.h"
#include "itkSmallIsoComponentUnionFind.h"
#include <algorithm>


namespace itk
{
namespace SmallIsoComponentDetail
{
void
RunLinking::Initialize(const std::vector<SizeValueType> & size, bool fullyConnected)
{
  m_LineLength = size[0];
  m_FullyConnected = fullyConnected;
  m_NumberOfLines = 1;
  for (unsigned int axis = 1; axis < size.size(); ++axis)
  {
    m_NumberOfLines *= size[axis];
  }
  m_LinesPerRow = size.size() == 3 ? size[1] : 0;
  m_LinesPerPlane = m_NumberOfLines / std::max<SizeValueType>(size.back(), 1);
  m_LineNeighbors = LineNeighbors(size, fullyConnected);
  // A ring holds the lines back to a line's farthest earlier neighbour, within its budget;
  // a line that fell out of it has its bits written again. Its slots are a power of two, so
  // that a line's slot is a mask of its number rather than a division.
  m_BitsWords = (size[0] + 63) / 64;
  const SizeValueType affordable = std::max<SizeValueType>(2, m_BitsCacheBytes / (m_BitsWords * sizeof(uint64_t)));
  const SizeValueType wantedSlots = m_LineNeighbors.GetFarthestEarlier() + 1;
  m_BitsSlots = 2;
  while (m_BitsSlots < wantedSlots && 2 * m_BitsSlots <= affordable)
  {
    m_BitsSlots *= 2;
  }
  m_KeepLineBits = false;
}

void
RunLinking::SetRuns(const CoordinateType * start,
                    RunIndexType *         parent,
                    const SizeValueType *  lineBegin,
                    const uint8_t *        lineFirstAbove,
                    SizeValueType          numberOfRuns)
{
  m_RunStart = start;
  m_RunParent = parent;
  m_LineRunBegin = lineBegin;
  m_LineFirstAbove = lineFirstAbove;
  // Dense lines are linked from their bits: keep every line's, written with its starts,
  // rather than writing them again from the starts when they are linked. (The memory is
  // kept for the next image, as the run arrays are.)
  m_KeepLineBits = m_LineLinking == LineLinking::Automatic &&
                   2 * numberOfRuns >= Tuning::BitsRunsPerWord * m_BitsWords * m_NumberOfLines;
  if (m_KeepLineBits)
  {
    m_KeptLineBits.Reserve(m_NumberOfLines * m_BitsWords);
  }
}

void
RunLinking::MakeLineBits(SizeValueType numberOfWorkUnits)
{
  const std::lock_guard<std::mutex> lock(m_BitsPool->Mutex);
  m_BitsPool->Free.resize(std::max<std::size_t>(m_BitsPool->Free.size(), numberOfWorkUnits));
  for (auto & bits : m_BitsPool->Free)
  {
    if (!bits)
    {
      bits = std::make_unique<LineBits>();
    }
    bits->Words.resize(m_BitsSlots * m_BitsWords);
    bits->Lines.resize(m_BitsSlots);
  }
}

void
RunLinking::SetLineBitsFromStarts(SizeValueType line, uint64_t * bits) const
{
  std::fill(bits, bits + m_BitsWords, uint64_t{ 0 });
  const CoordinateType * const start = m_RunStart;
  const SizeValueType          end = m_LineRunBegin[line + 1];
  for (SizeValueType run = m_LineRunBegin[line]; run < end; ++run)
  {
    bits[start[run] / 64] |= uint64_t{ 1 } << (start[run] % 64);
  }
}

SMALLISO_ALWAYS_INLINE void
RunLinking::Union(RunIndexType a, RunIndexType b)
{
  Join(m_RunParent, a, b);
}

SMALLISO_ALWAYS_INLINE void
RunLinking::MergeLines(SizeValueType lineA, SizeValueType lineB)
{
  const auto aFirst = static_cast<RunIndexType>(m_LineRunBegin[lineA]);
  const auto bFirst = static_cast<RunIndexType>(m_LineRunBegin[lineB]);
  // Sides alternate along a line: two runs are on one side when the parities of their places in
  // their lines differ exactly as the sides of the lines' first runs do.
  const RunIndexType differ = (aFirst ^ bFirst ^ (m_LineFirstAbove[lineA] != m_LineFirstAbove[lineB])) & 1;
  JoinTouchingRuns(
    m_RunStart,
    aFirst,
    static_cast<RunIndexType>(m_LineRunBegin[lineA + 1] - 1),
    bFirst,
    static_cast<RunIndexType>(m_LineRunBegin[lineB + 1] - 1),
    static_cast<CoordinateType>(m_LineLength),
    m_FullyConnected,
    [differ](RunIndexType a, RunIndexType b) { return ((a ^ b) & 1) == differ; },
    [this](RunIndexType a, RunIndexType b) { this->Union(a, b); });
}

namespace
{
/** Bit i of the result is the parity of bits 0..i of \a bits. */
inline uint64_t
PrefixParity(uint64_t bits)
{
  bits ^= bits << 1;
  bits ^= bits << 2;
  bits ^= bits << 4;
  bits ^= bits << 8;
  bits ^= bits << 16;
  bits ^= bits << 32;
  return bits;
}

/** The voxels of a word of two lines, whose boundary bits there are \a a and \a b, at which
 * their runs are on opposite sides. \a opposite tells (all ones, or none) whether they are
 * before the word, and is set to whether they are after it. Voxel 0 starts both lines: no
 * change of side there. */
SMALLISO_ALWAYS_INLINE uint64_t
SidesApart(uint64_t a, uint64_t b, SizeValueType word, uint64_t & opposite)
{
  const uint64_t flips = word == 0 ? (a ^ b) & ~uint64_t{ 1 } : a ^ b;
  const uint64_t apart = PrefixParity(flips) ^ opposite;
  opposite = static_cast<uint64_t>(-static_cast<int64_t>(apart >> 63));
  return apart;
}
} // namespace

SMALLISO_ALWAYS_INLINE void
RunLinking::UnionAt(uint64_t starts, uint64_t a, RunIndexType baseA, uint64_t b, RunIndexType baseB)
{
  // The pairs whose runs share a parent are in one set already and are left out before
  // any union, without a branch: the union's own first test, whether the two share a
  // parent, is true for many of the pairs of a random volume and mispredicts.
  // A pair found apart here may be joined by an earlier pair's union meanwhile; the
  // union then ends at its first test.
  const RunIndexType * const parent = m_RunParent;
  RunIndexType               pairA[64];
  RunIndexType               pairB[64];
  unsigned int               pairs = 0;
  for (; starts != 0; starts &= starts - 1)
  {
    const uint64_t     upTo = starts ^ (starts - 1);
    const RunIndexType runA = baseA + static_cast<RunIndexType>(CountBits(a & upTo));
    const RunIndexType runB = baseB + static_cast<RunIndexType>(CountBits(b & upTo));
    pairA[pairs] = runA;
    pairB[pairs] = runB;
    pairs += parent[runA] != parent[runB] ? 1 : 0;
  }
  for (unsigned int pair = 0; pair < pairs; ++pair)
  {
    this->Union(pairA[pair], pairB[pair]);
  }
}

SMALLISO_ALWAYS_INLINE void
RunLinking::LinkLineBits(SizeValueType lineA, const uint64_t * bitsA, SizeValueType lineB, const uint64_t * bitsB)
{
  // A run starts at every set bit of its line; the runs of each line partition the line.
  // Where either line has a boundary, a new pair of overlapping runs starts: the runs
  // holding that voxel, whose indices are the line's first run plus the number of its
  // boundaries before, up to and including the voxel, less one. The pair is on the same
  // side where the sides of the two lines agree; their difference flips at each voxel
  // where exactly one line has a boundary. So every same-side overlapping pair is joined
  // once, without a branch on the runs' ends. With full connectivity, where both lines
  // have a boundary and the runs there are on opposite sides, each run ending there meets
  // the other line's run starting there on its own side.
  // (Run indices wrap around below 0 in unsigned arithmetic and come back with the count.)
  auto     baseA = static_cast<RunIndexType>(m_LineRunBegin[lineA] - 1);
  auto     baseB = static_cast<RunIndexType>(m_LineRunBegin[lineB] - 1);
  uint64_t opposite = m_LineFirstAbove[lineA] != m_LineFirstAbove[lineB] ? ~uint64_t{ 0 } : 0;
  for (SizeValueType word = 0; word < m_BitsWords; ++word)
  {
    const uint64_t a = bitsA[word];
    const uint64_t b = bitsB[word];
    const uint64_t apart = SidesApart(a, b, word, opposite);
    this->UnionAt((a | b) & ~apart, a, baseA, b, baseB);
    if (m_FullyConnected)
    {
      for (uint64_t ties = a & b & apart & (word == 0 ? ~uint64_t{ 1 } : ~uint64_t{ 0 }); ties != 0; ties &= ties - 1)
      {
        const uint64_t upTo = ties ^ (ties - 1);
        const auto     runA = baseA + static_cast<RunIndexType>(CountBits(a & upTo));
        const auto     runB = baseB + static_cast<RunIndexType>(CountBits(b & upTo));
        this->Union(runA - 1, runB);
        this->Union(runA, runB - 1);
      }
    }
    baseA += static_cast<RunIndexType>(CountBits(a));
    baseB += static_cast<RunIndexType>(CountBits(b));
  }
}

#if defined(SMALLISO_POPCOUNT_DISPATCH)
// The same loop, compiled for processors that count bits in one instruction: without it,
// each count is a library call, and the loop takes more than twice as long.
__attribute__((target("popcnt"))) void
RunLinking::LinkLineBitsWithPopcount(SizeValueType    lineA,
                                     const uint64_t * bitsA,
                                     SizeValueType    lineB,
                                     const uint64_t * bitsB)
{
  this->LinkLineBits(lineA, bitsA, lineB, bitsB);
}
#endif

SMALLISO_ALWAYS_INLINE void
RunLinking::LinkSquareBits(SizeValueType    lineA,
                           SizeValueType    linesPerRow,
                           const uint64_t * bitsA,
                           const uint64_t * bitsB,
                           const uint64_t * bitsC,
                           const uint64_t * bitsD)
{
  // As LinkLineBits(), for lineA with lineB (the line before it along axis 1, the first
  // pair, so its runs start as sets of their own) and with lineC (a plane before), in one
  // pass. A pair of A and C needs no union where, at a voxel they share, the voxels of B and
  // D there are on their side too: A's run is joined to B's (this pass), B's to D's (when B
  // was linked with D) and D's to C's (when C was linked with D, its first pair), or, where
  // a pair of B and D was left out so, to runs that are joined by the same argument on
  // earlier lines. On a random volume many of the pairs of A and C are left out so, by the
  // first three voxels of their overlap. Pairs of A and B are never left out.
  const SizeValueType  lineB = lineA - 1;
  const SizeValueType  lineC = lineA - linesPerRow;
  const SizeValueType  lineD = lineC - 1;
  RunIndexType * const parent = m_RunParent;
  auto                 baseA = static_cast<RunIndexType>(m_LineRunBegin[lineA] - 1);
  auto                 baseB = static_cast<RunIndexType>(m_LineRunBegin[lineB] - 1);
  auto                 baseC = static_cast<RunIndexType>(m_LineRunBegin[lineC] - 1);
  const bool           firstAbove = m_LineFirstAbove[lineA] != 0;
  uint64_t             oppositeB = firstAbove != (m_LineFirstAbove[lineB] != 0) ? ~uint64_t{ 0 } : 0;
  uint64_t             oppositeC = firstAbove != (m_LineFirstAbove[lineC] != 0) ? ~uint64_t{ 0 } : 0;
  uint64_t             oppositeD = firstAbove != (m_LineFirstAbove[lineD] != 0) ? ~uint64_t{ 0 } : 0;
  for (SizeValueType word = 0; word < m_BitsWords; ++word)
  {
    const uint64_t a = bitsA[word];
    const uint64_t b = bitsB[word];
    const uint64_t c = bitsC[word];
    const uint64_t apartB = SidesApart(a, b, word, oppositeB);
    const uint64_t apartC = SidesApart(a, c, word, oppositeC);
    const uint64_t apartD = SidesApart(a, bitsD[word], word, oppositeD);

    const uint64_t joinedB = (a | b) & ~apartB;
    for (uint64_t starts = a & joinedB; starts != 0; starts &= starts - 1)
    {
      const uint64_t upTo = starts ^ (starts - 1);
      parent[baseA + static_cast<RunIndexType>(CountBits(a & upTo))] =
        parent[baseB + static_cast<RunIndexType>(CountBits(b & upTo))];
    }
    this->UnionAt(joinedB & ~a, a, baseA, b, baseB);

    // The voxels where B, C and D are all on A's side; an overlap of A and C starting at a
    // voxel is left out if one of its first three voxels is such a voxel (a voxel past the
    // word's end counts as none).
    const uint64_t boundaries = a | c;
    const uint64_t square = ~(apartB | apartC | apartD);
    const uint64_t on1 = ~(boundaries >> 1);
    const uint64_t joinedAlready = square | ((square >> 1) & on1) | ((square >> 2) & on1 & ~(boundaries >> 2));
    this->UnionAt(boundaries & ~apartC & ~joinedAlready, a, baseA, c, baseC);
    baseA += static_cast<RunIndexType>(CountBits(a));
    baseB += static_cast<RunIndexType>(CountBits(b));
    baseC += static_cast<RunIndexType>(CountBits(c));
  }
}

#if defined(SMALLISO_POPCOUNT_DISPATCH)
__attribute__((target("popcnt"))) void
RunLinking::LinkSquareBitsWithPopcount(SizeValueType    lineA,
                                       SizeValueType    linesPerRow,
                                       const uint64_t * bitsA,
                                       const uint64_t * bitsB,
                                       const uint64_t * bitsC,
                                       const uint64_t * bitsD)
{
  this->LinkSquareBits(lineA, linesPerRow, bitsA, bitsB, bitsC, bitsD);
}
#endif

void
RunLinking::LinkSquare(SizeValueType lineA, SizeValueType linesPerRow, LineBits & bits)
{
  const SizeValueType lineB = lineA - 1;
  const SizeValueType lineC = lineA - linesPerRow;
  // The ring holds more lines than the square spans: the four lines' bits stay in it.
  const uint64_t * const bitsD = this->BitsOf(bits, lineC - 1);
  const uint64_t * const bitsC = this->BitsOf(bits, lineC);
  const uint64_t * const bitsB = this->BitsOf(bits, lineB);
  const uint64_t * const bitsA = this->BitsOf(bits, lineA);
#if defined(SMALLISO_POPCOUNT_DISPATCH)
  if (HasPopcount())
  {
    this->LinkSquareBitsWithPopcount(lineA, linesPerRow, bitsA, bitsB, bitsC, bitsD);
    return;
  }
#endif
  this->LinkSquareBits(lineA, linesPerRow, bitsA, bitsB, bitsC, bitsD);
}

const uint64_t *
RunLinking::BitsOf(LineBits & bits, SizeValueType line) const
{
  if (m_KeepLineBits)
  {
    return m_KeptLineBits.data() + line * m_BitsWords;
  }
  const SizeValueType slot = line & (m_BitsSlots - 1);
  uint64_t * const    words = bits.Words.data() + slot * m_BitsWords;
  if (bits.Lines[slot] != line)
  {
    bits.Lines[slot] = line;
    this->SetLineBitsFromStarts(line, words);
  }
  return words;
}

inline bool
RunLinking::LinksByBits(SizeValueType lineA, SizeValueType lineB) const
{
  // The merge branches once per run, unpredictably where runs are short; the bits cost a
  // few operations per 64 voxels and one union per joined pair. Two lines in the same slot
  // of the ring are merged.
  const SizeValueType runs =
    m_LineRunBegin[lineA + 1] - m_LineRunBegin[lineA] + m_LineRunBegin[lineB + 1] - m_LineRunBegin[lineB];
  const bool merge = m_LineLinking == LineLinking::Automatic ? runs < Tuning::BitsRunsPerWord * m_BitsWords || runs <= 2
                                                             : m_LineLinking == LineLinking::Merge;
  // (lineA comes after lineB: they share a slot only if they are a multiple of the ring
  // apart, never when the ring holds every line a line reaches back to.)
  const SizeValueType apart = lineA - lineB;
  return !merge && (m_KeepLineBits || apart < m_BitsSlots || (apart & (m_BitsSlots - 1)) != 0);
}

inline void
RunLinking::LinkLines(SizeValueType lineA, SizeValueType lineB, LineBits & bits, bool byBits)
{
  if (!byBits)
  {
    this->MergeLines(lineA, lineB);
    return;
  }
  const uint64_t * const bitsA = this->BitsOf(bits, lineA);
  const uint64_t * const bitsB = this->BitsOf(bits, lineB);
#if defined(SMALLISO_POPCOUNT_DISPATCH)
  if (HasPopcount())
  {
    this->LinkLineBitsWithPopcount(lineA, bitsA, lineB, bitsB);
    return;
  }
#endif
  this->LinkLineBits(lineA, bitsA, lineB, bitsB);
}

auto
RunLinking::TakeLineBits() -> std::unique_ptr<LineBits>
{
  std::unique_ptr<LineBits> bits;
  {
    const std::lock_guard<std::mutex> lock(m_BitsPool->Mutex);
    if (!m_BitsPool->Free.empty())
    {
      bits = std::move(m_BitsPool->Free.back());
      m_BitsPool->Free.pop_back();
    }
  }
  if (!bits)
  {
    bits = std::make_unique<LineBits>();
  }
  bits->Words.resize(m_BitsSlots * m_BitsWords);
  bits->Lines.assign(m_BitsSlots, NumericTraits<SizeValueType>::max());
  return bits;
}

void
RunLinking::GiveBackLineBits(std::unique_ptr<LineBits> bits)
{
  const std::lock_guard<std::mutex> lock(m_BitsPool->Mutex);
  m_BitsPool->Free.push_back(std::move(bits));
}

void
RunLinking::LinkInsideSlab(SizeValueType begin, SizeValueType end)
{
  auto bits = this->TakeLineBits();
  auto position = m_LineNeighbors.At(begin);
  // Face connectivity in 3-D, with a ring that holds a plane and a line more: the lines
  // past the slab's first plane and the first line of their plane are linked by squares.
  // (Slabs begin with a plane.)
  const SizeValueType linesPerRow = m_LinesPerRow;
  const bool    squares = linesPerRow > 0 && !m_FullyConnected && (m_KeepLineBits || m_BitsSlots > linesPerRow + 1);
  SizeValueType row = 0; // the line's coordinate along axis 1
  for (SizeValueType line = begin; line < end;
       ++line, m_LineNeighbors.Next(position), row = row + 1 == linesPerRow ? 0 : row + 1)
  {
    if (squares && row > 0 && line >= begin + linesPerRow)
    {
      // The two earlier lines: by a square where both pairs are linked from their bits.
      const SizeValueType before = line - 1;
      const SizeValueType planeBefore = line - linesPerRow;
      const bool          bitsBefore = this->LinksByBits(line, before);
      const bool          bitsPlaneBefore = this->LinksByBits(line, planeBefore);
      if (bitsBefore && bitsPlaneBefore)
      {
        this->LinkSquare(line, linesPerRow, *bits);
      }
      else
      {
        this->LinkLines(line, before, *bits, bitsBefore);
        this->LinkLines(line, planeBefore, *bits, bitsPlaneBefore);
      }
      continue;
    }
    // The earlier lines before the slab are its seam, linked by LinkSeams().
    m_LineNeighbors.ForEachEarlier(position, [&](SizeValueType earlier) {
      if (earlier >= begin)
      {
        this->LinkLines(line, earlier, *bits, this->LinksByBits(line, earlier));
      }
    });
  }
  this->GiveBackLineBits(std::move(bits));
}

void
RunLinking::LinkSeams(const std::vector<SizeValueType> & slabBeginLine)
{
  // LinkInsideSlab() linked the runs inside each slab. The seams: the first plane of each
  // slab with the planes before it.
  const SizeValueType linesPerPlane = m_LinesPerPlane;
  auto                bits = this->TakeLineBits();
  for (SizeValueType slab = 1; slab + 1 < slabBeginLine.size(); ++slab)
  {
    const SizeValueType begin = slabBeginLine[slab];
    auto                position = m_LineNeighbors.At(begin);
    for (SizeValueType line = begin; line < begin + linesPerPlane; ++line, m_LineNeighbors.Next(position))
    {
      m_LineNeighbors.ForEachEarlier(position, [&](SizeValueType earlier) {
        if (earlier < begin)
        {
          this->LinkLines(line, earlier, *bits, this->LinksByBits(line, earlier));
        }
      });
    }
  }
  this->GiveBackLineBits(std::move(bits));
}

SizeValueType
RunLinking::GetMemoryInBytes() const
{
  return m_KeptLineBits.capacity() * sizeof(uint64_t) + this->GetLineBitsBytes();
}

SizeValueType
RunLinking::GetLineBitsBytes() const
{
  const std::lock_guard<std::mutex> lock(m_BitsPool->Mutex);
  SizeValueType                     bytes = 0;
  for (const auto & bits : m_BitsPool->Free)
  {
    bytes += bits->Words.capacity() * sizeof(uint64_t) + bits->Lines.capacity() * sizeof(SizeValueType);
  }
  return bytes;
}
} // namespace SmallIsoComponentDetail
} // end namespace itk
