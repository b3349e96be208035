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
#ifndef itkSmallIsoComponentBelowGrouping_h
#define itkSmallIsoComponentBelowGrouping_h

#include "itkSmallIsoComponentRunLabeling.h"
#include "SmallIsoComponentExport.h"
#include <atomic>
#include <memory>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \class BelowGrouping
 * \brief The groups of below components joined through flipped above components: the
 * below components of the image that the below pass of Side Both sees, found without
 * labelling it again. Internal to SmallIsoComponentImageFilter.
 *
 * When the above pass removes an above component, its voxels move below the isovalue: the
 * component flips, and joins the below components it touches, and through them other
 * ones. JoinNeighbors() is given the runs of the flipped components, in ranges that may be
 * joined concurrently (a lock-free union-find over components); it visits no run of the
 * other components and reads no voxel, so that it can share a loop with the repair of the
 * same runs. It finds a flipped run's neighbours in the neighbouring lines from the lines'
 * boundary bits where the labelling keeps them (dense images: a bit per voxel is read
 * instead of four bytes per run), else by a search of the run starts near where the runs
 * would be if spread evenly. Finish() then numbers the groups.
 *
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT BelowGrouping
{
public:
  using ComponentIndexType = RunLabeling::ComponentIndexType;
  using LineRun = RunLabeling::LineRun;

  /** The group of a component that belongs to none (an above component that did not flip). */
  static constexpr ComponentIndexType NoGroup = NumericTraits<ComponentIndexType>::max();

  /** A grouping of nothing: Reset() gives it a labelling. */
  BelowGrouping();
  /** Every component in a group of its own. The labeling must outlive the grouping. */
  explicit BelowGrouping(const RunLabeling & labeling);
  ~BelowGrouping();
  BelowGrouping(const BelowGrouping &) = delete;
  BelowGrouping &
  operator=(const BelowGrouping &) = delete;

  /** Every component of \a labeling (which must outlive its use here) in a group of its
   * own, in the memory of an earlier, larger labelling if there was one. */
  void
  Reset(const RunLabeling & labeling);

  /** Gives back the memory; Reset() must come before the next use. */
  void
  ReleaseMemory();

  /** Joins the components of the flipped runs [first, last) (in run order) with the
   * components of the below runs they touch. Safe to call from several threads at once. */
  void
  JoinNeighbors(const LineRun * first, const LineRun * last);

  /** The groups, once every flipped run has been joined. */
  struct Groups
  {
    /** The group of every below or flipped component (NoGroup for the other above
     * components), numbered in order of their first run. */
    std::vector<ComponentIndexType> GroupOfComponent;
    /** The number of voxels in each group. */
    std::vector<SizeValueType> GroupSize;
  };
  /** Numbers the groups of the below components and of the components flagged in
   * \a flipped (one flag per component). */
  Groups
  Finish(const std::vector<uint8_t> & flipped);
  /** The same into \a groups, whose memory is kept. */
  void
  Finish(const std::vector<uint8_t> & flipped, Groups & groups);

  /** Bytes of scratch held (with what is kept from an earlier, larger labelling). */
  SizeValueType
  GetScratchBytes() const;

private:
  /** JoinNeighbors(), the runs of the neighbouring lines found from the lines' boundary
   * bits (\a VByBits, where they are kept) or from the run starts. */
  template <bool VByBits>
  void
  JoinNeighborsOf(const LineRun * first, const LineRun * last);
  /** JoinNeighborsOf<true>() compiled for a processor with a bit-count instruction. */
  void
  JoinNeighborsByBitsWithPopcount(const LineRun * first, const LineRun * last);

  const RunLabeling *                                m_Labeling{ nullptr };
  std::unique_ptr<std::atomic<ComponentIndexType>[]> m_Parent;
  SizeValueType                                      m_Capacity{ 0 };
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
