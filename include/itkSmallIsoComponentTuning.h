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
#ifndef itkSmallIsoComponentTuning_h
#define itkSmallIsoComponentTuning_h

#include "itkIntTypes.h"

#include <chrono>
#include <cstddef>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** The engine's tuning constants, all in one place. None changes a result; each was set with
 * the benchmark (docs/performance.md), and its line says what it trades. */
namespace Tuning
{
/** Voxel bytes per block the encoder's caller fills just before the encoder reads them: small
 * enough to be still in the cache when read, large enough to call the caller rarely. */
constexpr SizeValueType EncoderBlockBytes = 32768;

/** Slabs of lines per work unit in the labelling: more balance the load, fewer leave fewer
 * seams to link serially. */
constexpr unsigned int SlabsPerWorkUnit = 4;

/** Runs from which the numbering is shared between work units: below, a serial numbering
 * leaves the other work units free to write the output beside it. */
constexpr SizeValueType MinimumRunsToShareNumbering = SizeValueType{ 1 } << 20;

/** Output and mask bytes per run up to which the numbering is shared while the output is
 * written: above, writing is the longer work and takes every other work unit. */
constexpr SizeValueType FillBytesPerRunToShareNumbering = 16;

/** Lines per claim in a shared numbering: larger claims cost fewer atomic operations, smaller
 * ones balance the two ends better. */
constexpr SizeValueType LinesPerClaim = 64;

/** Lines the first stage of a shared numbering numbers between two publications of how far it
 * got, which the second stage waits on: fewer atomic stores against a longer wait. */
constexpr SizeValueType NumberingLinesPerStep = 16;

/** Runs the collection of candidate runs buffers before it appends them to its vector: one
 * append per buffer instead of one per run, with a buffer that stays cached. */
constexpr SizeValueType CandidateBufferRuns = 256;

/** A label map's run arrays are reserved for a run per this many voxels before they are
 * written: real maps have fewer runs, so a first update does not grow them (an array that grows
 * can leave its old blocks resident), and what is reserved but not written is address space,
 * not memory. */
constexpr SizeValueType VoxelsPerReservedLabelRun = 8;

/** Runs per 64 voxels (over two lines) from which two lines are linked through their boundary
 * bits rather than by a merge of their runs. */
constexpr SizeValueType BitsRunsPerWord = 6;

/** Bytes of boundary bits a work unit keeps for the lines before its line: the second-level
 * cache, against encoding a line's bits again. */
constexpr SizeValueType BitsCacheBytes = SizeValueType{ 1 } << 20;

/** How far from its guess the search for the run holding a voxel looks first. */
constexpr SizeValueType NearRuns = 16;

/** Runs from which the loops over removed or flipped runs prefetch what a run reads: below,
 * the run arrays fit the second-level cache and the requests only cost (docs/performance.md,
 * "Prefetches"). */
constexpr SizeValueType PrefetchMinimumRuns = SizeValueType{ 1 } << 20;

/** How many runs ahead those loops prefetch: far enough to hide memory latency, near enough
 * that the lines are still cached when used. */
constexpr SizeValueType PrefetchRunsAhead = 8;

/** How many runs ahead the grouping prefetches the neighbouring lines' run tables: twice
 * PrefetchRunsAhead, so that they have arrived when their runs are requested. */
constexpr SizeValueType PrefetchLineTablesAhead = 2 * PrefetchRunsAhead;

/** Output and mask bytes per block of the deferred fill, the unit its work units take:
 * smaller blocks share the fill more evenly, larger ones cost fewer hand-outs. */
constexpr SizeValueType FillBlockBytes = SizeValueType{ 256 } << 10;

/** Output and mask bytes from which they are written with streaming stores (twice a core's
 * second-level cache): they would not stay cached, and streaming skips reading each line. */
constexpr SizeValueType StreamingThresholdInBytes = SizeValueType{ 4 } << 20;

/** Bytes from which arrays are asked for huge pages: far fewer page faults, against memory
 * touched at the end of the last huge page that a smaller array would not touch. */
constexpr SizeValueType LargeBlockBytes = SizeValueType{ 4 } << 20;

/** Slabs a sweep keeps with their arrays for the next slab: fewer allocations against the
 * memory of one slab. */
constexpr std::size_t MaximumSpareSlabs = 1;

/** Cheap items (runs to repair or group) from which a loop is shared: waking the threader's
 * pool costs more than it saves on fewer. */
constexpr SizeValueType MinimumItemsToShare = 2048;

/** The same when the team's helpers are awake already. */
constexpr SizeValueType MinimumItemsToShareWithHelpers = 256;

/** Chunks per work unit of a shared loop over cheap items: balance against hand-out cost. */
constexpr SizeValueType ChunksPerWorkUnit = 32;

/** How long an idle helper keeps checking for the next loop before it sleeps: longer than the
 * serial steps between an update's loops on real volumes, against a core kept busy. */
constexpr auto HelperSpinTime = std::chrono::microseconds(1000);
} // namespace Tuning
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
