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
#ifndef itkSmallIsoComponentImageFilter_h
#define itkSmallIsoComponentImageFilter_h

#include "itkProgressTransformer.h"
#include "itkSmallIsoComponentBelowGrouping.h"
#include "itkSmallIsoComponentDeferredFill.h"
#include "itkSmallIsoComponentImageFilterBase.h"
#include "itkSmallIsoComponentPeakMemory.h"
#include "itkSmallIsoComponentPhaseClock.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentTuning.h"
#include "itkSmallIsoComponentWorkingMemory.h"
#include <memory>
#include <vector>

namespace itk
{
/** \class SmallIsoComponentImageFilter
 * \brief Removes the components of at most K voxels on either side of an isovalue, so that
 * an isosurface extracted afterwards has no specks or bubbles.
 *
 * Every voxel is \e above the isovalue σ (f >= σ) or \e below it (f < σ, NaN included), the
 * test Marching Cubes uses. The filter finds the connected components of both sets (face
 * connectivity, 2·N neighbours, by default; FullyConnectedOn() gives 3^N - 1) and removes the
 * small ones, those of at most K voxels: each of their voxels gets a value on the other side
 * of σ, the mean of the first other-side values met along the 2·N axis directions. Every other
 * voxel keeps its value bit for bit. The input is first converted to the output pixel type
 * (static_cast, as CastImageFilter does), and the guarantees hold for the converted values.
 *
 * Parameters: IsoValue σ; MaximumComponentSize K (default 20) or MaximumComponentVolume in the
 * spacing's units cubed, whichever was set last; Side: Above removes specks, Below bubbles, Both
 * (the default) Above and then Below on its result; FullyConnected; GenerateRemovedMask;
 * InPlace (off by default; input and output of one type).
 *
 * Outputs: output 0 is the filtered image, with the input's geometry. Output 1,
 * GetRemovedMask(), is filled only with GenerateRemovedMaskOn(): 0 kept, 1 removed by the above
 * pass, 2 removed by the below pass. Statistics of the last Update(): for each side the number of
 * components, of removed components and of their voxels, and the component-size histogram (the
 * below side's describe the image the below pass saw); the voxels modified; the voxels that could
 * not be repaired (their walks all found nothing, or the output type has no value on the other
 * side, in which case the component is kept); GetPeakExtraMemoryInBytes(), GetPhaseSeconds().
 *
 * Output and statistics depend on neither the number of work units nor the threads. Working
 * memory is mostly 8 bytes per scanline run; an image of at least 2^30 voxels is swept in slabs,
 * with the same result. docs/algorithm.md states every rule in full (ties, NaN, rounding, the
 * fallback value, memory) and says how the filter works and where each step is implemented.
 *
 * \sa SmallIsoComponentImageFilterBase
 * \sa SmallIsoComponentStreamingImageFilter
 * \sa ConnectedComponentImageFilter
 * \sa RelabelComponentImageFilter
 * \sa BinaryThresholdImageFilter
 * \sa BinaryShapeOpeningImageFilter
 *
 * \ingroup SmallIsoComponent
 */
template <typename TInputImage, typename TOutputImage = TInputImage>
class ITK_TEMPLATE_EXPORT SmallIsoComponentImageFilter
  : public SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(SmallIsoComponentImageFilter);

  using Self = SmallIsoComponentImageFilter;
  using Superclass = SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  using InputImageType = typename Superclass::InputImageType;
  using OutputImageType = typename Superclass::OutputImageType;
  using InputPixelType = typename Superclass::InputPixelType;
  using OutputPixelType = typename Superclass::OutputPixelType;
  static constexpr unsigned int ImageDimension = Superclass::ImageDimension;
  using MaskPixelType = typename Superclass::MaskPixelType;
  using MaskImageType = typename Superclass::MaskImageType;
  using SideEnum = typename Superclass::SideEnum;
  using PhaseEnum = SmallIsoComponentEnums::Phase;
  /** Component size (voxels) -> number of components of that size. */
  using ComponentSizeHistogramType = typename Superclass::ComponentSizeHistogramType;

  itkNewMacro(Self);
#ifdef itkOverrideGetNameOfClassMacro
  itkOverrideGetNameOfClassMacro(SmallIsoComponentImageFilter);
#else
  itkTypeMacro(SmallIsoComponentImageFilter, SmallIsoComponentImageFilterBase);
#endif

  /** \name Statistics of the last Update()
   * The parameters, the mask and the component counts of each side are those of
   * SmallIsoComponentImageFilterBase. side is Above or Below (Both is not a side and gives an
   * exception). */
  /** @{ */
  const ComponentSizeHistogramType &
  GetComponentSizeHistogram(SideEnum side) const;
  itkGetConstMacro(NumberOfModifiedVoxels, SizeValueType);
  itkGetConstMacro(NumberOfUnrepairableVoxels, SizeValueType);
  /** Peak bytes the last Update() held beyond input, output and (when generated) mask. */
  virtual SizeValueType
  GetPeakExtraMemoryInBytes() const
  {
    return m_ExtraMemory.GetPeakInBytes();
  }
  /** Seconds of wall time the last Update() spent in \a phase (SmallIsoComponentEnums::Phase); the
   * phases' times add up to the update's after the outputs are allocated, and are 0 after a sweep. */
  double
  GetPhaseSeconds(PhaseEnum phase) const
  {
    return m_PhaseClock.GetSeconds(phase);
  }
  /** @} */

  /** \name Large images: a sweep in slabs
   * A 2-D or 3-D image of at least SlabSweepMinimumSize voxels (2^30 by default) is labelled a
   * slab of planes at a time along its last axis, with the same output, mask and statistics, bit
   * for bit, and the working memory of a window of planes; when the window would exceed half the
   * depth, the whole image is labelled (docs/algorithm.md, "The in-memory filter in slabs").
   * SetSlabThickness(T > 0) sweeps every 2-D or 3-D image in slabs of T planes; 0 (the default)
   * lets the filter decide. GetSweptSlabThickness() tells the last update's slabs (0: none). */
  /** @{ */
  itkSetMacro(SlabSweepMinimumSize, SizeValueType);
  itkGetConstMacro(SlabSweepMinimumSize, SizeValueType);
  itkSetMacro(SlabThickness, SizeValueType);
  itkGetConstMacro(SlabThickness, SizeValueType);
  itkGetConstMacro(SweptSlabThickness, SizeValueType);
  bool
  GetSweptInSlabs() const
  {
    return m_SweptSlabThickness > 0;
  }
  /** The default of SlabSweepMinimumSize, and the voxels of a slab the filter chooses. */
  static constexpr SizeValueType DefaultSlabSweepMinimumSize = 1073741824; // 2^30
  static constexpr SizeValueType ChosenSlabVoxels = 16777216;              // 2^24
  /** @} */

  /** \name Working memory kept between updates
   * The run arrays and the passes' arrays are kept after Update(), so that an update of an image
   * of the same size or smaller takes no fresh memory. ReleaseWorkingMemory() gives them back, as
   * destroying the filter does; GetWorkingMemoryInBytes() tells how much is kept. */
  /** @{ */
  void
  ReleaseWorkingMemory();
  SizeValueType
  GetWorkingMemoryInBytes() const;
  /** @} */

protected:
  SmallIsoComponentImageFilter();
  ~SmallIsoComponentImageFilter() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  /** The whole image is needed: components reach anywhere. */
  void
  GenerateInputRequestedRegion() override;
  void
  EnlargeOutputRequestedRegion(DataObject * output) override;

  void
  GenerateData() override;

  /** The counts of \a side of the last Update(). */
  typename Superclass::SideCounts
  GetSideCounts(SideEnum side) const override;

private:
  using WorkTeam = SmallIsoComponentDetail::WorkTeam;
  using RunLabeling = SmallIsoComponentDetail::RunLabeling;
  using DeferredFill = SmallIsoComponentDetail::DeferredFill;
  using LineRun = RunLabeling::LineRun;
  using BelowGrouping = SmallIsoComponentDetail::BelowGrouping;

  struct SideStatistics : Superclass::SideCounts
  {
    ComponentSizeHistogramType Histogram;
  };

  /** Kept for the next update (ReleaseWorkingMemory() gives it back). */
  using WorkingMemory = SmallIsoComponentDetail::WorkingMemory<OutputPixelType, ImageDimension>;

  SideStatistics &
  StatisticsOf(SideEnum side);
  const SideStatistics &
  StatisticsOf(SideEnum side) const;

  /** Throws unless the input, the output and the mask are one whole image each. */
  void
  VerifyBufferedRegions();

  /** Clears the statistics of the last update. */
  void
  ResetStatistics();

  /** \name The phases of GenerateData(), in order
   * Each phase reports the bytes it holds at its fullest to m_ExtraMemory. */
  /** @{ */
  /** Encodes every line of the input as runs into \a labeling, after copying it to the output
   * and clearing its mask line; for large images of one pixel type, returns the copy and the
   * clearing instead, to be done while the components are numbered. */
  DeferredFill
  EncodeRuns(WorkTeam & team, RunLabeling & labeling);

  /** Links the runs across the slabs' seams and numbers the components, keeping those of at
   * most K voxels as candidates; the work units that would wait meanwhile do \a fill. */
  void
  LinkAndNumberComponents(WorkTeam & team, RunLabeling & labeling, const DeferredFill & fill);

  /** The above pass: decides which components it removes (m_Working->RemovedAbove) and repairs
   * them; before a below pass, m_Working->Grouping joins the below components next to them. */
  void
  RemoveAbove(WorkTeam & team);

  /** Groups the below components through the above components that flipped, and flags the
   * members of the groups the below pass removes in m_Working->RemovedBelow. */
  void
  GroupBelow(WorkTeam & team);

  /** The below pass: repairs the components flagged in m_Working->RemovedBelow. The
   * voxels of those that m_Working->RemovedAbove flags were counted as modified already. */
  void
  RemoveBelow(WorkTeam & team);
  /** @} */

  /** Counts the entries in their side's statistics and flags those its pass removes in
   * \a removedAbove or \a removedBelow (nullptr: that side is not decided): at most K voxels, when
   * the pass runs and the output type has a value on the other side. sizeOf(i) is entry i's size
   * (0: no entry), isAbove(i) its side; both are called by the work units of \a team at once. */
  template <typename TSizeOf, typename TIsAbove>
  void
  DecideRemovals(WorkTeam &             team,
                 SizeValueType          entries,
                 TSizeOf &&             sizeOf,
                 TIsAbove &&            isAbove,
                 std::vector<uint8_t> * removedAbove,
                 std::vector<uint8_t> * removedBelow);

  /** DecideRemovals() over the labelling's components: one flag per component. */
  void
  DecideComponentRemovals(WorkTeam & team, std::vector<uint8_t> * removedAbove, std::vector<uint8_t> * removedBelow);

  /** The runs of the components flagged in \a removed, of \a side, into m_Working->Runs in
   * run order, the candidates shared among the work units of \a team. */
  void
  CollectRemovedRuns(WorkTeam & team, const std::vector<uint8_t> & removed, SideEnum side);

  /** Gives every voxel of \a runs (removed from \a side) a value on the other side, marks it in
   * the mask, and with \a joinFlipped joins the below components next to the runs. */
  void
  RepairRuns(WorkTeam & team, const std::vector<LineRun> & runs, SideEnum side, BelowGrouping * joinFlipped);

  /** Planes per slab for the sweep in slabs, or 0 to label the whole image at once. */
  SizeValueType
  ChooseSlabThickness() const;

  /** The whole update as a sweep in slabs of \a slabPlanes planes (SmallIsoComponentDetail::
   * StreamingSweep) over the input's buffer, into the output's (which may be the same). */
  void
  SweepInSlabs(SizeValueType slabPlanes);

  /** Whether the above pass flips components for the below pass. */
  bool
  AbovePassFlips() const;

  /** Completes a phase's share of the progress, then stops if an abort was asked for. */
  void
  EndPhase(ProgressTransformer & progress);

  /** Throws ProcessAborted when an abort was asked for (AbortGenerateDataOn()). */
  void
  StopIfAborted() const;

  SideStatistics                      m_AboveStatistics;
  SideStatistics                      m_BelowStatistics;
  SizeValueType                       m_NumberOfModifiedVoxels{ 0 };
  SizeValueType                       m_NumberOfUnrepairableVoxels{ 0 };
  SmallIsoComponentDetail::PeakMemory m_ExtraMemory;
  SmallIsoComponentDetail::PhaseClock m_PhaseClock;
  SizeValueType                       m_SlabSweepMinimumSize{ DefaultSlabSweepMinimumSize };
  SizeValueType                       m_SlabThickness{ 0 };
  SizeValueType                       m_SweptSlabThickness{ 0 };
  /** Kept between updates for its memory. */
  std::unique_ptr<WorkingMemory> m_Working;
};
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentImageFilter.hxx"
#endif

#endif
