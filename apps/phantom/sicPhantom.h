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
#ifndef sicPhantom_h
#define sicPhantom_h

#include "itkImage.h"

#include <cstdint>

namespace sic
{
using PhantomImageType = itk::Image<std::int16_t, 3>;

/** The isovalue at which the phantom shows many specks and bubbles (Hounsfield units). */
constexpr double PhantomSuggestedIsoValue = 150.0;

/** A synthetic CT-like volume of size³ voxels (spacing 0.8 x 0.8 x 1.0 mm, centred on the
 * origin), in Hounsfield-like units: air (-1000) around an ellipsoidal body of soft tissue
 * (40) holding a dense ellipsoidal shell (700) with marrow (60) inside and a dense rod
 * (1000) beside it, edges ramped over about a voxel, and noise of about 20 everywhere.
 * Small dense specks (300 to 1000, 1 to about 25 voxels) are scattered where the volume is
 * below 100, and small bubbles (-200 to 100) inside the dense parts, so that thresholding
 * at PhantomSuggestedIsoValue gives many small components on both sides. The same size
 * and seed give the same volume, bit for bit, on every platform. */
PhantomImageType::Pointer
MakePhantom(unsigned int size, std::uint64_t seed);
} // namespace sic

#endif
