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
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentTouchingRuns.h"
#include "itkMacro.h"
#include "itkNumericTraits.h"
#include "itkSmallIsoComponentBitCount.h"
#include "itkSmallIsoComponentPrefetch.h"
#include "itkSmallIsoComponentUnionFind.h"
#include <algorithm>
#include <atomic>
#include <functional>
#include <memory>
#include <numeric>
#include <thread>
#include <type_traits>


namespace itk
{
namespace SmallIsoComponentDetail
{
void
RunLabeling::Initialize(const std::vector<SizeValueType> & size, bool fullyConnected, unsigned int maximumNumberOfSlabs)
{
  if (size.empty() || size[0] == 0 || size[0] > NumericTraits<CoordinateType>::max())
  {
    itkGenericExceptionMacro("SmallIsoComponent: lines along axis 0 must have between 1 and "
                             << NumericTraits<CoordinateType>::max() << " voxels");
  }
  m_Size = size;
  m_FullyConnected = fullyConnected;
  const auto dimension = static_cast<unsigned int>(size.size());
  m_NumberOfLines = 1;
  for (unsigned int axis = 1; axis < dimension; ++axis)
  {
    m_NumberOfLines *= size[axis];
  }

  // Slabs of whole planes along the last axis (whole lines in 1-D and 2-D).
  const SizeValueType planes = dimension > 1 ? size[dimension - 1] : 1;
  const SizeValueType linesPerPlane = m_NumberOfLines / std::max<SizeValueType>(planes, 1);
  const SizeValueType wanted =
    maximumNumberOfSlabs > 1 ? SizeValueType{ maximumNumberOfSlabs } * Tuning::SlabsPerWorkUnit : SizeValueType{ 1 };
  const SizeValueType slabs = std::max<SizeValueType>(1, std::min<SizeValueType>(wanted, planes));
  m_SlabBeginLine.resize(slabs + 1);
  for (SizeValueType slab = 0; slab <= slabs; ++slab)
  {
    m_SlabBeginLine[slab] = (slab * planes / slabs) * linesPerPlane;
  }

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

  // The arrays keep their memory: an image like the last one takes none afresh.
  m_NumberOfRuns = 0;
  m_KeepLineBits = false;
  m_LineRunBegin.assign(m_NumberOfLines + 1, 0);
  m_LineFirstAbove.assign(m_NumberOfLines, 0);
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  m_CandidateRuns.clear();
  m_PeakMemoryInBytes = 0;
}

void
RunLabeling::ReleaseMemory()
{
  const LineLinking   linking = m_LineLinking;
  const SizeValueType bitsCacheBytes = m_BitsCacheBytes;
  const SizeValueType minimumRunsToShareNumbering = m_MinimumRunsToShareNumbering;
  const SizeValueType linesPerClaim = m_LinesPerClaim;
  *this = RunLabeling();
  this->SetLineLinking(linking, bitsCacheBytes);
  this->SetMinimumRunsToShareNumbering(minimumRunsToShareNumbering);
  this->SetLinesPerClaim(linesPerClaim);
}

void
RunLabeling::ReserveRuns()
{
  // SetLineRuns() stored counts one place to the right; make them offsets.
  std::partial_sum(m_LineRunBegin.begin(), m_LineRunBegin.end(), m_LineRunBegin.begin());
  const SizeValueType numberOfRuns = m_LineRunBegin.back();
  if (numberOfRuns >= NumericTraits<RunIndexType>::max())
  {
    itkGenericExceptionMacro("SmallIsoComponent: the image has "
                             << numberOfRuns << " scanline runs; the filter holds at most "
                             << NumericTraits<RunIndexType>::max() - 1
                             << " at once: filter it in slabs with SmallIsoComponentStreamingImageFilter "
                                "(SmallIsoComponentFilter --memory-limit), which labels fewer at a time");
  }
  m_NumberOfRuns = numberOfRuns;
  m_RunStart.Reserve(numberOfRuns);
  m_RunLabel.Reserve(numberOfRuns);
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
RunLabeling::SetLineBitsFromStarts(SizeValueType line, uint64_t * bits) const
{
  std::fill(bits, bits + m_BitsWords, uint64_t{ 0 });
  const CoordinateType * const start = m_RunStart.data();
  const SizeValueType          end = m_LineRunBegin[line + 1];
  for (SizeValueType run = m_LineRunBegin[line]; run < end; ++run)
  {
    bits[start[run] / 64] |= uint64_t{ 1 } << (start[run] % 64);
  }
}

void
RunLabeling::AssembleRuns(WorkTeam & team)
{
  // One ring per work unit, made before the loop so that the memory held does not depend
  // on how the slabs met the work units.
  {
    const std::lock_guard<std::mutex> lock(m_BitsPool->Mutex);
    m_BitsPool->Free.resize(std::max<std::size_t>(m_BitsPool->Free.size(), team.GetNumberOfWorkUnits()));
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
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
  team.ForEach(this->GetNumberOfSlabs(), [this](SizeValueType slab) {
    const SizeValueType first = m_LineRunBegin[m_SlabBeginLine[slab]];
    const SizeValueType last = m_LineRunBegin[m_SlabBeginLine[slab + 1]];
    std::iota(m_RunLabel.data() + first, m_RunLabel.data() + last, static_cast<RunIndexType>(first));
    // The slab's runs are in cache now: link them (only runs of this slab are touched).
    this->LinkInsideSlab(slab);
  });
}

SMALLISO_ALWAYS_INLINE void
RunLabeling::Union(RunIndexType a, RunIndexType b)
{
  Join(m_RunLabel.data(), a, b);
}

SMALLISO_ALWAYS_INLINE void
RunLabeling::MergeLines(SizeValueType lineA, SizeValueType lineB)
{
  const auto aFirst = static_cast<RunIndexType>(m_LineRunBegin[lineA]);
  const auto bFirst = static_cast<RunIndexType>(m_LineRunBegin[lineB]);
  // Sides alternate along a line: two runs are on one side when the parities of their places in
  // their lines differ exactly as the sides of the lines' first runs do.
  const RunIndexType differ = (aFirst ^ bFirst ^ (m_LineFirstAbove[lineA] != m_LineFirstAbove[lineB])) & 1;
  JoinTouchingRuns(
    m_RunStart.data(),
    aFirst,
    static_cast<RunIndexType>(m_LineRunBegin[lineA + 1] - 1),
    bFirst,
    static_cast<RunIndexType>(m_LineRunBegin[lineB + 1] - 1),
    static_cast<CoordinateType>(m_Size[0]),
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
RunLabeling::UnionAt(uint64_t starts, uint64_t a, RunIndexType baseA, uint64_t b, RunIndexType baseB)
{
  // The pairs whose runs share a parent are in one set already and are left out before
  // any union, without a branch: the union's own first test, whether the two share a
  // parent, is true for many of the pairs of a random volume and mispredicts.
  // A pair found apart here may be joined by an earlier pair's union meanwhile; the
  // union then ends at its first test.
  const RunIndexType * const parent = m_RunLabel.data();
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
RunLabeling::LinkLineBits(SizeValueType lineA, const uint64_t * bitsA, SizeValueType lineB, const uint64_t * bitsB)
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
RunLabeling::LinkLineBitsWithPopcount(SizeValueType    lineA,
                                      const uint64_t * bitsA,
                                      SizeValueType    lineB,
                                      const uint64_t * bitsB)
{
  this->LinkLineBits(lineA, bitsA, lineB, bitsB);
}
#endif

SMALLISO_ALWAYS_INLINE void
RunLabeling::LinkSquareBits(SizeValueType    lineA,
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
  RunIndexType * const parent = m_RunLabel.data();
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
RunLabeling::LinkSquareBitsWithPopcount(SizeValueType    lineA,
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
RunLabeling::LinkSquare(SizeValueType lineA, SizeValueType linesPerRow, LineBits & bits)
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
RunLabeling::BitsOf(LineBits & bits, SizeValueType line) const
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
RunLabeling::LinksByBits(SizeValueType lineA, SizeValueType lineB) const
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
RunLabeling::LinkLines(SizeValueType lineA, SizeValueType lineB, LineBits & bits, bool byBits)
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
RunLabeling::TakeLineBits() -> std::unique_ptr<LineBits>
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
RunLabeling::GiveBackLineBits(std::unique_ptr<LineBits> bits)
{
  const std::lock_guard<std::mutex> lock(m_BitsPool->Mutex);
  m_BitsPool->Free.push_back(std::move(bits));
}

void
RunLabeling::LinkInsideSlab(SizeValueType slab)
{
  const SizeValueType begin = m_SlabBeginLine[slab];
  const SizeValueType end = m_SlabBeginLine[slab + 1];
  auto                bits = this->TakeLineBits();
  auto                position = m_LineNeighbors.At(begin);
  // Face connectivity in 3-D, with a ring that holds a plane and a line more: the lines
  // past the slab's first plane and the first line of their plane are linked by squares.
  // (Slabs begin with a plane.)
  const SizeValueType linesPerRow = m_Size.size() == 3 ? m_Size[1] : 0;
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
    // The earlier lines before the slab are its seam, linked by LinkRuns().
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
RunLabeling::LinkRuns()
{
  // AssembleRuns() linked the runs inside each slab. The seams: the first plane of each
  // slab with the planes before it.
  const SizeValueType linesPerPlane = m_NumberOfLines / m_Size.back();
  auto                bits = this->TakeLineBits();
  for (SizeValueType slab = 1; slab < this->GetNumberOfSlabs(); ++slab)
  {
    const SizeValueType begin = m_SlabBeginLine[slab];
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

namespace
{
/** Resizes \a sizes to \a count entries (new ones 0), its capacity doubled as often as
 * needed: the capacity is then that which adding the entries one by one gives, whatever
 * steps it was resized in (the shared numbering's depend on timing). */
void
GrowSizes(std::vector<SizeValueType> & sizes, SizeValueType count)
{
  if (count > sizes.capacity())
  {
    SizeValueType capacity = std::max<SizeValueType>(sizes.capacity(), 1);
    while (capacity < count)
    {
      capacity *= 2;
    }
    sizes.reserve(capacity);
  }
  sizes.resize(count, 0);
}

/** Candidate runs gathered in a small buffer, appended to \a runs when it is full and at the
 * end: a run is one store, and the vector is reached once per Tuning::CandidateBufferRuns runs. TEntry is
 * RunLabeling::CandidateRun (a run and its component) or RunLabeling::LineRun (a run and its
 * line). */
template <typename TEntry>
class CandidateBuffer
{
public:
  explicit CandidateBuffer(std::vector<TEntry> & runs)
    : m_Runs(runs)
  {}
  void
  Add(SizeValueType run, SizeValueType line, SizeValueType component)
  {
    if constexpr (std::is_same<TEntry, RunLabeling::LineRun>::value)
    {
      m_Buffer[m_Count++] = { static_cast<RunLabeling::RunIndexType>(run),
                              static_cast<RunLabeling::RunIndexType>(line) };
    }
    else
    {
      m_Buffer[m_Count++] = { static_cast<RunLabeling::RunIndexType>(run),
                              static_cast<RunLabeling::ComponentIndexType>(component) };
    }
    if (m_Count == Tuning::CandidateBufferRuns)
    {
      this->Flush();
    }
  }
  void
  Flush()
  {
    m_Runs.insert(m_Runs.end(), m_Buffer, m_Buffer + m_Count);
    m_Count = 0;
  }

private:
  std::vector<TEntry> & m_Runs;
  TEntry                m_Buffer[Tuning::CandidateBufferRuns];
  SizeValueType         m_Count{ 0 };
};

/** Adds the runs of \a line to the sizes of their components (numbered already), and keeps
 * as candidates those whose component has at most candidateSize[its side] voxels so far. */
template <typename TSize, typename TEntry>
SMALLISO_ALWAYS_INLINE void
SumLine(const RunLabeling::RunTable & table,
        SizeValueType                 line,
        TSize *                       sizes,
        const SizeValueType           candidateSize[2],
        CandidateBuffer<TEntry> &     candidates)
{
  const SizeValueType end = table.LineBegin[line + 1];
  bool                above = table.LineFirstAbove[line] != 0;
  for (SizeValueType run = table.LineBegin[line]; run < end; ++run, above = !above)
  {
    const SizeValueType component = table.Component[run];
    const SizeValueType size =
      sizes[component] + (run + 1 < end ? SizeValueType{ table.Start[run + 1] } : table.LineLength) - table.Start[run];
    sizes[component] = static_cast<TSize>(size);
    if (size <= candidateSize[above])
    {
      candidates.Add(run, line, component);
    }
  }
}
} // namespace

void
RunLabeling::LabelComponents()
{
  // Every run has at least one voxel: no run is a candidate.
  this->LabelComponents(0);
}

void
RunLabeling::LabelComponents(SizeValueType aboveCandidateSize, SizeValueType belowCandidateSize)
{
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  m_CandidateRuns.clear();
  RunIndexType * const          label = m_RunLabel.data();
  const CoordinateType * const  start = m_RunStart.data();
  const SizeValueType           length = m_Size[0];
  CandidateBuffer<CandidateRun> candidates(m_CandidateRuns);
  const SizeValueType           candidateSize[2] = { belowCandidateSize, aboveCandidateSize };
  // The sizes are reached through a local pointer, renewed when a component is added, so
  // that the loop does not read the vector's again for every run.
  SizeValueType * sizes = m_ComponentSize.data();
  for (SizeValueType line = 0; line < m_NumberOfLines; ++line)
  {
    const SizeValueType end = m_LineRunBegin[line + 1];
    bool                above = m_LineFirstAbove[line] != 0;
    for (SizeValueType run = m_LineRunBegin[line]; run < end; ++run, above = !above)
    {
      // Parents never point to a later run, so the parent's entry already holds its
      // component number.
      const RunIndexType parent = label[run];
      RunIndexType       component;
      if (parent == run)
      {
        component = static_cast<ComponentIndexType>(m_ComponentSize.size());
        m_ComponentSize.push_back(0);
        m_ComponentAbove.push_back(above);
        sizes = m_ComponentSize.data();
      }
      else
      {
        component = label[parent];
      }
      label[run] = component;
      const SizeValueType size =
        sizes[component] + (run + 1 < end ? SizeValueType{ start[run + 1] } : length) - start[run];
      sizes[component] = size;
      // A component's size only grows, so every run of a component that ends at most
      // candidateSize voxels large is kept, in a small buffer emptied when full. A branch,
      // though mispredicted where a speck begins or ends, is faster than storing every run
      // into the buffer without one: few runs are candidates.
      if (size <= candidateSize[above])
      {
        candidates.Add(run, line, component);
      }
    }
  }
  candidates.Flush();
}

void
RunLabeling::LabelComponents(WorkTeam &                        team,
                             SizeValueType                     aboveCandidateSize,
                             SizeValueType                     belowCandidateSize,
                             const std::function<bool()> &     otherWork,
                             bool                              share,
                             std::vector<ComponentIndexType> * partialSizes,
                             std::vector<LineRun> *            partialCandidates)
{
  const auto doOtherWork = [&otherWork] {
    if (otherWork)
    {
      while (otherWork())
      {}
    }
  };
  if (team.GetNumberOfWorkUnits() < 2 || !share || m_NumberOfRuns < m_MinimumRunsToShareNumbering)
  {
    // Serial, the other work beside it (with one work unit, no other work: ForEach() then
    // runs item 0 alone).
    team.ForEach(team.GetNumberOfWorkUnits(), [&](SizeValueType item) {
      if (item == 0)
      {
        this->LabelComponents(aboveCandidateSize, belowCandidateSize);
      }
      else
      {
        doOtherWork();
      }
    });
    return;
  }
  m_ComponentSize.clear();
  m_ComponentAbove.clear();
  m_CandidateRuns.clear();
  const SizeValueType candidateSize[2] = { belowCandidateSize, aboveCandidateSize };
  Progress            progress;
  // The second stage takes every claim unless the first helps it.
  const SizeValueType   claims = (m_NumberOfLines + m_LinesPerClaim - 1) / m_LinesPerClaim;
  std::atomic<uint64_t> claimed{ uint64_t{ claims } << 32 };
  bool                  helped = false;
  // The items are handed out in order: whoever takes the second finds the first under way
  // (or done), and the first never waits.
  team.ForEach(team.GetNumberOfWorkUnits(), [&](SizeValueType stage) {
    if (stage == 0)
    {
      // The shorter stage: the other work after it, then the help.
      this->NumberRuns(progress);
      doOtherWork();
      if (partialSizes != nullptr && partialCandidates != nullptr)
      {
        helped = this->SumComponentsFromTheEnd(claimed, candidateSize, *partialSizes, *partialCandidates);
      }
    }
    else if (stage == 1)
    {
      this->SumComponents(progress, candidateSize, otherWork, claimed);
    }
    else
    {
      doOtherWork();
    }
  });
  if (helped)
  {
    // The components first met in the helper's lines have no size yet.
    const SizeValueType components = m_ComponentAbove.size();
    GrowSizes(m_ComponentSize, components);
    const ComponentIndexType * const partial = partialSizes->data();
    SizeValueType * const            sizes = m_ComponentSize.data();
    for (SizeValueType component = 0; component < components; ++component)
    {
      sizes[component] += partial[component];
    }
    // The helper's claims, taken from the end, are appended in line order, and only the
    // runs of components of at most the candidate size: its partial sizes kept others too,
    // and the candidates are never more than the serial numbering's (the arrays sized by
    // them keep the size of the first update).
    const RunIndexType * const    label = m_RunLabel.data();
    CandidateBuffer<CandidateRun> candidates(m_CandidateRuns);
    for (SizeValueType claim = m_ClaimBegin.size() - 1; claim > 0; --claim)
    {
      for (SizeValueType i = m_ClaimBegin[claim - 1]; i < m_ClaimBegin[claim]; ++i)
      {
        const LineRun      candidate = (*partialCandidates)[i];
        const RunIndexType component = label[candidate.Run];
        if (sizes[component] <= candidateSize[m_ComponentAbove[component]])
        {
          candidates.Add(candidate.Run, candidate.Line, component);
        }
      }
    }
    candidates.Flush();
    partialCandidates->clear();
  }
  m_PeakMemoryInBytes = std::max(m_PeakMemoryInBytes, this->GetMemoryInBytes());
}

void
RunLabeling::NumberRuns(Progress & progress)
{
  RunIndexType * const label = m_RunLabel.data();
  ComponentIndexType   components = 0;
  for (SizeValueType line = 0; line < m_NumberOfLines; ++line)
  {
    const SizeValueType end = m_LineRunBegin[line + 1];
    bool                above = m_LineFirstAbove[line] != 0;
    for (SizeValueType run = m_LineRunBegin[line]; run < end; ++run, above = !above)
    {
      // Parents never point to a later run, so the parent's entry already holds its
      // component number.
      const RunIndexType parent = label[run];
      RunIndexType       component;
      if (parent == run)
      {
        component = components++;
        m_ComponentAbove.push_back(above);
      }
      else
      {
        component = label[parent];
      }
      label[run] = component;
    }
    if ((line + 1) % Tuning::NumberingLinesPerStep == 0)
    {
      progress.Components.store(components, std::memory_order_relaxed);
      progress.Lines.store(line + 1, std::memory_order_release);
    }
  }
  progress.Components.store(components, std::memory_order_relaxed);
  progress.Lines.store(m_NumberOfLines, std::memory_order_release);
}

void
RunLabeling::SumComponents(const Progress &              progress,
                           const SizeValueType           candidateSize[2],
                           const std::function<bool()> & otherWork,
                           std::atomic<uint64_t> &       claims)
{
  const RunTable                table = this->GetRunTable();
  CandidateBuffer<CandidateRun> candidates(m_CandidateRuns);
  SizeValueType *               sizes = m_ComponentSize.data();
  SizeValueType                 ready = 0;
  uint64_t                      claimed = claims.load(std::memory_order_relaxed);
  while (true)
  {
    // The next claim from the front, unless the first stage has taken it from the end. The
    // claims only share the lines out: the results are joined after the loop.
    const uint64_t front = claimed & 0xffffffffU;
    if (front >= (claimed >> 32))
    {
      break;
    }
    if (!claims.compare_exchange_weak(claimed, claimed + 1, std::memory_order_relaxed))
    {
      continue;
    }
    claimed = claimed + 1;
    const SizeValueType lastLine = std::min(m_NumberOfLines, (front + 1) * m_LinesPerClaim);
    for (SizeValueType line = front * m_LinesPerClaim; line < lastLine; ++line)
    {
      if (line >= ready)
      {
        // The sizes of the components numbered so far are made room for at once, rather
        // than one by one behind a branch on every run.
        while ((ready = progress.Lines.load(std::memory_order_acquire)) <= line)
        {
          if (!otherWork || !otherWork())
          {
            std::this_thread::yield();
          }
        }
        GrowSizes(m_ComponentSize, progress.Components.load(std::memory_order_relaxed));
        sizes = m_ComponentSize.data();
      }
      SumLine(table, line, sizes, candidateSize, candidates);
    }
  }
  candidates.Flush();
}

bool
RunLabeling::SumComponentsFromTheEnd(std::atomic<uint64_t> &           claims,
                                     const SizeValueType               candidateSize[2],
                                     std::vector<ComponentIndexType> & partialSizes,
                                     std::vector<LineRun> &            candidateRuns)
{
  const RunTable      table = this->GetRunTable();
  const SizeValueType length = m_Size[0];
  // The partial sizes have 32 bits: the help ends before its lines could hold more voxels.
  // It ends too before the candidates could fill the capacity the scratch has already
  // (every run of a claim could be one): the help takes no memory of its own (and none
  // the first time).
  const SizeValueType voxelsPerClaim = m_LinesPerClaim * length;
  const SizeValueType room = candidateRuns.capacity();
  SizeValueType       voxels = 0;
  uint64_t            claimed = claims.load(std::memory_order_relaxed);
  bool                first = true;
  while (voxels + voxelsPerClaim <= NumericTraits<ComponentIndexType>::max())
  {
    const uint64_t back = claimed >> 32;
    if ((claimed & 0xffffffffU) >= back)
    {
      break;
    }
    const SizeValueType claim = back - 1;
    const SizeValueType firstLine = claim * m_LinesPerClaim;
    const SizeValueType lastLine = std::min(m_NumberOfLines, firstLine + m_LinesPerClaim);
    const SizeValueType claimRuns = m_LineRunBegin[lastLine] - m_LineRunBegin[firstLine];
    if (candidateRuns.size() + claimRuns > room)
    {
      break;
    }
    if (!claims.compare_exchange_weak(claimed, claimed - (uint64_t{ 1 } << 32), std::memory_order_relaxed))
    {
      continue;
    }
    claimed = claimed - (uint64_t{ 1 } << 32);
    if (first)
    {
      partialSizes.assign(m_ComponentAbove.size(), 0);
      candidateRuns.clear();
      m_ClaimBegin.assign(1, 0);
      first = false;
    }
    ComponentIndexType * const sizes = partialSizes.data();
    CandidateBuffer<LineRun>   candidates(candidateRuns);
    for (SizeValueType line = firstLine; line < lastLine; ++line)
    {
      // A component with at most candidateSize voxels has at most as many here: its runs
      // are all kept.
      SumLine(table, line, sizes, candidateSize, candidates);
    }
    candidates.Flush();
    voxels += voxelsPerClaim;
    m_ClaimBegin.push_back(candidateRuns.size());
  }
  return !first;
}

auto
RunLabeling::CollectCandidateRuns(const std::vector<uint8_t> & selected) const -> std::vector<LineRun>
{
  std::vector<LineRun> runs;
  this->CollectCandidateRuns(selected, runs);
  return runs;
}

void
RunLabeling::CollectCandidateRuns(const std::vector<uint8_t> & selected, std::vector<LineRun> & runs) const
{
  runs.clear();
  const SizeValueType        candidates = m_CandidateRuns.size();
  const CandidateRun * const candidate = m_CandidateRuns.data();
  if (candidates == 0)
  {
    return;
  }
  // The candidates are in run order: the line of each selected one is found by moving a
  // cursor forward from the first candidate's.
  const SizeValueType * const lineBegin = m_LineRunBegin.data();
  SizeValueType               line = this->LineOfRun(candidate[0].Run);
  for (SizeValueType i = 0; i < candidates; ++i)
  {
    if (selected[candidate[i].Component])
    {
      while (lineBegin[line + 1] <= candidate[i].Run)
      {
        ++line;
      }
      runs.push_back({ candidate[i].Run, static_cast<RunIndexType>(line) });
    }
  }
}

void
RunLabeling::CollectCandidateRuns(const std::vector<uint8_t> & selected,
                                  WorkTeam &                   team,
                                  std::vector<uint8_t> &       marked,
                                  std::vector<LineRun> &       runs) const
{
  const SizeValueType candidates = m_CandidateRuns.size();
  const SizeValueType parts = team.GetNumberOfParts(candidates);
  if (parts == 1)
  {
    this->CollectCandidateRuns(selected, runs);
    return;
  }
  const CandidateRun * const candidate = m_CandidateRuns.data();
  marked.resize(candidates);
  std::vector<SizeValueType> partBegin(parts + 1, 0);
  team.ForEach(parts, [&](SizeValueType part) {
    const SizeValueType end = WorkTeam::PartBegin(candidates, part + 1, parts);
    SizeValueType       count = 0;
    for (SizeValueType i = WorkTeam::PartBegin(candidates, part, parts); i < end; ++i)
    {
      marked[i] = selected[candidate[i].Component];
      count += marked[i];
    }
    partBegin[part + 1] = count;
  });
  std::partial_sum(partBegin.begin(), partBegin.end(), partBegin.begin());
  runs.resize(partBegin[parts]);
  const SizeValueType * const lineBegin = m_LineRunBegin.data();
  team.ForEach(parts, [&](SizeValueType part) {
    const SizeValueType begin = WorkTeam::PartBegin(candidates, part, parts);
    const SizeValueType end = WorkTeam::PartBegin(candidates, part + 1, parts);
    if (begin == end)
    {
      return;
    }
    LineRun *     out = runs.data() + partBegin[part];
    SizeValueType line = this->LineOfRun(candidate[begin].Run);
    for (SizeValueType i = begin; i < end; ++i)
    {
      if (marked[i])
      {
        while (lineBegin[line + 1] <= candidate[i].Run)
        {
          ++line;
        }
        *out++ = { candidate[i].Run, static_cast<RunIndexType>(line) };
      }
    }
  });
}

SizeValueType
RunLabeling::GetMemoryInBytes() const
{
  return m_RunStart.capacity() * sizeof(CoordinateType) + m_RunLabel.capacity() * sizeof(RunIndexType) +
         m_LineRunBegin.capacity() * sizeof(SizeValueType) + m_LineFirstAbove.capacity() +
         m_ComponentSize.capacity() * sizeof(SizeValueType) + m_ComponentAbove.capacity() +
         m_CandidateRuns.capacity() * sizeof(CandidateRun) + m_KeptLineBits.capacity() * sizeof(uint64_t) +
         m_ClaimBegin.capacity() * sizeof(SizeValueType) + this->GetLineBitsBytes();
}

SizeValueType
RunLabeling::GetLineBitsBytes() const
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
