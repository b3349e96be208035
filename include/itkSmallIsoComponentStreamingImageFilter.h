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
#ifndef itkSmallIsoComponentStreamingImageFilter_h
#define itkSmallIsoComponentStreamingImageFilter_h

#include "itkSmallIsoComponentImageFilterBase.h"
#include "itkSmallIsoComponentStreamingSweep.h"
#include <deque>
#include <memory>

namespace itk
{
/** \class SmallIsoComponentStreamingImageFilter
 * \brief SmallIsoComponentImageFilter for images larger than memory: the same output, mask and
 * statistics, computed from slabs of input along the slowest axis and given out in slabs.
 *
 * Connect it to a reader that can stream (MetaImage reads any region of an uncompressed file) and
 * let a streaming writer pull its output in pieces (ImageFileWriter::SetNumberOfStreamDivisions(),
 * or StreamingImageFilter): each piece is a range of planes along the last axis, and the filter
 * asks its input only for the planes it has not seen yet, up to a bounded distance beyond the
 * piece. Pieces are expected in order, as ITK's writers ask for them; a request for an earlier
 * piece starts the sweep again from the first plane (correct, but the work is done again). Memory:
 * a window of at most 2K + 4 + 3 SlabThickness planes (2K + 4 + 2 SlabThickness with one work unit: with
 * more, the next slab is labelled while the one before is merged) with their run labelling, whatever the
 * image's depth (see SmallIsoComponentDetail::StreamingSweep and docs/algorithm.md).
 *
 * Parameters and statistics are those of SmallIsoComponentImageFilter (IsoValue,
 * MaximumComponentSize or MaximumComponentVolume, Side, FullyConnected, GenerateRemovedMask: see
 * SmallIsoComponentImageFilterBase); the statistics are valid once the last plane has been given
 * out. With GenerateRemovedMaskOn(), output 1 is the removed-voxel mask of each piece (the same
 * planes as output 0); without it (the default) the filter keeps no mask planes and output 1 has
 * an empty buffered region in every piece. Images of two and three dimensions; the input is
 * converted to the output pixel type first. The filter never runs in place (CanRunInPlace() is
 * false): the planes it gives out are not the ones its input holds at the time.
 *
 * \sa SmallIsoComponentImageFilter
 * \ingroup SmallIsoComponent
 */
template <typename TInputImage, typename TOutputImage = TInputImage>
class ITK_TEMPLATE_EXPORT SmallIsoComponentStreamingImageFilter
  : public SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(SmallIsoComponentStreamingImageFilter);

  using Self = SmallIsoComponentStreamingImageFilter;
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
  using ComponentSizeHistogramType = typename Superclass::ComponentSizeHistogramType;

  static_assert(ImageDimension == 2 || ImageDimension == 3,
                "SmallIsoComponentStreamingImageFilter handles images of two or three dimensions.");

  itkNewMacro(Self);
#ifdef itkOverrideGetNameOfClassMacro
  itkOverrideGetNameOfClassMacro(SmallIsoComponentStreamingImageFilter);
#else
  itkTypeMacro(SmallIsoComponentStreamingImageFilter, SmallIsoComponentImageFilterBase);
#endif

  /** Planes labelled at a time (at least 1; default 8): thicker slabs cost memory, thinner ones
   * more merges. */
  itkSetClampMacro(SlabThickness, SizeValueType, 1, NumericTraits<SizeValueType>::max());
  itkGetConstMacro(SlabThickness, SizeValueType);

  /** The filter never runs in place: InPlaceOn() has no effect. */
  bool
  CanRunInPlace() const override;

  /** \name Statistics, valid once the last plane has been given out
   * The component counts of each side are those of SmallIsoComponentImageFilterBase. */
  /** @{ */
  ComponentSizeHistogramType
  GetComponentSizeHistogram(SideEnum side) const;
  SizeValueType
  GetNumberOfModifiedVoxels() const;
  SizeValueType
  GetNumberOfUnrepairableVoxels() const;
  /** Most bytes the sweep held at once (planes, labellings, summaries, repairs, planes ready). */
  itkGetConstMacro(PeakMemoryInBytes, SizeValueType);
  /** Whether the statistics describe the whole image (every plane has been given out). */
  itkGetConstMacro(Complete, bool);
  /** @} */

protected:
  SmallIsoComponentStreamingImageFilter() = default;
  ~SmallIsoComponentStreamingImageFilter() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;
  /** Pieces are whole planes. */
  void
  EnlargeOutputRequestedRegion(DataObject * output) override;
  /** The planes not seen yet, up to the window's reach beyond the piece. */
  void
  GenerateInputRequestedRegion() override;
  void
  GenerateData() override;

  /** The counts of \a side; throws before the first run. */
  typename Superclass::SideCounts
  GetSideCounts(SideEnum side) const override;

private:
  using SweepType = SmallIsoComponentDetail::StreamingSweep<OutputPixelType>;
  struct ReadyPlane
  {
    uint64_t                     Plane;
    std::vector<OutputPixelType> Values;
    std::vector<MaskPixelType>   Mask; // empty without GenerateRemovedMask
  };
  /** Bytes a ready plane holds. */
  static SizeValueType
  BytesOf(const ReadyPlane & ready);
  /** Keeps a plane the sweep gives out (its mask, when there is one, without the fallback
   * marks) until a piece asks for it. */
  void
  KeepReadyPlane(uint64_t plane, const OutputPixelType * values, const uint8_t * mask);

  /** The requested planes [first, end) of output 0. */
  void
  RequestedPlanes(uint64_t & first, uint64_t & end) const;
  const SmallIsoComponentDetail::SideTally &
  TallyOf(SideEnum side) const;
  void
  StartSweep();

  SizeValueType m_SlabThickness{ 8 };

  std::unique_ptr<SweepType> m_Sweep;
  ModifiedTimeType           m_SweepTime{ 0 };
  uint64_t                   m_PlanesTaken{ 0 };
  uint64_t                   m_PlanesGiven{ 0 };
  uint64_t                   m_InputEnd{ 0 };
  std::deque<ReadyPlane>     m_Ready;
  SizeValueType              m_ReadyBytes{ 0 };
  SizeValueType              m_PeakMemoryInBytes{ 0 };
  bool                       m_Complete{ false };
};
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentStreamingImageFilter.hxx"
#endif

#endif
