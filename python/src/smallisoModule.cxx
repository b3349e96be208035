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
// smalliso._core: the compiled core of the smalliso package (see smallisoCore.h).

#include "smallisoCore.h"
#include "smallisoLabels.h"
#include "smallisoPixelTypes.h"
#include "smallisoStatistics.h"

#include "itkMacro.h"
#include "itkMultiThreaderBase.h"
#include "itkSmallIsoComponentRunSummary.h"

#include <pybind11/stl.h>

#include <array>
#if defined(__GLIBC__)
#  include <malloc.h>
#endif

namespace
{
namespace py = pybind11;
using namespace smalliso;

/** Calls function(TPixel{}) for the pixel type of \a array's dtype. The filter reads the array's
 * samples as TPixel, so they must lie at addresses aligned for it: NumPy allows arrays that are not
 * (views of raw bytes at an odd offset, some buffers unpickled from elsewhere), and the Python
 * layer copies those before they come here. */
template <typename TFunction>
auto
ForPixelTypeOf(const py::array & array, TFunction && function) -> decltype(function(uint8_t{}))
{
  if ((array.flags() & py::detail::npy_api::NPY_ARRAY_ALIGNED_) == 0)
  {
    throw py::value_error("the array's samples are not aligned for its dtype " + std::string(py::str(array.dtype())) +
                          "; expected an aligned array (numpy.require(array, requirements='A') makes an aligned copy)");
  }
#define SMALLISO_DISPATCH(T)                 \
  if (py::isinstance<py::array_t<T>>(array)) \
  {                                          \
    return function(T{});                    \
  }
  SMALLISO_FOR_EACH_PIXEL_TYPE(SMALLISO_DISPATCH)
#undef SMALLISO_DISPATCH
  throw py::type_error("dtype " + std::string(py::str(array.dtype())) + " is not supported");
}

py::tuple
PixelTypeNames()
{
  py::list names;
#define SMALLISO_NAME(T) names.append(py::str(py::dtype::of<T>()));
  SMALLISO_FOR_EACH_PIXEL_TYPE(SMALLISO_NAME)
#undef SMALLISO_NAME
  return py::tuple(names);
}

Parameters
MakeParameters(double              isoValue,
               uint64_t            maximumSize,
               const std::string & side,
               bool                fullyConnected,
               unsigned int        threads)
{
  return { isoValue, maximumSize, ParseSide(side), fullyConnected, threads };
}
/** Defines a function of the chunked mode, (chunk, index list, index list, the filter's parameters),
 * that calls call(TPixel{}, chunk, first list, second list, parameters) for the chunk's pixel type.
 * \a names are the names of the chunk and of the two lists. */
template <typename TCall>
void
DefineChunkFunction(py::module_ &               module,
                    const char *                name,
                    const char *                doc,
                    std::array<const char *, 3> names,
                    TCall                       call)
{
  module.def(
    name,
    [call](const py::array &             chunk,
           const std::vector<uint64_t> & first,
           const std::vector<uint64_t> & second,
           double                        isovalue,
           uint64_t                      maxSize,
           const std::string &           side,
           bool                          fullyConnected,
           unsigned int                  threads) {
      const Parameters parameters = MakeParameters(isovalue, maxSize, side, fullyConnected, threads);
      return ForPixelTypeOf(chunk, [&](auto pixel) { return call(pixel, chunk, first, second, parameters); });
    },
    doc,
    py::arg(names[0]),
    py::arg(names[1]),
    py::arg(names[2]),
    py::arg("isovalue"),
    py::arg("max_size"),
    py::arg("side"),
    py::arg("fully_connected"),
    py::arg("threads"));
}
} // namespace

PYBIND11_MODULE(_core, module)
{
  module.doc() = "The compiled core of smalliso: the in-memory filter on NumPy arrays and the chunked mode's "
                 "pieces. Use smalliso.remove_small_components and smalliso.dask instead; arguments are "
                 "checked there.";
  py::register_exception_translator([](std::exception_ptr exception) {
    try
    {
      if (exception)
      {
        std::rethrow_exception(exception);
      }
    }
    catch (const itk::ExceptionObject & error)
    {
      PyErr_SetString(PyExc_RuntimeError, error.GetDescription());
    }
  });
  module.attr("pixel_types") = PixelTypeNames();
  module.attr("max_threads") = ITK_MAX_THREADS;
  DefineLabelFunctions(module);

  module.def(
    "filter",
    [](const py::array &     array,
       double                isovalue,
       uint64_t              maxSize,
       std::optional<double> maxVolume,
       const std::string &   side,
       bool                  fullyConnected,
       std::vector<double>   spacing,
       bool                  inPlace,
       bool                  withMask,
       unsigned int          threads) {
      const Parameters parameters = MakeParameters(isovalue, maxSize, side, fullyConnected, threads);
      return ForPixelTypeOf(array, [&](auto pixel) {
        using PixelType = decltype(pixel);
        return FilterArray<PixelType>(
          array.cast<py::array_t<PixelType>>(), parameters, maxVolume, spacing, inPlace, withMask);
      });
    },
    "(output or None in place, mask or None without with_mask, statistics) of the filter on a C- or "
    "Fortran-contiguous 2-D or 3-D array.",
    py::arg("array"),
    py::arg("isovalue"),
    py::arg("max_size"),
    py::arg("max_volume"),
    py::arg("side"),
    py::arg("fully_connected"),
    py::arg("spacing"),
    py::arg("in_place"),
    py::arg("with_mask"),
    py::arg("threads"));

  DefineChunkFunction(
    module,
    "filter_chunk",
    "(output, mask, fallback voxels) of the chunk [crop_begin, crop_end) of a C-contiguous box holding it and "
    "its halo.",
    { "box", "crop_begin", "crop_end" },
    [](auto pixel, const py::array & box, const auto & cropBegin, const auto & cropEnd, const Parameters & parameters) {
      using PixelType = decltype(pixel);
      return FilterChunk<PixelType>(box.cast<py::array_t<PixelType>>(), cropBegin, cropEnd, parameters);
    });
  DefineChunkFunction(
    module,
    "summarize_chunk",
    "The serialized summary of a C-contiguous chunk at begin of an image of image_shape.",
    { "chunk", "image_shape", "begin" },
    [](
      auto pixel, const py::array & chunk, const auto & imageShape, const auto & begin, const Parameters & parameters) {
      using PixelType = decltype(pixel);
      return SummarizeChunk<PixelType>(chunk.cast<py::array_t<PixelType>>(), imageShape, begin, parameters);
    });

  module.def("merge_summaries",
             &MergeSummaries,
             "The summary of two chunks' union; upper starts where lower ends along one axis.",
             py::arg("lower"),
             py::arg("upper"));
  module.def("summary_statistics",
             &SummaryStatistics,
             "The statistics of the components a summary settled.",
             py::arg("summary"));
  module.def(
    "keep_freed_memory",
    [] {
#if defined(__GLIBC__)
      // A process that runs one task after another reuses the blocks its last task freed instead
      // of giving them back to the system and faulting fresh pages in for the next task.
      constexpr int largestReusedBlock = 1 << 30;
      mallopt(M_MMAP_THRESHOLD, largestReusedBlock);
      mallopt(M_TRIM_THRESHOLD, largestReusedBlock);
#endif
    },
    "Keeps the memory this process frees for its next allocations (glibc) instead of returning it to the system.");
  module.def(
    "box_halo",
    [](uint64_t maxSize, const std::string & side) {
      return itk::SmallIsoComponentDetail::BoxHalo(maxSize, ParseSide(side));
    },
    "How far beyond a chunk its result depends on the voxels: K for one side, 2K for both.",
    py::arg("max_size"),
    py::arg("side"));
}
