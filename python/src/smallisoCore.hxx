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
#ifndef smallisoCore_hxx
#define smallisoCore_hxx

#include "smallisoArrays.h"
#include "smallisoCore.h"
#include "smallisoStatistics.h"

#include "itkImage.h"
#include "itkSmallIsoComponentImageFilter.h"
#include "itkSmallIsoComponentRunSummary.h"
#include "itkSmallIsoComponentStreamingSweep.h"

namespace smalliso
{
namespace detail
{
template <typename TPixel, unsigned int VDimension>
py::tuple
FilterImage(py::array_t<TPixel> &       array,
            const Parameters &          parameters,
            std::optional<double>       maximumVolume,
            const std::vector<double> & spacing,
            bool                        inPlace,
            bool                        withMask)
{
  using ImageType = itk::Image<TPixel, VDimension>;
  using FilterType = itk::SmallIsoComponentImageFilter<ImageType>;
  // ITK's x is the fastest axis: a C-ordered array's last axis, a Fortran-ordered array's first.
  const bool fortran = (array.flags() & py::array::c_style) == 0;
  const auto image = ImageOf<ImageType>(array, spacing);

  auto filter = FilterType::New();
  filter->SetInput(image);
  filter->SetIsoValue(parameters.IsoValue);
  if (maximumVolume)
  {
    filter->SetMaximumComponentVolume(*maximumVolume);
  }
  else
  {
    filter->SetMaximumComponentSize(parameters.MaximumSize);
  }
  filter->SetSide(parameters.Side);
  filter->SetFullyConnected(parameters.FullyConnected);
  if (parameters.Threads > 0)
  {
    filter->SetNumberOfWorkUnits(parameters.Threads);
  }
  filter->SetInPlace(inPlace);
  filter->SetGenerateRemovedMask(withMask);
  {
    py::gil_scoped_release release;
    filter->Update();
  }
  ImageType * output = filter->GetOutput();
  if (inPlace && output->GetBufferPointer() != array.data())
  {
    throw std::logic_error("smalliso: the filter did not run in place");
  }

  const std::vector<py::ssize_t> shape(array.shape(), array.shape() + VDimension);
  const auto                     side = [&filter](SideEnum which) {
    const auto & histogram = filter->GetComponentSizeHistogram(which);
    return SideCounts{ filter->GetNumberOfComponents(which),
                       filter->GetNumberOfRemovedComponents(which),
                       filter->GetNumberOfRemovedVoxels(which),
                       { histogram.begin(), histogram.end() } };
  };
  py::dict statistics = StatisticsDict(side(SideEnum::Above),
                                       side(SideEnum::Below),
                                       filter->GetNumberOfModifiedVoxels(),
                                       filter->GetNumberOfUnrepairableVoxels());
  statistics["effective_max_size"] = filter->GetEffectiveMaximumComponentSize();
  statistics["peak_extra_bytes"] = filter->GetPeakExtraMemoryInBytes();
  return py::make_tuple(inPlace ? py::object(py::none()) : py::object(ArrayOf(output, shape, fortran)),
                        withMask ? py::object(ArrayOf(filter->GetRemovedMask(), shape, fortran))
                                 : py::object(py::none()),
                        statistics);
}

inline std::vector<uint64_t>
ShapeOf(const py::array & array)
{
  return { array.shape(), array.shape() + array.ndim() };
}

/** The threader and work units of a chunk's C++ code (made while the caller holds the GIL). */
inline std::pair<itk::MultiThreaderBase::Pointer, unsigned int>
ChunkThreader(const Parameters & parameters)
{
  auto threader = itk::MultiThreaderBase::New();
  return { threader, parameters.Threads > 0 ? parameters.Threads : threader->GetNumberOfWorkUnits() };
}
} // namespace detail

template <typename TPixel>
py::tuple
FilterArray(py::array_t<TPixel>         array,
            const Parameters &          parameters,
            std::optional<double>       maximumVolume,
            const std::vector<double> & spacing,
            bool                        inPlace,
            bool                        withMask)
{
  if (array.ndim() == 2)
  {
    return detail::FilterImage<TPixel, 2>(array, parameters, maximumVolume, spacing, inPlace, withMask);
  }
  return detail::FilterImage<TPixel, 3>(array, parameters, maximumVolume, spacing, inPlace, withMask);
}

template <typename TPixel>
py::tuple
FilterChunk(py::array_t<TPixel>           box,
            const std::vector<uint64_t> & cropBegin,
            const std::vector<uint64_t> & cropEnd,
            const Parameters &            parameters)
{
  std::vector<py::ssize_t> partShape;
  for (std::size_t axis = 0; axis < cropBegin.size(); ++axis)
  {
    partShape.push_back(static_cast<py::ssize_t>(cropEnd[axis] - cropBegin[axis]));
  }
  py::array_t<TPixel>  output(partShape);
  py::array_t<uint8_t> mask(partShape);
  TPixel *             outputData = output.mutable_data();
  uint8_t *            maskData = mask.mutable_data();
  const auto           voxels = static_cast<std::size_t>(mask.size());
  const auto [threader, workUnits] = detail::ChunkThreader(parameters);
  uint64_t fallbacks = 0;
  {
    py::gil_scoped_release release;
    itk::SmallIsoComponentDetail::FilterBoxPart(box.data(),
                                                ToBox(detail::ShapeOf(box), 1),
                                                ToBox(cropBegin, 0),
                                                ToBox(cropEnd, 1),
                                                parameters.IsoValue,
                                                parameters.MaximumSize,
                                                parameters.Side,
                                                parameters.FullyConnected,
                                                threader,
                                                workUnits,
                                                outputData,
                                                maskData);
    // Bits 4 and 8 mark the voxels that got the fallback value in the above and below pass.
    for (std::size_t v = 0; v < voxels; ++v)
    {
      fallbacks += ((maskData[v] >> 2) & 1u) + ((maskData[v] >> 3) & 1u);
      maskData[v] &= 3u;
    }
  }
  return py::make_tuple(output, mask, fallbacks);
}

template <typename TPixel>
py::bytes
SummarizeChunk(py::array_t<TPixel>           chunk,
               const std::vector<uint64_t> & imageShape,
               const std::vector<uint64_t> & begin,
               const Parameters &            parameters)
{
  itk::SmallIsoComponentDetail::ComponentRules rules;
  rules.MaximumComponentSize = parameters.MaximumSize;
  rules.Side = parameters.Side;
  rules.FullyConnected = parameters.FullyConnected;
  const auto [threader, workUnits] = detail::ChunkThreader(parameters);
  std::vector<uint8_t> serialized;
  {
    py::gil_scoped_release release;
    serialized = itk::SmallIsoComponentDetail::SummarizeBox(chunk.data(),
                                                            ToBox(detail::ShapeOf(chunk), 1),
                                                            ToBox(imageShape, 1),
                                                            ToBox(begin, 0),
                                                            parameters.IsoValue,
                                                            rules,
                                                            threader,
                                                            workUnits)
                   .Serialize();
  }
  return py::bytes(reinterpret_cast<const char *>(serialized.data()), serialized.size());
}
} // namespace smalliso

/** Compiles the core's functions for pixel type T. */
#define SMALLISO_INSTANTIATE(T)                                                                                        \
  namespace smalliso                                                                                                   \
  {                                                                                                                    \
  template py::tuple                                                                                                   \
  FilterArray<T>(py::array_t<T>, const Parameters &, std::optional<double>, const std::vector<double> &, bool, bool);  \
  template py::tuple                                                                                                   \
  FilterChunk<T>(py::array_t<T>, const std::vector<uint64_t> &, const std::vector<uint64_t> &, const Parameters &);    \
  template py::bytes                                                                                                   \
  SummarizeChunk<T>(py::array_t<T>, const std::vector<uint64_t> &, const std::vector<uint64_t> &, const Parameters &); \
  }

#endif
