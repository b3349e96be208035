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

// The differential test for the pixel types and dimensions beyond the common ones: the
// filter classifies 8- and 16-bit integers and float with SSE2 and other types with a
// generic block test, and it promises any dimension from 2 on.

#include "itkSmallIsoComponentDifferential.h"

using itk::SmallIsoComponentTest::ExpectFilterMatchesReference;

TEST(SmallIsoComponentDifferential, Int8Image3D)
{
  ExpectFilterMatchesReference<int8_t, int8_t, 3>(20000, 120);
}

TEST(SmallIsoComponentDifferential, UInt16Image2D)
{
  ExpectFilterMatchesReference<uint16_t, uint16_t, 2>(21000, 160);
}

TEST(SmallIsoComponentDifferential, Int32Image3D)
{
  ExpectFilterMatchesReference<int32_t, int32_t, 3>(22000, 120);
}

TEST(SmallIsoComponentDifferential, DoubleImageWithNaN3D)
{
  ExpectFilterMatchesReference<double, double, 3>(23000, 120);
}

TEST(SmallIsoComponentDifferential, FloatToDouble2D)
{
  ExpectFilterMatchesReference<float, double, 2>(24000, 160);
}

TEST(SmallIsoComponentDifferential, UInt8Image4D)
{
  ExpectFilterMatchesReference<uint8_t, uint8_t, 4>(25000, 120);
}

TEST(SmallIsoComponentDifferential, FloatImageWithNaN4D)
{
  ExpectFilterMatchesReference<float, float, 4>(26000, 120);
}
