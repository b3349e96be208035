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
#ifndef itkSmallIsoComponentLabelRuns_h
#define itkSmallIsoComponentLabelRuns_h

#include "itkMacro.h"
#include "itkNumericTraits.h"
#include "itkSmallIsoComponentLineSlabs.h"
#include "itkSmallIsoComponentTuning.h"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>
#if defined(__SSE2__)
#  include <emmintrin.h>
#endif

namespace itk
{
namespace SmallIsoComponentDetail
{
/** The bits of the first byte of each voxel of \a TLabel in 64 bytes. */
template <typename TLabel>
constexpr uint64_t
FirstByteBits()
{
  uint64_t bits = 0;
  for (unsigned int i = 0; i < 64; i += sizeof(TLabel))
  {
    bits |= uint64_t{ 1 } << i;
  }
  return bits;
}

/** A bit for each voxel of the 64 bytes from \a voxels that differs in some byte from the
 * voxel before it: bit i * sizeof(TLabel) for voxel i. */
template <typename TLabel>
uint64_t
DifferingVoxels(const TLabel * voxels)
{
#if defined(__SSE2__)
  const auto * here = reinterpret_cast<const char *>(voxels);
  const auto * before = reinterpret_cast<const char *>(voxels - 1);
  uint64_t     equal = 0;
  for (unsigned int i = 0; i < 4; ++i)
  {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i *>(here + 16 * i));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i *>(before + 16 * i));
    equal |= static_cast<uint64_t>(static_cast<uint16_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(a, b)))) << (16 * i);
  }
  // A voxel is equal when all its bytes are: fold each voxel's bits into its first byte's.
  for (unsigned int width = 1; width < sizeof(TLabel); width *= 2)
  {
    equal &= equal >> width;
  }
  return ~equal & FirstByteBits<TLabel>();
#else
  uint64_t differ = 0;
  for (unsigned int i = 0; i < 64 / sizeof(TLabel); ++i)
  {
    if (std::memcmp(voxels + i, voxels + i - 1, sizeof(TLabel)) != 0)
    {
      differ |= uint64_t{ 1 } << (i * sizeof(TLabel));
    }
  }
  return differ;
#endif
}

/** Whether the \a count values from \a values on are all finite whole numbers (integers always are). Below
 * 2^(digits - 1) in magnitude, adding that power rounds a value to a whole number, so subtracting it again gives the
 * value back exactly when it was one; every finite value above it is whole. Without branches, so that the loop is
 * vectorized. */
template <typename TReal>
bool
AreWholeNumbers(const TReal * values, SizeValueType count)
{
  if constexpr (!std::is_floating_point<TReal>::value)
  {
    return true;
  }
  else
  {
    constexpr TReal wholeAbove = TReal{ 1 } / std::numeric_limits<TReal>::epsilon();
    constexpr TReal largest = std::numeric_limits<TReal>::max();
    unsigned int    fractionalOrNotFinite = 0;
    for (SizeValueType i = 0; i < count; ++i)
    {
      const TReal magnitude = std::abs(values[i]);
      const bool  whole = ((magnitude + wholeAbove) - wholeAbove == magnitude) | (magnitude >= wholeAbove);
      fractionalOrNotFinite |= static_cast<unsigned int>(!whole | !(magnitude <= largest));
    }
    return fractionalOrNotFinite == 0;
  }
}

/** \class LabelRuns
 * The runs of a label image: its lines along axis 0, each cut into runs of one label, stored
 * line after line, so that a line's runs are numbered from LineBegin(line) to LineEnd(line).
 * \ingroup SmallIsoComponent */
template <typename TLabel>
class LabelRuns
{
public:
  using RunIndex = SizeValueType;
  /** A place on a line: lines of up to 2^32 - 1 voxels, as the scalar filter's. */
  using CoordinateType = uint32_t;

  /** Finds the runs of \a labels, an image of extent \a size with axis 0 fastest, in one pass
   * over the image: each work unit appends the runs of its part of the lines as it finds them,
   * and the parts are joined in order. With \a copy, each line is also copied there while it is
   * in cache. */
  void
  Encode(const TLabel * labels, const std::vector<SizeValueType> & size, WorkTeam & team, TLabel * copy = nullptr);

  /** Whether every sample Encode() read is a finite whole number, as a label map's must be. Each sample has its
   * run's label byte for byte, or as a value (-0 and 0, the only values equal with other bytes), so the runs' labels
   * are the ones to check. */
  bool
  HoldsWholeNumbersOnly() const
  {
    return AreWholeNumbers(m_Label.data(), m_Label.size());
  }

  /** The voxels of a line. */
  SizeValueType
  GetLineLength() const
  {
    return m_Length;
  }
  SizeValueType
  GetNumberOfLines() const
  {
    return m_LineBegin.size() - 1;
  }
  SizeValueType
  GetNumberOfRuns() const
  {
    return m_Start.size();
  }
  RunIndex
  LineBegin(SizeValueType line) const
  {
    return m_LineBegin[line];
  }
  RunIndex
  LineEnd(SizeValueType line) const
  {
    return m_LineBegin[line + 1];
  }
  /** Where each run starts on its line, in the order of the runs. */
  const CoordinateType *
  GetStarts() const
  {
    return m_Start.data();
  }
  SizeValueType
  Start(RunIndex run) const
  {
    return m_Start[run];
  }
  /** Where \a run, a run of \a line, ends (one past its last voxel). */
  SizeValueType
  End(RunIndex run, SizeValueType line) const
  {
    return run + 1 < m_LineBegin[line + 1] ? m_Start[run + 1] : m_Length;
  }
  TLabel
  Label(RunIndex run) const
  {
    return m_Label[run];
  }
  /** The run of \a line that holds voxel \a x. */
  RunIndex
  RunAt(SizeValueType line, SizeValueType x) const
  {
    const auto first = m_Start.begin() + static_cast<std::ptrdiff_t>(m_LineBegin[line]);
    const auto last = m_Start.begin() + static_cast<std::ptrdiff_t>(m_LineBegin[line + 1]);
    return static_cast<RunIndex>(std::upper_bound(first, last, x) - m_Start.begin()) - 1;
  }

private:
  /** Copies \a line of \a labels to \a copy, when there is one. */
  void
  CopyLine(const TLabel * labels, SizeValueType line, TLabel * copy) const
  {
    if (copy != nullptr)
    {
      std::copy_n(labels + line * m_Length, m_Length, copy + line * m_Length);
    }
  }

  /** The runs of a part of the lines, before they are appended to the others. */
  struct PartRuns
  {
    std::vector<CoordinateType> Start;
    std::vector<TLabel>         Label;
  };

  /** Appends the runs of lines \a first to \a end of the image to the empty \a part, line after
   * line, noting each line's end in m_LineBegin (counted from the part's first run), and copies
   * each line to \a copy, when there is one. */
  void
  AppendRuns(const TLabel * labels, SizeValueType first, SizeValueType end, TLabel * copy, PartRuns & part);

  /** Calls function(x) for every voxel x > 0 of \a row whose label differs from the one before
   * it. */
  template <typename TFunction>
  void
  ForEachRunStart(const TLabel * row, TFunction && function) const
  {
    this->ForEachBlock(row, [row, &function](SizeValueType first, uint64_t differ) {
      for (; differ != 0; differ &= differ - 1)
      {
        const SizeValueType x = first + static_cast<SizeValueType>(__builtin_ctzll(differ)) / sizeof(TLabel);
        if (!std::is_floating_point<TLabel>::value || !(row[x] == row[x - 1]))
        {
          function(x);
        }
      }
    });
  }

  /** Calls function(first, differ) for blocks of 64 bytes of \a row from voxel 1 on, a line's
   * last block overlapping the one before it: bit i * sizeof(TLabel) of differ is set when voxel
   * first + i differs in some byte from the voxel before it and lies past the blocks before. */
  template <typename TFunction>
  void
  ForEachBlock(const TLabel * row, TFunction && function) const
  {
    constexpr SizeValueType block = 64 / sizeof(TLabel);
    SizeValueType           x = 1;
    for (; x + block <= m_Length; x += block)
    {
      function(x, DifferingVoxels(row + x));
    }
    if (x < m_Length && m_Length > block)
    {
      const SizeValueType first = m_Length - block;
      function(first, DifferingVoxels(row + first) & (~uint64_t{ 0 } << ((x - first) * sizeof(TLabel))));
      return;
    }
    for (; x < m_Length; ++x)
    {
      if (std::memcmp(row + x, row + x - 1, sizeof(TLabel)) != 0)
      {
        function(x, uint64_t{ 1 });
      }
    }
  }

  SizeValueType               m_Length{ 0 };
  std::vector<RunIndex>       m_LineBegin;
  std::vector<CoordinateType> m_Start;
  std::vector<TLabel>         m_Label;
  /** The runs of the parts after the first, kept between updates for their memory. */
  std::vector<PartRuns> m_Parts;
};

template <typename TLabel>
inline void
LabelRuns<TLabel>::Encode(const TLabel *                     labels,
                          const std::vector<SizeValueType> & size,
                          WorkTeam &                         team,
                          TLabel *                           copy)
{
  if (size[0] > NumericTraits<CoordinateType>::max())
  {
    itkGenericExceptionMacro("SmallIsoComponent: lines along axis 0 must have at most "
                             << NumericTraits<CoordinateType>::max() << " voxels, not " << size[0]);
  }
  m_Length = size[0];
  SizeValueType lines = 1;
  for (std::size_t a = 1; a < size.size(); ++a)
  {
    lines *= size[a];
  }
  m_LineBegin.resize(lines + 1);
  m_LineBegin[0] = 0;
  // Each work unit appends the runs of its part of the lines, in one pass over the image; the
  // first part's go straight to the run arrays, the others' after them.
  const SizeValueType parts = team.GetNumberOfParts(lines);
  m_Parts.resize(parts - 1);
  // Room for all the parts' runs, so that joining them does not move the first part's.
  m_Start.reserve(lines * m_Length / Tuning::VoxelsPerReservedLabelRun);
  m_Label.reserve(lines * m_Length / Tuning::VoxelsPerReservedLabelRun);
  PartRuns whole{ std::move(m_Start), std::move(m_Label) };
  team.ForEach(parts, [&](SizeValueType part) {
    this->AppendRuns(labels,
                     WorkTeam::PartBegin(lines, part, parts),
                     WorkTeam::PartBegin(lines, part + 1, parts),
                     copy,
                     part == 0 ? whole : m_Parts[part - 1]);
  });
  m_Start = std::move(whole.Start);
  m_Label = std::move(whole.Label);
  for (SizeValueType part = 1; part < parts; ++part)
  {
    const RunIndex offset = m_Start.size();
    for (SizeValueType line = WorkTeam::PartBegin(lines, part, parts);
         line < WorkTeam::PartBegin(lines, part + 1, parts);
         ++line)
    {
      m_LineBegin[line + 1] += offset;
    }
    m_Start.insert(m_Start.end(), m_Parts[part - 1].Start.begin(), m_Parts[part - 1].Start.end());
    m_Label.insert(m_Label.end(), m_Parts[part - 1].Label.begin(), m_Parts[part - 1].Label.end());
  }
}

template <typename TLabel>
inline void
LabelRuns<TLabel>::AppendRuns(const TLabel * labels,
                              SizeValueType  first,
                              SizeValueType  end,
                              TLabel *       copy,
                              PartRuns &     part)
{
  part.Start.clear();
  part.Label.clear();
  part.Start.reserve((end - first) * m_Length / Tuning::VoxelsPerReservedLabelRun);
  part.Label.reserve((end - first) * m_Length / Tuning::VoxelsPerReservedLabelRun);
  for (SizeValueType line = first; line < end; ++line)
  {
    const TLabel * const row = labels + line * m_Length;
    part.Start.push_back(0);
    part.Label.push_back(row[0]);
    this->ForEachRunStart(row, [&part, row](SizeValueType x) {
      part.Start.push_back(static_cast<CoordinateType>(x));
      part.Label.push_back(row[x]);
    });
    m_LineBegin[line + 1] = part.Start.size();
    this->CopyLine(labels, line, copy);
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
