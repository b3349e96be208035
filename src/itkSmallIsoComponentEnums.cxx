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
#include "itkSmallIsoComponentEnums.h"

namespace itk
{
std::ostream &
operator<<(std::ostream & out, const SmallIsoComponentEnums::Side value)
{
  switch (value)
  {
    case SmallIsoComponentEnums::Side::Above:
      return out << "itk::SmallIsoComponentEnums::Side::Above";
    case SmallIsoComponentEnums::Side::Below:
      return out << "itk::SmallIsoComponentEnums::Side::Below";
    case SmallIsoComponentEnums::Side::Both:
      return out << "itk::SmallIsoComponentEnums::Side::Both";
  }
  return out << "INVALID VALUE FOR itk::SmallIsoComponentEnums::Side";
}

std::ostream &
operator<<(std::ostream & out, const SmallIsoComponentEnums::Phase value)
{
  switch (value)
  {
    case SmallIsoComponentEnums::Phase::Encoding:
      return out << "itk::SmallIsoComponentEnums::Phase::Encoding";
    case SmallIsoComponentEnums::Phase::Linking:
      return out << "itk::SmallIsoComponentEnums::Phase::Linking";
    case SmallIsoComponentEnums::Phase::Seams:
      return out << "itk::SmallIsoComponentEnums::Phase::Seams";
    case SmallIsoComponentEnums::Phase::Numbering:
      return out << "itk::SmallIsoComponentEnums::Phase::Numbering";
    case SmallIsoComponentEnums::Phase::Deciding:
      return out << "itk::SmallIsoComponentEnums::Phase::Deciding";
    case SmallIsoComponentEnums::Phase::Repair:
      return out << "itk::SmallIsoComponentEnums::Phase::Repair";
    case SmallIsoComponentEnums::Phase::Writes:
      return out << "itk::SmallIsoComponentEnums::Phase::Writes";
  }
  return out << "INVALID VALUE FOR itk::SmallIsoComponentEnums::Phase";
}
} // end namespace itk
