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
#include <cstdint>
#include <cstring>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
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

  /** Finds the runs of \a labels, an image of extent \a size with axis 0 fastest: each line's
   * runs counted, then written where the counts put them, both in slabs of lines shared among
   * the members of \a team. */
  void
  Encode(const TLabel * labels, const std::vector<SizeValueType> & size, WorkTeam & team)
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
    const auto forEachLine = [&team, lines](const auto & lineFunction) {
      ForEachLineInSlabs(team, lines, lineFunction);
    };
    m_LineBegin.assign(lines + 1, 0);
    forEachLine([this, labels](SizeValueType line) {
      const TLabel * const row = labels + line * m_Length;
      RunIndex             runs = 1;
      this->ForEachRunStart(row, [&runs](SizeValueType) { ++runs; });
      m_LineBegin[line + 1] = runs;
    });
    for (SizeValueType line = 0; line < lines; ++line)
    {
      m_LineBegin[line + 1] += m_LineBegin[line];
    }
    m_Start.resize(m_LineBegin[lines]);
    m_Label.resize(m_LineBegin[lines]);
    forEachLine([this, labels](SizeValueType line) {
      const TLabel * const row = labels + line * m_Length;
      RunIndex             run = m_LineBegin[line];
      m_Start[run] = 0;
      m_Label[run] = row[0];
      this->ForEachRunStart(row, [this, row, &run](SizeValueType x) {
        m_Start[++run] = static_cast<CoordinateType>(x);
        m_Label[run] = row[x];
      });
    });
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
  /** Calls function(x) for every voxel x > 0 of \a row whose label differs from the one before
   * it. A block whose bytes equal those of the block one voxel before holds no run start: the
   * library's vector compare skips it, so a voxel inside a long run costs a fraction of a
   * compare. (Equal bytes mean equal labels: float maps are whole numbers, never NaN.) */
  template <typename TFunction>
  void
  ForEachRunStart(const TLabel * row, TFunction && function) const
  {
    constexpr SizeValueType block = Tuning::LabelBlockBytes / sizeof(TLabel);
    for (SizeValueType x = 1; x < m_Length;)
    {
      const SizeValueType end = std::min(m_Length, x + block);
      if (end - x == block && std::memcmp(row + x, row + x - 1, Tuning::LabelBlockBytes) == 0)
      {
        x = end;
        continue;
      }
      for (; x < end; ++x)
      {
        if (!(row[x] == row[x - 1]))
        {
          function(x);
        }
      }
    }
  }

  SizeValueType               m_Length{ 0 };
  std::vector<RunIndex>       m_LineBegin;
  std::vector<CoordinateType> m_Start;
  std::vector<TLabel>         m_Label;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
