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

// The filter against the brute-force reference on seeded random volumes: every output
// bit, every mask voxel and every statistic must agree, for 1, 2 and 7 work units.

#include "itkSmallIsoComponentDifferential.h"

using itk::SmallIsoComponentTest::ExpectFilterMatchesReference;

TEST(SmallIsoComponentDifferential, UInt8Image2D)
{
  ExpectFilterMatchesReference<uint8_t, uint8_t, 2>(1000, 260);
}

TEST(SmallIsoComponentDifferential, UInt8Image3D)
{
  ExpectFilterMatchesReference<uint8_t, uint8_t, 3>(2000, 160);
}

TEST(SmallIsoComponentDifferential, Int16Image2D)
{
  ExpectFilterMatchesReference<int16_t, int16_t, 2>(3000, 260);
}

TEST(SmallIsoComponentDifferential, Int16Image3D)
{
  ExpectFilterMatchesReference<int16_t, int16_t, 3>(4000, 160);
}

TEST(SmallIsoComponentDifferential, FloatImageWithNaN2D)
{
  ExpectFilterMatchesReference<float, float, 2>(5000, 260);
}

TEST(SmallIsoComponentDifferential, FloatImageWithNaN3D)
{
  ExpectFilterMatchesReference<float, float, 3>(6000, 160);
}

TEST(SmallIsoComponentDifferential, UInt8ToFloat2D)
{
  ExpectFilterMatchesReference<uint8_t, float, 2>(7000, 260);
}

TEST(SmallIsoComponentDifferential, UInt8ToFloat3D)
{
  ExpectFilterMatchesReference<uint8_t, float, 3>(8000, 160);
}

TEST(SmallIsoComponentDifferential, Int16ToFloat2D)
{
  ExpectFilterMatchesReference<int16_t, float, 2>(9000, 260);
}

TEST(SmallIsoComponentDifferential, Int16ToFloat3D)
{
  ExpectFilterMatchesReference<int16_t, float, 3>(10000, 160);
}

TEST(SmallIsoComponentDifferential, LargeUInt8Image3D)
{
  // Every extent 20 to 40: many slabs per work unit count, long walks, big components.
  ExpectFilterMatchesReference<uint8_t, uint8_t, 3>(11000, 40, true);
}

TEST(SmallIsoComponentDifferential, LargeFloatImageWithNaN3D)
{
  ExpectFilterMatchesReference<float, float, 3>(12000, 40, true);
}
