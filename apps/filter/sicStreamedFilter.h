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
#ifndef sicStreamedFilter_h
#define sicStreamedFilter_h

#include "sicFilterReport.h"
#include "sicStreamedImageFiles.h"

#include <cstdint>
#include <functional>
#include <string>

namespace sic
{
/** Parses a byte count with an optional suffix (K, M, G, T: powers of 1024, an optional B, any
 * case), e.g. "512M", "8G", "1000000". Throws ToolError naming \a option otherwise. */
std::uint64_t
ParseByteCount(const std::string & text, const std::string & option);

/** The limit a streamed run keeps to, as its errors name it: "--memory-limit N MiB", or the share of the available
 * memory the tool took by itself. */
std::string
MemoryLimitText(const FilterSettings & settings, std::uint64_t limit);

/** The work units the streaming mode runs with: --threads, or ITK's default. */
unsigned int
StreamingWorkUnits(const FilterSettings & settings);

/** The most bytes the labelling of any plane of the image \a path takes, read through once: it grows with the
 * plane's scanline runs (maximal runs of voxels along the first axis on one side of \a isoValue), with its
 * components of runs (with the filter's connectivity, \a fullyConnected or by faces), which bound the
 * components of the volume that meet the plane, and with the voxels of those that may be small (at most \a
 * maximumSize voxels), which may be repaired. */
std::uint64_t
MostLabelBytesInAPlane(const std::string & path, double isoValue, bool fullyConnected, std::uint64_t maximumSize);

/** The bytes the process holds beside the window of planes while it streams: what it holds now (libraries, the
 * tool) and what a run adds (its threads' stacks, the readers' and writers' buffers). */
std::uint64_t
StreamingProcessBytes();

/** The bytes of memory the streaming mode holds for an image of \a geometry whose planes' labelling takes at
 * most \a labelBytesPerPlane bytes (MostLabelBytesInAPlane), slabs of \a slabPlanes planes, components of at
 * most \a maximumSize voxels and \a workUnits work units: the planes of the window (never more than the
 * image's), their voxels and their labelling, and the planes being read and written. */
std::uint64_t
StreamingWorkingBytes(const VolumeGeometry & geometry,
                      std::uint64_t          labelBytesPerPlane,
                      std::uint64_t          maximumSize,
                      std::uint64_t          slabPlanes,
                      unsigned int           workUnits);

/** The thickest slab (in planes, at most the image's depth) whose working memory fits in
 * \a budget bytes, or 0 when even slabs of one plane do not fit. */
std::uint64_t
SlabPlanesForBudget(const VolumeGeometry & geometry,
                    std::uint64_t          labelBytesPerPlane,
                    std::uint64_t          maximumSize,
                    std::uint64_t          budget,
                    unsigned int           workUnits);

/** Where a streamed run writes: the staged paths of the image and the mask (empty: none). */
struct StreamedOutputs
{
  std::string Image;
  std::string RemovedMask;
};

/** Thrown by RunStreamedFilter() when the process's peak resident size passed its memory limit before the
 * last plane: after \a Planes planes, at \a PeakBytes bytes. */
struct MemoryLimitPassed
{
  std::uint64_t Planes;
  std::uint64_t PeakBytes;
};

/** Filters \a input into the staged outputs plane by plane with slabs of \a slabPlanes planes and
 * components of at most \a maximumSize voxels, never holding the whole image; fills \a report
 * (statistics, times of reading, filtering and writing). \a progress receives the fraction done. With a
 * \a memoryLimit (bytes; 0 for none) the process's peak resident size is watched after every slab, and the run
 * stops with MemoryLimitPassed when it passes the limit. */
void
RunStreamedFilter(PlaneReader &                       input,
                  const FilterSettings &              settings,
                  const StreamedOutputs &             outputs,
                  std::uint64_t                       maximumSize,
                  std::uint64_t                       slabPlanes,
                  std::uint64_t                       memoryLimit,
                  const std::function<void(double)> & progress,
                  FilterReport &                      report);
} // namespace sic

#endif
