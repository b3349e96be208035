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
#include <type_traits>

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

/** Calls \a function with the ImageTypeTag of \a TPixel and \a info's dimension, 2 or 3. */
template <typename TPixel, typename TFunction>
decltype(auto)
DispatchDimension(const ScalarImageInfo & info, TFunction && function)
{
  if (info.Dimension == 2)
  {
    return function(ImageTypeTag<TPixel, 2>{});
  }
  if (info.Dimension == 3)
  {
    return function(ImageTypeTag<TPixel, 3>{});
  }
  throw std::logic_error("DispatchDimension: unsupported dimension " + std::to_string(info.Dimension));
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
      return DispatchDimension<typename decltype(pixel)::PixelType>(info, function);
    },
    [&] {
      return std::logic_error("DispatchScalarImage: unsupported pixel type " + PixelTypeName(info.ComponentType));
    });
}

/** DispatchScalarImage() for a label map, whose \a info comes from ReadLabelImageInfo(): 64-bit integers too, which
 * ITK names LONG or LONGLONG by reader and platform (each size is instantiated once). */
template <typename TFunction>
decltype(auto)
DispatchLabelImage(const ScalarImageInfo & info, TFunction && function)
{
  using Long = std::conditional_t<sizeof(long) == 8, std::int64_t, std::int32_t>;
  using UnsignedLong = std::make_unsigned_t<Long>;
  switch (info.ComponentType)
  {
    case itk::IOComponentEnum::LONGLONG:
      return DispatchDimension<std::int64_t>(info, function);
    case itk::IOComponentEnum::ULONGLONG:
      return DispatchDimension<std::uint64_t>(info, function);
    case itk::IOComponentEnum::LONG:
      return DispatchDimension<Long>(info, function);
    case itk::IOComponentEnum::ULONG:
      return DispatchDimension<UnsignedLong>(info, function);
    default:
      return DispatchScalarImage(info, function);
  }
}
} // namespace sic

#endif
