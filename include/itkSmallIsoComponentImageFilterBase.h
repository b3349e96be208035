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
#ifndef itkSmallIsoComponentImageFilterBase_h
#define itkSmallIsoComponentImageFilterBase_h

#include "itkInPlaceImageFilter.h"
#include "itkSmallIsoComponentEnums.h"
#include <map>
#include <type_traits>

namespace itk
{
/** \class SmallIsoComponentImageFilterBase
 * \brief What SmallIsoComponentImageFilter and SmallIsoComponentStreamingImageFilter share:
 * their parameters, the removed-voxel mask output, the checks of the parameters, K, and the
 * component counts of each side.
 *
 * Parameters (SmallIsoComponentImageFilter states what each one means):
 * - IsoValue σ: voxels with f >= σ are above, all others (NaN included) below; must not be NaN.
 * - MaximumComponentSize K (default 20) or MaximumComponentVolume (in the units of the spacing,
 *   cubed; must be >= 0): whichever was set last is the threshold, and
 *   GetUseMaximumComponentVolume() tells which. GetEffectiveMaximumComponentSize() is the K of the
 *   last run, floor(volume / voxel volume) with a relative tolerance of 1e-12 for a volume.
 * - Side (default Both) and FullyConnected (default off).
 * - GenerateRemovedMask (default off): whether output 1, GetRemovedMask(), is filled. The mask
 *   marks each voxel 0 (kept), 1 (removed in the above pass) or 2 (removed in the below pass).
 *   Without it output 1 keeps the image's geometry but has an empty buffered region (no voxels,
 *   no memory), in every piece the filter gives out.
 *
 * The filters run out of place by default (InPlaceOff()); SmallIsoComponentImageFilter can run
 * in place, SmallIsoComponentStreamingImageFilter never does.
 *
 * The component counts of each side (GetNumberOfComponents(), GetNumberOfRemovedComponents(),
 * GetNumberOfRemovedVoxels()) are read from what each filter keeps; side must be Above or Below
 * (Both is not a side and gives an exception).
 *
 * \sa SmallIsoComponentImageFilter
 * \sa SmallIsoComponentStreamingImageFilter
 * \ingroup SmallIsoComponent
 */
template <typename TInputImage, typename TOutputImage = TInputImage>
class ITK_TEMPLATE_EXPORT SmallIsoComponentImageFilterBase : public InPlaceImageFilter<TInputImage, TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(SmallIsoComponentImageFilterBase);

  using Self = SmallIsoComponentImageFilterBase;
  using Superclass = InPlaceImageFilter<TInputImage, TOutputImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  using InputImageType = TInputImage;
  using OutputImageType = TOutputImage;
  using InputPixelType = typename InputImageType::PixelType;
  using OutputPixelType = typename OutputImageType::PixelType;
  static constexpr unsigned int ImageDimension = TInputImage::ImageDimension;
  using MaskPixelType = uint8_t;
  using MaskImageType = Image<MaskPixelType, ImageDimension>;
  using SideEnum = SmallIsoComponentEnums::Side;
  /** Component size (voxels) -> number of components of that size. */
  using ComponentSizeHistogramType = std::map<SizeValueType, SizeValueType>;

  static_assert(std::is_arithmetic<InputPixelType>::value && std::is_arithmetic<OutputPixelType>::value,
                "SmallIsoComponent filters need scalar pixel types (integer or floating point); vector, RGB and "
                "complex pixels have no isovalue.");
  static_assert(static_cast<unsigned int>(TOutputImage::ImageDimension) == ImageDimension,
                "SmallIsoComponent filters need input and output images of the same dimension.");

#ifdef itkOverrideGetNameOfClassMacro
  itkOverrideGetNameOfClassMacro(SmallIsoComponentImageFilterBase);
#else
  itkTypeMacro(SmallIsoComponentImageFilterBase, InPlaceImageFilter);
#endif

  /** The isovalue σ. Voxels with f >= σ are above, all others (NaN included) below. */
  itkSetMacro(IsoValue, double);
  itkGetConstMacro(IsoValue, double);

  /** K: components with at most K voxels are removed; 0 removes nothing. Default 20. */
  virtual void
  SetMaximumComponentSize(SizeValueType size);
  itkGetConstMacro(MaximumComponentSize, SizeValueType);

  /** The threshold as a physical volume (units of the spacing, cubed): components whose
   * volume is at most this are removed. Must be >= 0. */
  virtual void
  SetMaximumComponentVolume(double volume);
  itkGetConstMacro(MaximumComponentVolume, double);

  /** True when the last threshold set was MaximumComponentVolume. */
  itkGetConstMacro(UseMaximumComponentVolume, bool);

  /** Which side loses its small components. Default Both. */
  itkSetEnumMacro(Side, SideEnum);
  itkGetEnumMacro(Side, SideEnum);

  /** Face connectivity (off, the default) or full connectivity (on). */
  itkSetMacro(FullyConnected, bool);
  itkGetConstReferenceMacro(FullyConnected, bool);
  itkBooleanMacro(FullyConnected);

  /** Whether the filter fills the mask of the removed voxels (output 1). Default off: the
   * filter then needs no memory for it. */
  itkSetMacro(GenerateRemovedMask, bool);
  itkGetConstMacro(GenerateRemovedMask, bool);
  itkBooleanMacro(GenerateRemovedMask);

  /** Mask of the removed voxels: 0 kept, 1 removed above, 2 removed below. Filled only with
   * GenerateRemovedMaskOn(); otherwise its buffered region is empty. */
  MaskImageType *
  GetRemovedMask();

  /** \name Component counts of each side, from the last run
   * side is Above or Below (Both is not a side and gives an exception). */
  /** @{ */
  SizeValueType
  GetNumberOfComponents(SideEnum side) const;
  SizeValueType
  GetNumberOfRemovedComponents(SideEnum side) const;
  SizeValueType
  GetNumberOfRemovedVoxels(SideEnum side) const;
  /** @} */

  /** K used by the last run (from MaximumComponentVolume when that was set last). */
  itkGetConstMacro(EffectiveMaximumComponentSize, SizeValueType);

  using DataObjectPointerArraySizeType = ProcessObject::DataObjectPointerArraySizeType;
  using Superclass::MakeOutput;
  /** Output 1 is the mask (a MaskImageType); the others are output images. */
  DataObject::Pointer
  MakeOutput(DataObjectPointerArraySizeType idx) override;

protected:
  /** The counts of one side. */
  struct SideCounts
  {
    SizeValueType Components{ 0 };
    SizeValueType RemovedComponents{ 0 };
    SizeValueType RemovedVoxels{ 0 };
  };

  /** Two outputs (the image and the mask), out of place. */
  SmallIsoComponentImageFilterBase();
  ~SmallIsoComponentImageFilterBase() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  /** Throws unless IsoValue is a number, MaximumComponentVolume (when it is the threshold) is
   * >= 0 and Side is Above, Below or Both. */
  // ProcessObject::VerifyPreconditions() is const, except in ITK 5 builds with ITKV4_COMPATIBILITY.
#if defined(ITKV4_COMPATIBILITY)
  void
  VerifyPreconditions() override;
#else
  void
  VerifyPreconditions() const override;
#endif

  /** Allocates the outputs as the superclass does, except the mask when it is not to be
   * generated: it then keeps its geometry, gives back any buffer an earlier run left, and is
   * allocated with no voxels. */
  void
  AllocateOutputs() override;

  /** K: MaximumComponentSize, or MaximumComponentVolume in voxels of \a spacing. */
  SizeValueType
  ComputeEffectiveMaximumComponentSize(const typename InputImageType::SpacingType & spacing) const;

  /** The counts of \a side from the last run; throws unless \a side is Above or Below. */
  virtual SideCounts
  GetSideCounts(SideEnum side) const = 0;

  /** Throws unless \a side is Above or Below. */
  void
  VerifyStatisticsSide(SideEnum side) const;

  // The filters' algorithms read the parameters directly, and set the K of their run.
  double        m_IsoValue{ 0.0 };
  SizeValueType m_MaximumComponentSize{ 20 };
  double        m_MaximumComponentVolume{ 0.0 };
  bool          m_UseMaximumComponentVolume{ false };
  SideEnum      m_Side{ SideEnum::Both };
  bool          m_FullyConnected{ false };
  bool          m_GenerateRemovedMask{ false };
  SizeValueType m_EffectiveMaximumComponentSize{ 0 };
};
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentImageFilterBase.hxx"
#endif

#endif
