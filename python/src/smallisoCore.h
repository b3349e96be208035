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
#ifndef smallisoCore_h
#define smallisoCore_h

#include "itkSmallIsoComponentBlockSummary.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <vector>

/** The compiled core of the smalliso Python package: the public filter on NumPy arrays, and the
 * chunked mode's two pieces (a chunk filtered with its halo, a chunk's summary) on the chunks of a
 * Dask array. The package's Python code checks the arguments before they get here. */
namespace smalliso
{
namespace py = pybind11;
using SideEnum = itk::SmallIsoComponentEnums::Side;
using BoxIndex = itk::SmallIsoComponentDetail::BlockSummary::IndexType;

/** What the filter is asked to do. */
struct Parameters
{
  double   IsoValue{ 0.0 };
  uint64_t MaximumSize{ 20 };
  SideEnum Side{ SideEnum::Both };
  bool     FullyConnected{ false };
  /** Work units of the C++ code; 0 for ITK's default. */
  unsigned int Threads{ 0 };
};

/** A shape, begin or end in NumPy's axis order (C order: the last axis fastest) as an index of the
 * chunked mode's 3-D boxes (x fastest, planes along axis 2): (z, y, x) gives {x, y, z}, and a 2-D
 * (y, x) gives {x, fill, y}. */
BoxIndex
ToBox(const std::vector<uint64_t> & numpyOrder, uint64_t fill);

/** Filters \a array (2-D or 3-D, C- or Fortran-contiguous, so that its first or its last axis is
 * ITK's x) with itk::SmallIsoComponentImageFilter, its buffer imported without a copy. A positive
 * \a maximumVolume replaces the maximum size, with \a spacing in NumPy's axis order (empty: 1 per
 * axis). Returns (output, mask, statistics); output is None in place, where the result is in
 * \a array itself, and mask is None unless \a withMask asks for it. */
template <typename TPixel>
py::tuple
FilterArray(py::array_t<TPixel>         array,
            const Parameters &          parameters,
            std::optional<double>       maximumVolume,
            const std::vector<double> & spacing,
            bool                        inPlace,
            bool                        withMask);

/** The chunked mode's voxels of one chunk: \a box (C-contiguous) is the chunk with its halo, and
 * [cropBegin, cropEnd) the chunk within it (NumPy order). Returns (output, mask, fallbacks): the
 * chunk's voxels, its mask (0 kept, 1 or 2 removed in the above or below pass) and the number of
 * its voxels that got the fallback value in a pass. */
template <typename TPixel>
py::tuple
FilterChunk(py::array_t<TPixel>           box,
            const std::vector<uint64_t> & cropBegin,
            const std::vector<uint64_t> & cropEnd,
            const Parameters &            parameters);

/** The chunked mode's summary of one chunk alone (C-contiguous) at \a begin of an image of
 * \a imageShape (NumPy order), serialized. */
template <typename TPixel>
py::bytes
SummarizeChunk(py::array_t<TPixel>           chunk,
               const std::vector<uint64_t> & imageShape,
               const std::vector<uint64_t> & begin,
               const Parameters &            parameters);
} // namespace smalliso

#endif
