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
/** Names a pixel type for a generic lambda: `[](auto tag) { using PixelType = typename
 * decltype(tag)::PixelType; ... }`. */
template <typename TPixel>
struct PixelTypeTag
{
  using PixelType = TPixel;
};

/** Names an image type for a generic lambda: `[](auto tag) { using ImageType = typename
 * decltype(tag)::ImageType; ... }`. */
template <typename TPixel, unsigned int VDimension>
struct ImageTypeTag
{
  using PixelType = TPixel;
  using ImageType = itk::Image<TPixel, VDimension>;
  static constexpr unsigned int Dimension = VDimension;
};

/** Calls \a function with the PixelTypeTag of \a componentType, one of the types SupportedPixelTypes() names; for any
 * other type, throws what \a unsupported() returns. Every instantiation of \a function must return the same type. */
template <typename TFunction, typename TUnsupported>
decltype(auto)
DispatchPixelType(itk::IOComponentEnum componentType, TFunction && function, TUnsupported && unsupported)
{
  switch (componentType)
  {
    case itk::IOComponentEnum::UCHAR:
      return function(PixelTypeTag<std::uint8_t>{});
    case itk::IOComponentEnum::CHAR:
      return function(PixelTypeTag<std::int8_t>{});
    case itk::IOComponentEnum::USHORT:
      return function(PixelTypeTag<std::uint16_t>{});
    case itk::IOComponentEnum::SHORT:
      return function(PixelTypeTag<std::int16_t>{});
    case itk::IOComponentEnum::UINT:
      return function(PixelTypeTag<std::uint32_t>{});
    case itk::IOComponentEnum::INT:
      return function(PixelTypeTag<std::int32_t>{});
    case itk::IOComponentEnum::FLOAT:
      return function(PixelTypeTag<float>{});
    case itk::IOComponentEnum::DOUBLE:
      return function(PixelTypeTag<double>{});
    default:
      throw unsupported();
  }
}

/** Calls \a function with the ImageTypeTag of the image \a info describes: its own pixel type and dimension, so the
 * image is processed without conversion. \a info must come from ReadScalarImageInfo(), which accepts exactly the types
 * handled here. Every instantiation of \a function must return the same type. */
template <typename TFunction>
decltype(auto)
DispatchScalarImage(const ScalarImageInfo & info, TFunction && function)
{
  return DispatchPixelType(
    info.ComponentType,
    [&](auto pixel) -> decltype(auto) {
      using PixelType = typename decltype(pixel)::PixelType;
      if (info.Dimension == 2)
      {
        return function(ImageTypeTag<PixelType, 2>{});
      }
      if (info.Dimension == 3)
      {
        return function(ImageTypeTag<PixelType, 3>{});
      }
      throw std::logic_error("DispatchScalarImage: unsupported dimension " + std::to_string(info.Dimension));
    },
    [&] {
      return std::logic_error("DispatchScalarImage: unsupported pixel type " + PixelTypeName(info.ComponentType));
    });
}
} // namespace sic

#endif
