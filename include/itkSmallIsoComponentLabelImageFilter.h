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
#ifndef itkSmallIsoComponentLabelImageFilter_h
#define itkSmallIsoComponentLabelImageFilter_h

#include "itkInPlaceImageFilter.h"
#include "itkSmallIsoComponentLabelEnums.h"
#include "itkSmallIsoComponentLabelRepair.h"
#include "itkSmallIsoComponentRegionLines.h"
#include <map>
#include <ostream>
#include <vector>

namespace itk
{
/** \class SmallIsoComponentLabelImageFilter
 * \brief Removes the small islands and fills the small holes of a label map, each removed
 * voxel taking the label voted by the labels around its component.
 *
 * A component is a connected set of voxels of one label (face connectivity, or full with
 * FullyConnectedOn()); the background is a label like the others. A component of a selected
 * label (see SmallIsoComponentLabelEnums::Selection) is removed when it has at most K voxels
 * (MaximumComponentSize, default 20; or MaximumComponentVolume in physical units; or the
 * label's own K from SetMaximumComponentSizes()), or, with KeepLargestComponents N > 0, when it
 * is smaller than its label's N-th largest component. Every decision is made on the input.
 *
 * Each voxel v of a removed component C walks along the 2·N axis directions to the first voxel
 * w outside C; each w votes for its label. The votes of w in kept components count, or all the
 * votes when none of them is kept; the label with the most votes wins, ties going to the label
 * of the nearest w, then to the smallest label. A voxel whose walks all leave the image keeps
 * its label and counts as unrepairable. Nothing else changes, and the result does not depend on
 * the number of threads.
 *
 * The pixel type is any integer type, or a floating-point type whose samples are whole numbers
 * (an image with a fractional, infinite or NaN sample is refused). Output 1, GetRemovedMask(),
 * marks the removed voxels with 1 when GenerateRemovedMaskOn(). GetLabelStatistics() gives each
 * label's components, removals, gains and component sizes.
 *
 * Any region asked of the output is exactly that part of the whole image's output: the filter
 * reads it with a halo of twice the largest K, so it streams (with KeepLargestComponents > 0 it
 * makes the whole image at once). The statistics describe the last piece: only its removed
 * voxels are repaired, so the modified, unrepairable and gained voxels are those of the piece,
 * while the components, removed components, removed voxels and histograms are those of the part
 * read, the piece and its halo.
 *
 * docs/labels.md describes the rule and its choices; docs/algorithm.md the engine.
 *
 * \sa SmallIsoComponentImageFilter
 * \ingroup SmallIsoComponent
 */
template <typename TImage>
class ITK_TEMPLATE_EXPORT SmallIsoComponentLabelImageFilter : public InPlaceImageFilter<TImage, TImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(SmallIsoComponentLabelImageFilter);

  using Self = SmallIsoComponentLabelImageFilter;
  using Superclass = InPlaceImageFilter<TImage, TImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  using ImageType = TImage;
  using LabelType = typename ImageType::PixelType;
  using SizeType = typename ImageType::SizeType;
  using RegionType = typename ImageType::RegionType;
  using IndexType = typename ImageType::IndexType;
  using SpacingType = typename ImageType::SpacingType;
  static constexpr unsigned int ImageDimension = TImage::ImageDimension;
  using MaskImageType = Image<uint8_t, ImageDimension>;
  using SelectionEnum = SmallIsoComponentLabelEnums::Selection;
  /** Component size (voxels) -> number of components of that size. */
  using ComponentSizeHistogramType = std::map<SizeValueType, SizeValueType>;
  using LabelSizeMapType = std::map<LabelType, SizeValueType>;

  /** What the last run found and changed for one label. */
  struct LabelStatistics
  {
    SizeValueType              Components{ 0 };
    SizeValueType              RemovedComponents{ 0 };
    SizeValueType              RemovedVoxels{ 0 };
    SizeValueType              GainedVoxels{ 0 };
    ComponentSizeHistogramType Histogram;
  };
  using LabelStatisticsMapType = std::map<LabelType, LabelStatistics>;

  itkNewMacro(Self);
#ifdef itkOverrideGetNameOfClassMacro
  itkOverrideGetNameOfClassMacro(SmallIsoComponentLabelImageFilter);
#else
  itkTypeMacro(SmallIsoComponentLabelImageFilter, InPlaceImageFilter);
#endif

  /** K: components with at most K voxels are removed; 0 removes none by size. Default 20. */
  void
  SetMaximumComponentSize(SizeValueType size);
  itkGetConstMacro(MaximumComponentSize, SizeValueType);

  /** K as a physical volume (units of the spacing, cubed, >= 0); whichever of the two was set
   * last is used. */
  void
  SetMaximumComponentVolume(double volume);
  itkGetConstMacro(MaximumComponentVolume, double);
  itkGetConstMacro(UseMaximumComponentVolume, bool);

  /** K of the labels it names, in voxels; the other labels use the K above. */
  void
  SetMaximumComponentSizes(const LabelSizeMapType & sizes);
  itkGetConstReferenceMacro(MaximumComponentSizes, LabelSizeMapType);
  /** K of one label, in voxels: its entry of the map above, for callers without std::map (Python). */
  void
  SetMaximumComponentSizeOfLabel(LabelType label, SizeValueType size);

  /** Which labels lose their small components. Default All. */
  itkSetEnumMacro(Selection, SelectionEnum);
  itkGetEnumMacro(Selection, SelectionEnum);

  /** The labels of Selection Listed. */
  void
  SetSelectedLabels(const std::vector<LabelType> & labels);
  itkGetConstReferenceMacro(SelectedLabels, std::vector<LabelType>);

  /** The background's label, for Selection Islands and Holes. Default 0. */
  itkSetMacro(BackgroundValue, LabelType);
  itkGetConstMacro(BackgroundValue, LabelType);

  /** N > 0: a selected label's components smaller than its N-th largest are removed too (those
   * tied with it are kept). Default 0: off. */
  itkSetMacro(KeepLargestComponents, SizeValueType);
  itkGetConstMacro(KeepLargestComponents, SizeValueType);

  /** Face connectivity (off, the default) or full connectivity (on). */
  itkSetMacro(FullyConnected, bool);
  itkGetConstMacro(FullyConnected, bool);
  itkBooleanMacro(FullyConnected);

  /** Whether output 1, the mask of removed voxels, is filled. Default off. */
  itkSetMacro(GenerateRemovedMask, bool);
  itkGetConstMacro(GenerateRemovedMask, bool);
  itkBooleanMacro(GenerateRemovedMask);

  /** 1 for each removed voxel, 0 elsewhere; empty without GenerateRemovedMaskOn(). */
  MaskImageType *
  GetRemovedMask();

  /** \name What the last run found and did */
  /** @{ */
  itkGetConstReferenceMacro(LabelStatistics, LabelStatisticsMapType);
  /** The labels of GetLabelStatistics(), ascending, and each one's statistics (zeros for another label), for
   * callers without std::map of a struct (Python). */
  std::vector<LabelType>
  GetLabels() const;
  SizeValueType
  GetNumberOfComponents(LabelType label) const;
  SizeValueType
  GetNumberOfRemovedComponents(LabelType label) const;
  SizeValueType
  GetNumberOfRemovedVoxels(LabelType label) const;
  SizeValueType
  GetNumberOfGainedVoxels(LabelType label) const;
  ComponentSizeHistogramType
  GetComponentSizeHistogram(LabelType label) const;
  itkGetConstMacro(NumberOfModifiedVoxels, SizeValueType);
  itkGetConstMacro(NumberOfUnrepairableVoxels, SizeValueType);
  itkGetConstMacro(EffectiveMaximumComponentSize, SizeValueType);
  /** @} */

  using DataObjectPointerArraySizeType = ProcessObject::DataObjectPointerArraySizeType;
  using Superclass::MakeOutput;
  DataObject::Pointer
  MakeOutput(DataObjectPointerArraySizeType idx) override;

protected:
  SmallIsoComponentLabelImageFilter();
  ~SmallIsoComponentLabelImageFilter() override = default;

#if defined(ITKV4_COMPATIBILITY)
  void
  VerifyPreconditions() override;
#else
  void
  VerifyPreconditions() const override;
#endif
  void
  GenerateInputRequestedRegion() override;
  void
  EnlargeOutputRequestedRegion(DataObject *) override;
  void
  AllocateOutputs() override;
  void
  GenerateData() override;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  using Components = SmallIsoComponentDetail::LabelComponents<LabelType>;
  using RunIndex = typename Components::RunIndex;
  using Repair = SmallIsoComponentDetail::LabelRepair<LabelType, ImageDimension>;

  /** Throws, naming the first sample that is not a whole number, unless the runs found in \a labels, the voxels of
   * \a region, hold whole numbers only. */
  void
  VerifyWholeNumbers(const LabelType * labels, const RegionType & region) const;
  /** The statistics of \a label, or of none. */
  const LabelStatistics &
  StatisticsOf(LabelType label) const;
  /** K: MaximumComponentSize, or MaximumComponentVolume in voxels of \a spacing. */
  SizeValueType
  ComputeEffectiveMaximumComponentSize(const SpacingType & spacing) const;
  /** With \a copyInput, copies \a labels, the voxels of \a region, into the output's region;
   * clears the mask; line by line with the members of \a team. Returns the mask's buffer
   * (nullptr without it). */
  uint8_t *
  CopyInputAndClearMask(const LabelType *                   labels,
                        const RegionType &                  region,
                        bool                                copyInput,
                        SmallIsoComponentDetail::WorkTeam & team);
  bool
  IsSelected(LabelType label) const;
  /** What one slab's components add to the statistics, on cache lines of their own. */
  struct alignas(64) SlabCounts
  {
    LabelStatisticsMapType                          Labels;
    std::map<LabelType, std::vector<SizeValueType>> Sizes;
  };

  /** Which components are removed (marked in m_Components), with the statistics. */
  void
  DecideRemovals(SmallIsoComponentDetail::WorkTeam & team);
  /** Adds \a counts to the statistics. */
  void
  AddLabelStatistics(const LabelStatisticsMapType & counts);
  /** Counts the components whose roots are in \a slab, with their sizes for KeepLargestComponents. */
  void
  CountComponents(SizeValueType slab, SlabCounts & counts) const;
  /** Marks the selected components of \a slab that are removed, counting them. */
  void
  MarkRemovals(SizeValueType slab, const std::map<LabelType, SizeValueType> & smallestKept, SlabCounts & counts);
  void
  StopIfAborted() const;

  SizeValueType          m_MaximumComponentSize{ 20 };
  double                 m_MaximumComponentVolume{ 0.0 };
  bool                   m_UseMaximumComponentVolume{ false };
  LabelSizeMapType       m_MaximumComponentSizes;
  SelectionEnum          m_Selection{ SelectionEnum::All };
  std::vector<LabelType> m_SelectedLabels;
  LabelType              m_BackgroundValue{};
  SizeValueType          m_KeepLargestComponents{ 0 };
  bool                   m_FullyConnected{ false };
  bool                   m_GenerateRemovedMask{ false };

  Components             m_Components;
  Repair                 m_Repair;
  std::vector<LabelType> m_Part;
  LabelStatisticsMapType m_LabelStatistics;
  SizeValueType          m_NumberOfModifiedVoxels{ 0 };
  SizeValueType          m_NumberOfUnrepairableVoxels{ 0 };
  SizeValueType          m_EffectiveMaximumComponentSize{ 0 };
};
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentLabelImageFilter.hxx"
#endif

#endif
