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
#ifndef smallisoArrays_h
#define smallisoArrays_h

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "itkIntTypes.h"

#include <vector>

namespace smalliso
{
namespace detail
{
namespace py = pybind11;

/** A NumPy array over the buffer of \a image, which the array keeps alive: C order, or Fortran
 * order when \a fortran. */
template <typename TImage>
py::array
ArrayOf(TImage * image, const std::vector<py::ssize_t> & shape, bool fortran)
{
  using PixelType = typename TImage::PixelType;
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t              stride = sizeof(PixelType);
  for (std::size_t k = 0; k < shape.size(); ++k)
  {
    const std::size_t axis = fortran ? k : shape.size() - 1 - k;
    strides[axis] = stride;
    stride *= shape[axis];
  }
  auto *      owner = new typename TImage::Pointer(image);
  py::capsule capsule(owner, [](void * pointer) { delete static_cast<typename TImage::Pointer *>(pointer); });
  return py::array(py::dtype::of<PixelType>(), shape, strides, image->GetBufferPointer(), capsule);
}

/** An ITK image over the buffer of \a array (C- or Fortran-contiguous, so that its last or its first
 * axis is ITK's x), with \a spacing in NumPy's axis order (empty: 1 per axis). */
template <typename TImage>
typename TImage::Pointer
ImageOf(const py::array_t<typename TImage::PixelType> & array, const std::vector<double> & spacing)
{
  using PixelType = typename TImage::PixelType;
  constexpr unsigned int       dimension = TImage::ImageDimension;
  const bool                   fortran = (array.flags() & py::array::c_style) == 0;
  typename TImage::SizeType    size;
  typename TImage::SpacingType itkSpacing;
  for (unsigned int axis = 0; axis < dimension; ++axis)
  {
    const unsigned int numpyAxis = fortran ? axis : dimension - 1 - axis;
    size[axis] = static_cast<itk::SizeValueType>(array.shape(numpyAxis));
    itkSpacing[axis] = spacing.empty() ? 1.0 : spacing[numpyAxis];
  }
  auto image = TImage::New();
  image->SetRegions(size);
  auto container = TImage::PixelContainer::New();
  // The filter writes the input only in place, where the caller gives a writable array.
  container->SetImportPointer(
    const_cast<PixelType *>(array.data()), static_cast<itk::SizeValueType>(array.size()), false);
  image->SetPixelContainer(container);
  image->SetSpacing(itkSpacing);
  return image;
}
} // namespace detail
} // namespace smalliso

#endif
