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
#ifndef itkSmallIsoComponentEnums_h
#define itkSmallIsoComponentEnums_h

#include "itkIntTypes.h"
#include "SmallIsoComponentExport.h"
#include <ostream>

namespace itk
{
/** \class SmallIsoComponentEnums
 * \brief Enums used by SmallIsoComponentImageFilter.
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponentEnums
{
public:
  /** \ingroup SmallIsoComponent
   * Which side of the isovalue loses its small components.
   * Above: small components of {f >= IsoValue} (specks outside an object).
   * Below: small components of {f < IsoValue} (bubbles inside an object).
   * Both: Above, then Below on the result of the first pass. */
  enum class Side : uint8_t
  {
    Above = 0,
    Below = 1,
    Both = 2
  };

  /** \ingroup SmallIsoComponent
   * The phases of an update that labels the whole image, in order (docs/algorithm.md).
   * Encoding: the lines' runs (and the output's copy of the input).
   * Linking: the runs linked inside each slab of lines, the slabs shared among the work units.
   * Seams: the runs linked across the slabs' borders (one work unit; the others meanwhile
   * write the output's copy of a large input).
   * Numbering: the components numbered and their sizes summed (at several work units and
   * 2^20 runs or more, two of them as a pipeline, the output's copy written in the moments
   * it leaves, and with Side Both the first stage summing the last lines once done; else
   * one work unit, the others writing the copy beside it; at one work unit, with the copy
   * after it).
   * Deciding: which components each pass removes, their runs gathered, and the below side's
   * components grouped through the flipped ones (the groups numbered).
   * Repair: the repaired value of every removed voxel computed (with Side Above or Below
   * and an output apart from the input, also written, with the mask).
   * Writes: the repaired values (and the mask) written where the repair did not write them. */
  enum class Phase : uint8_t
  {
    Encoding = 0,
    Linking = 1,
    Seams = 2,
    Numbering = 3,
    Deciding = 4,
    Repair = 5,
    Writes = 6
  };
  /** How many phases there are. */
  static constexpr unsigned int NumberOfPhases = 7;
};

/** Prints the enumerator's qualified name, e.g. "itk::SmallIsoComponentEnums::Side::Both". */
extern SmallIsoComponent_EXPORT std::ostream &
                                operator<<(std::ostream & out, const SmallIsoComponentEnums::Side value);
/** Prints the enumerator's qualified name, e.g. "itk::SmallIsoComponentEnums::Phase::Seams". */
extern SmallIsoComponent_EXPORT std::ostream &
                                operator<<(std::ostream & out, const SmallIsoComponentEnums::Phase value);
} // end namespace itk

#endif
