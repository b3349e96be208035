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
#ifndef sicScalarImageDispatch_h
#define sicScalarImageDispatch_h

#include "sicImageFiles.h"

#include "itkImage.h"

#include <cstdint>
#include <stdexcept>

namespace sic
{
/** Names an image type for a generic lambda: `[](auto tag) { using ImageType = typename
 * decltype(tag)::ImageType; ... }`. */
template <typename TPixel, unsigned int VDimension>
struct ImageTypeTag
{
  using PixelType = TPixel;
  using ImageType = itk::Image<TPixel, VDimension>;
  static constexpr unsigned int Dimension = VDimension;
};

namespace detail
{
template <typename TPixel, typename TFunction>
decltype(auto)
DispatchDimension(unsigned int dimension, TFunction && function)
{
  if (dimension == 2)
  {
    return function(ImageTypeTag<TPixel, 2>{});
  }
  if (dimension == 3)
  {
    return function(ImageTypeTag<TPixel, 3>{});
  }
  throw std::logic_error("DispatchScalarImage: unsupported dimension " + std::to_string(dimension));
}
} // namespace detail

/** Calls \a function with the ImageTypeTag of the image \a info describes: its own pixel
 * type and dimension, so the image is processed without conversion. \a info must come
 * from ReadScalarImageInfo(), which accepts exactly the types handled here. Every
 * instantiation of \a function must return the same type. */
template <typename TFunction>
decltype(auto)
DispatchScalarImage(const ScalarImageInfo & info, TFunction && function)
{
  using detail::DispatchDimension;
  switch (info.ComponentType)
  {
    case itk::IOComponentEnum::UCHAR:
      return DispatchDimension<std::uint8_t>(info.Dimension, function);
    case itk::IOComponentEnum::CHAR:
      return DispatchDimension<std::int8_t>(info.Dimension, function);
    case itk::IOComponentEnum::USHORT:
      return DispatchDimension<std::uint16_t>(info.Dimension, function);
    case itk::IOComponentEnum::SHORT:
      return DispatchDimension<std::int16_t>(info.Dimension, function);
    case itk::IOComponentEnum::UINT:
      return DispatchDimension<std::uint32_t>(info.Dimension, function);
    case itk::IOComponentEnum::INT:
      return DispatchDimension<std::int32_t>(info.Dimension, function);
    case itk::IOComponentEnum::FLOAT:
      return DispatchDimension<float>(info.Dimension, function);
    case itk::IOComponentEnum::DOUBLE:
      return DispatchDimension<double>(info.Dimension, function);
    default:
      throw std::logic_error("DispatchScalarImage: unsupported pixel type " + PixelTypeName(info.ComponentType));
  }
}
} // namespace sic

#endif
