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
#ifndef itkSmallIsoComponentLabelEnums_h
#define itkSmallIsoComponentLabelEnums_h

#include <cstdint>
#include <ostream>

namespace itk
{
/** \class SmallIsoComponentLabelEnums
 * \brief Enums used by SmallIsoComponentLabelImageFilter.
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponentLabelEnums
{
public:
  /** \ingroup SmallIsoComponent
   * The labels whose small components are removed. All: every label, the background too
   * (islands removed and holes filled). Islands: every label but the background. Holes: the
   * background only. Listed: the labels of SetSelectedLabels(). */
  enum class Selection : uint8_t
  {
    All = 0,
    Islands = 1,
    Holes = 2,
    Listed = 3
  };
};

/** Prints the enumerator's qualified name, e.g. "itk::SmallIsoComponentLabelEnums::Selection::All". */
inline std::ostream &
operator<<(std::ostream & out, const SmallIsoComponentLabelEnums::Selection value)
{
  static const char * const names[] = { "All", "Islands", "Holes", "Listed" };
  const auto                index = static_cast<unsigned int>(value);
  return out << "itk::SmallIsoComponentLabelEnums::Selection::" << (index < 4 ? names[index] : "INVALID");
}
} // end namespace itk

#endif
