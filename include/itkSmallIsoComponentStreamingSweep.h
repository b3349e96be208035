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
#ifndef itkSmallIsoComponentStreamingSweep_h
#define itkSmallIsoComponentStreamingSweep_h

#include "itkSmallIsoComponentBlockSummary.h"
#include "itkSmallIsoComponentRunLabeling.h"
#include "itkSmallIsoComponentRunEncoder.h"
#include "itkSmallIsoComponentWorkTeam.h"
#include "itkSmallIsoComponentTuning.h"
#include <deque>
#include <functional>
#include <memory>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class StreamingSweep
 * \brief The filter's result computed plane by plane along the slowest axis, holding only a
 * window of planes: input planes go in, in order, and each output plane comes out as soon as it
 * is final, bit for bit what the in-memory filter gives, with the same statistics.
 *
 * The image is seen as a 3-D box of Size voxels whose planes are along axis 2 (a 2-D image of
 * nx by ny voxels is the box {nx, 1, ny}, whose planes are its lines). Planes are labelled a slab
 * of SlabPlanes at a time with the run labelling; each slab's summary (BlockSummary) is merged
 * into the summary of everything before it, which settles the components that the new slab
 * completes. A component is decided when it is complete, or earlier when it has more than K
 * voxels (it stays then); the voxels of a removed one are repaired at once, from the planes it
 * spans and the one on either side, all still in the window. A plane is given out once every
 * component that has voxels in it is decided and repaired, and dropped once the plane after it is
 * given out. A small component spans at most K planes and a below group of Side Both is decided
 * at most about 2K + 3 planes after its first one, so the window holds about 2K + 3 planes plus a
 * slab (docs/algorithm.md derives the bound), whatever the depth of the image.
 *
 * With two work units or more, each slab is labelled on a background thread (BackgroundTask, with
 * the work units but one) while the calling thread merges the slab before it, repairs and gives
 * out planes; the window then holds one slab more. Planes are always given out on the calling
 * thread, in order, and the output and statistics do not depend on the work units.
 *
 * Internal to the module: SmallIsoComponentStreamingImageFilter and the command-line tool use it.
 * \ingroup SmallIsoComponent
 */
template <typename TPixel>
class ITK_TEMPLATE_EXPORT StreamingSweep
{
public:
  using IndexType = BlockSummary::IndexType;
  using PixelType = TPixel;
  /** Called with each output plane in order: its index along axis 2, its voxels (x fastest),
   * and the removed-voxel mask of the plane (nullptr unless the mask was asked for). The mask's
   * two low bits are the filter's mask value (0 kept, 1 removed in the above pass, 2 in the below
   * pass); bit value 4 marks a voxel that got the fallback value in the above pass (every walk
   * left the image or stopped on NaN), 8 one that got it in the below pass. */
  using PlaneCallback = std::function<void(uint64_t plane, const TPixel * values, const uint8_t * mask)>;

  StreamingSweep(const IndexType &            size,
                 double                       isoValue,
                 uint64_t                     maximumComponentSize,
                 SmallIsoComponentEnums::Side side,
                 bool                         fullyConnected,
                 uint64_t                     slabPlanes,
                 bool                         withMask,
                 MultiThreaderBase *          threader,
                 unsigned int                 workUnits,
                 PlaneCallback                emit);
  ~StreamingSweep();
  StreamingSweep(const StreamingSweep &) = delete;
  StreamingSweep &
  operator=(const StreamingSweep &) = delete;

  /** Takes the next \a planes planes of input (voxels x fastest); any number at a time. */
  void
  Push(const TPixel * values, uint64_t planes);
  /** After the last plane: settles and gives out everything left. */
  void
  Finish();

  /** Planes given out so far. */
  uint64_t
  GetNumberOfPlanesOut() const
  {
    return m_NextPlaneOut;
  }

  /** The statistics (valid after Finish()): the components' tally, and the voxels that got the
   * fallback value because every walk left the image. */
  const ComponentTally &
  GetTally() const
  {
    return m_Summary->GetTally();
  }
  uint64_t
  GetNumberOfFallbackVoxels() const
  {
    return m_FallbackVoxels;
  }
  /** Most bytes held at once (input planes, labellings, summaries, repairs). */
  uint64_t
  GetPeakMemoryInBytes() const
  {
    return m_PeakMemoryInBytes;
  }

  /** Most planes held at once (labelled and not dropped yet, and taken but not labelled yet). */
  uint64_t
  GetPeakWindowPlanes() const
  {
    return m_PeakWindowPlanes;
  }

  /** A bound on the planes the sweep holds at once, for components of at most
   * \a maximumComponentSize voxels, slabs of \a slabPlanes planes and \a workUnits work units:
   * 2K + 4 + 2T planes with one work unit, 2K + 4 + 3T with more (a slab more is labelled while
   * the one before it is merged). It is also how many planes beyond a plane the sweep may need
   * before it gives that plane out. */
  static uint64_t
  WindowPlanes(uint64_t maximumComponentSize, uint64_t slabPlanes, unsigned int workUnits);

private:
  struct Slab;
  using Resolution = BlockSummary::Resolution;
  using State = BlockSummary::State;

  struct HeldMemory
  {
    uint64_t Bytes{ 0 };
    uint64_t Planes{ 0 };
  };

  /** Takes the pending planes as the next slab: merges the slab labelled before while it labels
   * this one. */
  void
  ProcessSlab();
  /** Labels \a slab on its own, finds its candidate runs and summarizes it. */
  void
  LabelSlab(Slab & slab, unsigned int workUnits) const;
  /** Merges the labelled \a slab into the summary, repairs what is decided, gives out what is
   * ready. */
  void
  MergeSlab(std::unique_ptr<Slab> slab);
  void
  Follow(Slab & slab, SizeValueType component, const Resolution & resolution);
  void
  RepairDecided();
  void
  RepairComponent(Slab & slab, SizeValueType component, bool abovePass);
  void
  EmitReadyPlanes();
  /** The slab holding plane \a z (which the window holds). */
  Slab &
  SlabOf(uint64_t z);
  /** Whether voxel (x, y, z) is below the isovalue as the below pass sees it (after the above
   * pass), and its value. */
  bool
  IsBelowAfterAbovePass(uint64_t x, uint64_t y, uint64_t z, TPixel & value);
  HeldMemory
  GetHeldMemory() const;
  void
  UpdateMemory();

  IndexType           m_Size;
  uint64_t            m_PlaneVoxels;
  Threshold<TPixel>   m_Threshold;
  RunEncoder<TPixel>  m_Encoder;
  ComponentRules      m_Rules;
  uint64_t            m_SlabPlanes;
  bool                m_WithMask;
  MultiThreaderBase * m_Threader;
  unsigned int        m_WorkUnits;
  PlaneCallback       m_Emit;

  std::vector<TPixel>                m_Pending;
  std::vector<std::unique_ptr<Slab>> m_SpareSlabs;
  uint64_t                           m_PlanesIn{ 0 };
  uint64_t                           m_NextPlaneOut{ 0 };
  std::deque<std::unique_ptr<Slab>>  m_Window;
  /** The last slab taken: labelled, merged when the next one is taken (or at Finish()). */
  std::unique_ptr<Slab>         m_Labelled;
  BackgroundTask                m_Labeller;
  uint64_t                      m_MergePeakBytes{ 0 };
  uint64_t                      m_MergePeakPlanes{ 0 };
  std::unique_ptr<BlockSummary> m_Summary;
  uint64_t                      m_FallbackVoxels{ 0 };
  uint64_t                      m_PeakMemoryInBytes{ 0 };
  uint64_t                      m_PeakWindowPlanes{ 0 };
  std::vector<TPixel>           m_OutputPlane;
  std::vector<uint8_t>          m_MaskPlane;
};

/** Copies \a voxels values of a mask plane as StreamingSweep gives it into \a out as the filter's
 * mask values (0, 1 or 2), without the marks of the fallback value. */
template <typename TMaskPixel>
void
CopyRemovedMask(const uint8_t * planeMask, std::size_t voxels, TMaskPixel * out)
{
  for (std::size_t v = 0; v < voxels; ++v)
  {
    out[v] = static_cast<TMaskPixel>(planeMask[v] & 3);
  }
}

/** Filters the box of \a extent voxels at \a values (x fastest) as if it were the whole image, and
 * writes the output and the mask (as StreamingSweep gives it, fallback bits included; nullptr for
 * none) of its part [cropBegin, cropEnd), x fastest. When the box reaches BoxHalo() voxels beyond
 * the part on every side where it does not end at the image's border, the part is exactly what
 * filtering the whole image gives there: this is how a chunk of the chunked mode is filtered. */
template <typename TPixel>
void
FilterBoxPart(const TPixel *                  values,
              const BlockSummary::IndexType & extent,
              const BlockSummary::IndexType & cropBegin,
              const BlockSummary::IndexType & cropEnd,
              double                          isoValue,
              uint64_t                        maximumComponentSize,
              SmallIsoComponentEnums::Side    side,
              bool                            fullyConnected,
              MultiThreaderBase *             threader,
              unsigned int                    workUnits,
              TPixel *                        output,
              uint8_t *                       mask);
} // namespace SmallIsoComponentDetail
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkSmallIsoComponentStreamingSweep.hxx"
#endif

#endif
