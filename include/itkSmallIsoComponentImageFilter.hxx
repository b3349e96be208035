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
#ifndef itkSmallIsoComponentImageFilter_hxx
#define itkSmallIsoComponentImageFilter_hxx

#include "itkSmallIsoComponentImageFilter.h"
#include "itkMath.h"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <numeric>
#if defined(__SSE2__)
#  include <emmintrin.h>
#endif

namespace itk
{
namespace SmallIsoComponentDetail
{
template <typename T>
bool
IsNaN(T value)
{
  if constexpr (std::is_floating_point<T>::value)
  {
    return std::isnan(value);
  }
  else
  {
    (void)value;
    return false;
  }
}

/** Counts components by size: the many small sizes in an array, the few large ones in
 * the histogram itself, so that millions of components cost no tree look-ups. */
class SizeCounter
{
public:
  void
  Add(SizeValueType size)
  {
    if (size < m_Small.size())
    {
      ++m_Small[size];
    }
    else
    {
      ++m_Large[size];
    }
  }

  std::map<SizeValueType, SizeValueType>
  Histogram() const
  {
    std::map<SizeValueType, SizeValueType> histogram = m_Large;
    for (SizeValueType size = 0; size < m_Small.size(); ++size)
    {
      if (m_Small[size] > 0)
      {
        histogram[size] = m_Small[size];
      }
    }
    return histogram;
  }

private:
  std::vector<SizeValueType>             m_Small = std::vector<SizeValueType>(4096, 0);
  std::map<SizeValueType, SizeValueType> m_Large;
};

/** Images whose output and mask together take at least this many bytes (twice a core's
 * level-2 cache on the machines measured) are written with streaming stores when the runs
 * are encoded: they would not stay in the caches anyway, and streaming saves reading every
 * written cache line from memory first. */
constexpr SizeValueType StreamingThresholdInBytes = SizeValueType{ 4 } << 20;

/** Copies \a bytes from \a source to \a destination, with streaming stores where
 * SSE2 has them: whole 64-byte cache lines only, the partial lines at both ends with
 * ordinary stores (a partly streamed line costs more than it saves). */
inline void
StreamCopy(void * destination, const void * source, SizeValueType bytes)
{
#if defined(__SSE2__)
  auto *       d = static_cast<char *>(destination);
  const auto * s = static_cast<const char *>(source);
  const auto   head = std::min<SizeValueType>(bytes, (64 - reinterpret_cast<uintptr_t>(d) % 64) % 64);
  std::memcpy(d, s, head);
  for (d += head, s += head, bytes -= head; bytes >= 64; d += 64, s += 64, bytes -= 64)
  {
    const __m128i v0 = _mm_loadu_si128(reinterpret_cast<const __m128i *>(s));
    const __m128i v1 = _mm_loadu_si128(reinterpret_cast<const __m128i *>(s + 16));
    const __m128i v2 = _mm_loadu_si128(reinterpret_cast<const __m128i *>(s + 32));
    const __m128i v3 = _mm_loadu_si128(reinterpret_cast<const __m128i *>(s + 48));
    _mm_stream_si128(reinterpret_cast<__m128i *>(d), v0);
    _mm_stream_si128(reinterpret_cast<__m128i *>(d + 16), v1);
    _mm_stream_si128(reinterpret_cast<__m128i *>(d + 32), v2);
    _mm_stream_si128(reinterpret_cast<__m128i *>(d + 48), v3);
  }
  std::memcpy(d, s, bytes);
#else
  std::memcpy(destination, source, bytes);
#endif
}

/** Sets \a bytes at \a destination to zero, with streaming stores for the whole cache
 * lines where SSE2 has them. */
inline void
StreamZero(void * destination, SizeValueType bytes)
{
#if defined(__SSE2__)
  auto *     d = static_cast<char *>(destination);
  const auto head = std::min<SizeValueType>(bytes, (64 - reinterpret_cast<uintptr_t>(d) % 64) % 64);
  std::memset(d, 0, head);
  const __m128i zero = _mm_setzero_si128();
  for (d += head, bytes -= head; bytes >= 64; d += 64, bytes -= 64)
  {
    _mm_stream_si128(reinterpret_cast<__m128i *>(d), zero);
    _mm_stream_si128(reinterpret_cast<__m128i *>(d + 16), zero);
    _mm_stream_si128(reinterpret_cast<__m128i *>(d + 32), zero);
    _mm_stream_si128(reinterpret_cast<__m128i *>(d + 48), zero);
  }
  std::memset(d, 0, bytes);
#else
  std::memset(destination, 0, bytes);
#endif
}

/** Makes this thread's streaming stores visible before it hands its work back. */
inline void
StreamFence()
{
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

/** Asks for the cache line at \a address ahead of its use; a hint only. */
inline void
Prefetch(const void * address)
{
#if defined(__GNUC__)
  __builtin_prefetch(address);
#else
  (void)address;
#endif
}

/** Output and mask bytes per block when they are written while the components are
 * numbered. */
constexpr SizeValueType FillBlockBytes = SizeValueType{ 256 } << 10;

/** How many removed runs ahead the repair requests the voxels it will read. */
constexpr SizeValueType PrefetchDistance = 8;

/** A mean of values of type T, as T: rounded half up for integers. */
template <typename T>
T
MeanToPixel(double mean)
{
  if constexpr (std::is_integral<T>::value)
  {
    return static_cast<T>(Math::Round<int64_t>(mean));
  }
  else
  {
    return static_cast<T>(mean);
  }
}
} // namespace SmallIsoComponentDetail

template <typename TInputImage, typename TOutputImage>
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::SmallIsoComponentImageFilter()
{
  this->SetNumberOfRequiredOutputs(2);
  this->SetNthOutput(1, this->MakeOutput(1));
  this->InPlaceOff();
}

template <typename TInputImage, typename TOutputImage>
DataObject::Pointer
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::MakeOutput(DataObjectPointerArraySizeType idx)
{
  if (idx == 1)
  {
    return MaskImageType::New().GetPointer();
  }
  return Superclass::MakeOutput(idx);
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GetRemovedMask() -> MaskImageType *
{
  return itkDynamicCastInDebugMode<MaskImageType *>(this->ProcessObject::GetOutput(1));
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::SetMaximumComponentSize(SizeValueType size)
{
  if (m_MaximumComponentSize != size || m_UseMaximumComponentVolume)
  {
    m_MaximumComponentSize = size;
    m_UseMaximumComponentVolume = false;
    this->Modified();
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::SetMaximumComponentVolume(double volume)
{
  if (Math::NotExactlyEquals(m_MaximumComponentVolume, volume) || !m_UseMaximumComponentVolume)
  {
    m_MaximumComponentVolume = volume;
    m_UseMaximumComponentVolume = true;
    this->Modified();
  }
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::StatisticsOf(SideEnum side) const -> const SideStatistics &
{
  switch (side)
  {
    case SideEnum::Above:
      return m_AboveStatistics;
    case SideEnum::Below:
      return m_BelowStatistics;
    default:
      itkExceptionMacro("Statistics are kept per side: ask for SideEnum::Above or SideEnum::Below, not " << side);
  }
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GetNumberOfComponents(SideEnum side) const
{
  return this->StatisticsOf(side).Components;
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GetNumberOfRemovedComponents(SideEnum side) const
{
  return this->StatisticsOf(side).RemovedComponents;
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GetNumberOfRemovedVoxels(SideEnum side) const
{
  return this->StatisticsOf(side).RemovedVoxels;
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GetComponentSizeHistogram(SideEnum side) const
  -> const ComponentSizeHistogramType &
{
  return this->StatisticsOf(side).Histogram;
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::VerifyPreconditions()
#if !defined(ITKV4_COMPATIBILITY)
  const
#endif
{
  Superclass::VerifyPreconditions();
  if (std::isnan(m_IsoValue))
  {
    itkExceptionMacro("IsoValue is NaN; it must be a number (every voxel is compared with it).");
  }
  if (m_UseMaximumComponentVolume && !(m_MaximumComponentVolume >= 0.0))
  {
    itkExceptionMacro("MaximumComponentVolume is "
                      << m_MaximumComponentVolume << "; it must be a volume >= 0 in the image's physical units cubed.");
  }
  if (m_Side != SideEnum::Above && m_Side != SideEnum::Below && m_Side != SideEnum::Both)
  {
    itkExceptionMacro("Side is " << static_cast<int>(m_Side) << "; it must be Above, Below or Both.");
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  if (auto * input = const_cast<InputImageType *>(this->GetInput()))
  {
    input->SetRequestedRegionToLargestPossibleRegion();
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::EnlargeOutputRequestedRegion(DataObject *)
{
  for (unsigned int i = 0; i < this->GetNumberOfIndexedOutputs(); ++i)
  {
    if (DataObject * output = this->ProcessObject::GetOutput(i))
    {
      output->SetRequestedRegionToLargestPossibleRegion();
    }
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::CheckAbort(float progress)
{
  this->UpdateProgress(progress);
  if (this->GetAbortGenerateData())
  {
    ProcessAborted abort(__FILE__, __LINE__);
    abort.SetDescription("SmallIsoComponentImageFilter: aborted by the user");
    throw abort;
  }
}

template <typename TInputImage, typename TOutputImage>
std::function<void(SizeValueType, SizeValueType)>
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::EncodeRuns(SmallIsoComponentRunLabeling & labeling,
                                                                    const InputImageType *         input,
                                                                    OutputImageType *              output,
                                                                    MaskImageType *                mask)
{
  MaskPixelType *        maskBuffer = mask->GetBufferPointer();
  const InputPixelType * inBuffer = input->GetBufferPointer();
  OutputPixelType *      outBuffer = output->GetBufferPointer();
  const bool             copy = static_cast<const void *>(inBuffer) != static_cast<const void *>(outBuffer);
  const SizeValueType    length = labeling.GetLineLength();
  const SizeValueType    voxels = length * labeling.GetNumberOfLines();
  const bool             stream =
    voxels * (sizeof(OutputPixelType) + sizeof(MaskPixelType)) >= SmallIsoComponentDetail::StreamingThresholdInBytes;
  const SmallIsoComponentThreshold<OutputPixelType> threshold(m_IsoValue);
  // The output and the mask are filled block by block (whole lines, contiguous in
  // memory) just before the block's lines are encoded.
  if constexpr (std::is_same<InputPixelType, OutputPixelType>::value)
  {
    if (stream)
    {
      // The output would not stay in the caches: the lines are encoded from the input,
      // which holds the same values, and the output and the mask are written later,
      // with streaming stores, while the components are numbered (a serial step that
      // leaves the other work units free).
      threshold.Encode(inBuffer, labeling, this->GetMultiThreader(), [](SizeValueType, SizeValueType) {});
      return [=](SizeValueType first, SizeValueType end) {
        if (copy)
        {
          SmallIsoComponentDetail::StreamCopy(
            outBuffer + first * length, inBuffer + first * length, (end - first) * length * sizeof(OutputPixelType));
        }
        SmallIsoComponentDetail::StreamZero(maskBuffer + first * length,
                                            (end - first) * length * sizeof(MaskPixelType));
        SmallIsoComponentDetail::StreamFence();
      };
    }
  }
  threshold.Encode(
    outBuffer,
    labeling,
    this->GetMultiThreader(),
    [&](SizeValueType first, SizeValueType end) {
      const InputPixelType * in = inBuffer + first * length;
      OutputPixelType *      out = outBuffer + first * length;
      const SizeValueType    count = (end - first) * length;
      if constexpr (std::is_same<InputPixelType, OutputPixelType>::value)
      {
        if (copy)
        {
          std::memcpy(out, in, count * sizeof(OutputPixelType));
        }
      }
      else
      {
        std::transform(in, in + count, out, [](InputPixelType v) { return static_cast<OutputPixelType>(v); });
      }
      if (stream)
      {
        SmallIsoComponentDetail::StreamZero(maskBuffer + first * length, count * sizeof(MaskPixelType));
      }
      else
      {
        std::memset(maskBuffer + first * length, 0, count * sizeof(MaskPixelType));
      }
    },
    [stream] {
      if (stream)
      {
        SmallIsoComponentDetail::StreamFence();
      }
    });
  return nullptr;
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::Repair(
  const SmallIsoComponentRunLabeling &                       labeling,
  const std::vector<uint8_t> &                               removedComponent,
  const std::vector<SmallIsoComponentRunLabeling::LineRun> & runs,
  bool                                                       removedAreAbove,
  MaskPixelType                                              maskValue,
  OutputImageType *                                          output,
  MaskImageType *                                            mask,
  const OutputPixelType *                                    source,
  const std::function<void(SizeValueType, SizeValueType)> &  alongside,
  SizeValueType                                              alongsideBytes)
{
  using namespace SmallIsoComponentDetail;
  const SmallIsoComponentThreshold<OutputPixelType> threshold(m_IsoValue);
  const OutputPixelType fallback = removedAreAbove ? threshold.HighestBelow() : threshold.LowestAbove();

  if (runs.empty())
  {
    return 0;
  }

  const auto &    size = output->GetBufferedRegion().GetSize();
  OffsetValueType stride[ImageDimension];
  stride[0] = 1;
  for (unsigned int a = 1; a < ImageDimension; ++a)
  {
    stride[a] = stride[a - 1] * static_cast<OffsetValueType>(size[a - 1]);
  }
  OutputPixelType * buffer = output->GetBufferPointer();
  // The values are read from \a source, which holds the output's values before the pass.
  const OutputPixelType * const read = source != nullptr ? source : buffer;
  const auto                    sameSide = [&](OutputPixelType v) { return threshold.IsAbove(v) == removedAreAbove; };

  // New values are computed, in chunks of runs, before any is written: walks read the
  // values before the pass.
  // A few removed runs are repaired by the calling thread alone: handing them to other
  // threads costs more than it saves.
  const SizeValueType chunks = labeling.GetNumberOfChunks(runs.size(), this->GetMultiThreader());
  const auto          forEachChunk = [this, &labeling, chunks](auto && function) {
    labeling.Parallelize(this->GetMultiThreader(), chunks, function);
  };
  const auto chunkBegin = [&](SizeValueType chunk) { return chunk * runs.size() / chunks; };
  std::vector<std::vector<OutputPixelType>> values(chunks);
  std::vector<SizeValueType>                unrepairable(chunks, 0);
  const SizeValueType                       voxels = output->GetBufferedRegion().GetNumberOfPixels();
  // The removed runs are few and far apart: each one's voxels and their neighbours along
  // the other axes are usually not in cache. Requesting them a few runs ahead overlaps
  // the waits.
  using LineRun = SmallIsoComponentRunLabeling::LineRun;
  const auto firstVoxel = [&](const LineRun & run) { return run.Line * size[0] + labeling.GetRunStart(run.Run); };
  // Calls visit(run) for the runs of a chunk in order, and prefetch(run) for the run
  // PrefetchDistance ahead of each.
  const auto forEachRunOf = [&](SizeValueType chunk, auto && prefetch, auto && visit) {
    const SizeValueType begin = chunkBegin(chunk);
    const SizeValueType end = chunkBegin(chunk + 1);
    for (SizeValueType i = begin; i < std::min(end, begin + PrefetchDistance); ++i)
    {
      prefetch(runs[i]);
    }
    for (SizeValueType i = begin; i < end; ++i)
    {
      if (i + PrefetchDistance < end)
      {
        prefetch(runs[i + PrefetchDistance]);
      }
      visit(runs[i]);
    }
  };
  const auto prefetchNeighbors = [&](const LineRun & ahead) {
    const SizeValueType first = firstVoxel(ahead);
    Prefetch(read + first);
    for (unsigned int a = 1; a < ImageDimension; ++a)
    {
      const auto step = static_cast<SizeValueType>(stride[a]);
      if (first >= step)
      {
        Prefetch(read + first - step);
      }
      if (first + step < voxels)
      {
        Prefetch(read + first + step);
      }
    }
  };
  forEachChunk([&](SizeValueType chunk) {
    const SizeValueType length = size[0];
    auto &              chunkValues = values[chunk];
    chunkValues.reserve(2 * (chunkBegin(chunk + 1) - chunkBegin(chunk)));
    forEachRunOf(chunk, prefetchNeighbors, [&](const LineRun & removed) {
      // The run's coordinates along axes 1..N-1.
      SizeValueType coordinates[ImageDimension];
      SizeValueType rest = removed.Line;
      for (unsigned int a = 1; a < ImageDimension; ++a)
      {
        coordinates[a] = rest % size[a];
        rest /= size[a];
      }
      const OutputPixelType * line = read + removed.Line * length;
      const SizeValueType     start = labeling.GetRunStart(removed.Run);
      const SizeValueType     end = labeling.GetRunEnd(removed.Run, removed.Line);
      // Along axis 0 every voxel of the run meets the same two values.
      SizeValueType left = start;
      while (left > 0 && sameSide(line[left - 1]))
      {
        --left;
      }
      SizeValueType right = end;
      while (right < length && sameSide(line[right]))
      {
        ++right;
      }
      double       lineSum = 0.0;
      unsigned int lineFound = 0;
      const auto   use = [](OutputPixelType v, double & sum, unsigned int & found) {
        if (!IsNaN(v))
        {
          sum += static_cast<double>(v);
          ++found;
        }
      };
      if (left > 0)
      {
        use(line[left - 1], lineSum, lineFound);
      }
      if (right < length)
      {
        use(line[right], lineSum, lineFound);
      }
      for (const OutputPixelType * voxel = line + start; voxel < line + end; ++voxel)
      {
        double       sum = lineSum;
        unsigned int found = lineFound;
        for (unsigned int a = 1; a < ImageDimension; ++a)
        {
          const OffsetValueType   step = stride[a];
          const OutputPixelType * v = voxel;
          for (SizeValueType k = coordinates[a]; k > 0; --k)
          {
            v -= step;
            if (!sameSide(*v))
            {
              use(*v, sum, found);
              break;
            }
          }
          v = voxel;
          for (SizeValueType k = coordinates[a] + 1; k < size[a]; ++k)
          {
            v += step;
            if (!sameSide(*v))
            {
              use(*v, sum, found);
              break;
            }
          }
        }
        if (found > 0)
        {
          chunkValues.push_back(MeanToPixel<OutputPixelType>(sum / found));
        }
        else
        {
          chunkValues.push_back(fallback);
          ++unrepairable[chunk];
        }
      }
    });
    if (alongside)
    {
      alongside(chunkBegin(chunk), chunkBegin(chunk + 1));
    }
  });

  MaskPixelType *            maskBuffer = mask->GetBufferPointer();
  std::vector<SizeValueType> newlyModified(chunks, 0);
  SizeValueType              valueBytes = 0;
  for (const auto & chunkValues : values)
  {
    valueBytes += chunkValues.capacity() * sizeof(OutputPixelType);
  }
  forEachChunk([&](SizeValueType chunk) {
    auto value = values[chunk].cbegin();
    forEachRunOf(
      chunk,
      [&](const LineRun & ahead) { Prefetch(maskBuffer + firstVoxel(ahead)); },
      [&](const LineRun & removed) {
        const SizeValueType first = firstVoxel(removed);
        const SizeValueType count = labeling.GetRunEnd(removed.Run, removed.Line) - labeling.GetRunStart(removed.Run);
        // Runs are a few voxels: plain loops, no library calls.
        SizeValueType newly = 0;
        for (SizeValueType i = 0; i < count; ++i)
        {
          buffer[first + i] = value[i];
          newly += maskBuffer[first + i] == 0 ? 1 : 0;
          maskBuffer[first + i] = maskValue;
        }
        value += count;
        newlyModified[chunk] += newly;
      });
  });
  for (const SizeValueType u : unrepairable)
  {
    m_NumberOfUnrepairableVoxels += u;
  }
  m_PeakExtraMemoryInBytes = std::max(m_PeakExtraMemoryInBytes,
                                      labeling.GetMemoryInBytes() + removedComponent.capacity() +
                                        runs.capacity() * sizeof(LineRun) + valueBytes + alongsideBytes);
  return std::accumulate(newlyModified.begin(), newlyModified.end(), SizeValueType{ 0 });
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::GenerateData()
{
  using namespace SmallIsoComponentDetail;
  // The parallel steps below are short: one team of threads takes them all, instead of
  // waking the threader's pool for each. It is formed first, so that its helpers wake up
  // while the outputs are allocated.
  this->GetMultiThreader()->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  SmallIsoComponentWorkTeam team(this->GetMultiThreader(), this->GetNumberOfWorkUnits());
  const InputImageType *    input = this->GetInput();
  this->AllocateOutputs();
  OutputImageType * output = this->GetOutput();
  MaskImageType *   mask = this->GetRemovedMask();

  const auto & region = output->GetBufferedRegion();
  if (input->GetBufferedRegion() != region || mask->GetBufferedRegion() != region)
  {
    itkExceptionMacro("The input's buffered region " << input->GetBufferedRegion() << " differs from the output's "
                                                     << region << "; the filter needs the whole image in one buffer.");
  }
  if (region.GetNumberOfPixels() == 0)
  {
    itkExceptionMacro("The input image is empty (size " << region.GetSize() << "); it must have at least one voxel.");
  }

  m_EffectiveMaximumComponentSize = m_MaximumComponentSize;
  if (m_UseMaximumComponentVolume)
  {
    double voxelVolume = 1.0;
    for (unsigned int a = 0; a < ImageDimension; ++a)
    {
      voxelVolume *= input->GetSpacing()[a];
    }
    // A relative tolerance keeps volume = k * voxel volume from rounding down to k - 1.
    const double voxels = m_MaximumComponentVolume / voxelVolume * (1.0 + 1e-12);
    m_EffectiveMaximumComponentSize = voxels >= static_cast<double>(NumericTraits<SizeValueType>::max())
                                        ? NumericTraits<SizeValueType>::max()
                                        : static_cast<SizeValueType>(std::floor(voxels));
  }
  const SizeValueType K = m_EffectiveMaximumComponentSize;
  m_AboveStatistics = SideStatistics();
  m_BelowStatistics = SideStatistics();
  m_NumberOfModifiedVoxels = 0;
  m_NumberOfUnrepairableVoxels = 0;
  m_PeakExtraMemoryInBytes = 0;

  SmallIsoComponentRunLabeling labeling;
  labeling.SetWorkTeam(&team);
  std::vector<SizeValueType> extent(region.GetSize().begin(), region.GetSize().end());
  labeling.Initialize(extent, m_FullyConnected, this->GetNumberOfWorkUnits());

  // Phase 1: encode each line as runs of the two sides, copying it to the output and
  // clearing its mask line first (large images of one pixel type leave that for phase 2).
  const std::function<void(SizeValueType, SizeValueType)> fillLater = this->EncodeRuns(labeling, input, output, mask);
  this->CheckAbort(0.3f);
  labeling.AssembleRuns(this->GetMultiThreader());
  m_PeakExtraMemoryInBytes = labeling.GetPeakMemoryInBytes();
  this->CheckAbort(0.35f);

  // Phase 2: link touching runs of each side across the slabs, then number the
  // components. Every run of a component of at most K voxels is kept as a candidate, so
  // that the passes below find the runs to repair without scanning all runs again.
  const auto linkAndNumber = [&labeling, K, this] {
    labeling.LinkRuns(this->GetMultiThreader());
    labeling.LabelComponents(K);
  };
  if (fillLater)
  {
    // Item 0 is the serial linking and numbering; the other work units meanwhile write
    // the output and the mask, block by block (the one that numbers joins them after).
    const SizeValueType lines = labeling.GetNumberOfLines();
    const SizeValueType lineBytes = labeling.GetLineLength() * (sizeof(OutputPixelType) + sizeof(MaskPixelType));
    const SizeValueType linesPerBlock = std::max<SizeValueType>(1, FillBlockBytes / lineBytes);
    const SizeValueType blocks = (lines + linesPerBlock - 1) / linesPerBlock;
    labeling.Parallelize(this->GetMultiThreader(), 1 + blocks, [&](SizeValueType item) {
      if (item == 0)
      {
        linkAndNumber();
      }
      else
      {
        const SizeValueType first = (item - 1) * linesPerBlock;
        fillLater(first, std::min(lines, first + linesPerBlock));
      }
    });
  }
  else
  {
    linkAndNumber();
  }
  m_PeakExtraMemoryInBytes = std::max(m_PeakExtraMemoryInBytes, labeling.GetMemoryInBytes());
  this->CheckAbort(0.7f);

  const SmallIsoComponentThreshold<OutputPixelType> threshold(m_IsoValue);
  const SizeValueType                               numberOfComponents = labeling.GetNumberOfComponents();

  // Counts a component of a side and tells whether its pass removes it: when the side is
  // processed, the component is small, and the output type has a value on the other side
  // (otherwise its voxels are unrepairable).
  const auto removes = [this, K](SideStatistics & statistics,
                                 SizeCounter &    sizes,
                                 SizeValueType    componentSize,
                                 bool             sideProcessed,
                                 bool             otherSideRepresentable) -> uint8_t {
    ++statistics.Components;
    sizes.Add(componentSize);
    if (!sideProcessed || componentSize > K)
    {
      return 0;
    }
    if (!otherSideRepresentable)
    {
      m_NumberOfUnrepairableVoxels += componentSize;
      return 0;
    }
    ++statistics.RemovedComponents;
    statistics.RemovedVoxels += componentSize;
    return 1;
  };

  // Phase 3: the above pass, on the input's components.
  std::vector<uint8_t> removedAbove(numberOfComponents, 0);
  SizeCounter          aboveSizes;
  for (SizeValueType c = 0; c < numberOfComponents; ++c)
  {
    const auto component = static_cast<SmallIsoComponentRunLabeling::ComponentIndexType>(c);
    if (labeling.IsComponentAbove(component))
    {
      removedAbove[c] = removes(m_AboveStatistics,
                                aboveSizes,
                                labeling.GetComponentSize(component),
                                m_Side != SideEnum::Below,
                                threshold.AnyBelow());
    }
  }
  m_AboveStatistics.Histogram = aboveSizes.Histogram();
  // The runs of the removed above components, also the ones that flip for the below pass.
  std::vector<SmallIsoComponentRunLabeling::LineRun> removedAboveRuns;
  if (m_AboveStatistics.RemovedComponents > 0)
  {
    removedAboveRuns = labeling.CollectCandidateRuns(removedAbove);
  }
  // The output holds the input's values until this pass writes: where they are the
  // same type, the input (likely still in the caches, unlike a streamed output) is read.
  const OutputPixelType * before = nullptr;
  if constexpr (std::is_same<InputPixelType, OutputPixelType>::value)
  {
    before = input->GetBufferPointer();
  }
  // The below pass (phase 4) with Both sees the result of this one: each removed above
  // component joins the below components it touches. Finding those visits the same runs
  // as this pass's repair, so it is done in the repair's loop.
  const bool aboveWasRemoved = m_Side == SideEnum::Both && m_AboveStatistics.RemovedComponents > 0;
  SmallIsoComponentRunLabeling::FlipGrouping        grouping(labeling, removedAboveRuns);
  const SizeValueType                               groupingBytes = grouping.GetScratchBytes();
  std::function<void(SizeValueType, SizeValueType)> joinFlipped;
  if (aboveWasRemoved)
  {
    joinFlipped = [&grouping](SizeValueType first, SizeValueType last) { grouping.JoinNeighbors(first, last); };
  }
  m_NumberOfModifiedVoxels +=
    this->Repair(labeling, removedAbove, removedAboveRuns, true, 1, output, mask, before, joinFlipped, groupingBytes);
  this->CheckAbort(0.8f);

  // Phase 4: the below pass, on the groups of below components joined by the flipped ones.
  if (!aboveWasRemoved)
  {
    std::fill(removedAbove.begin(), removedAbove.end(), 0);
    removedAboveRuns.clear();
  }
  std::vector<SmallIsoComponentRunLabeling::ComponentIndexType> groupOfComponent;
  std::vector<SizeValueType>                                    groupSize;
  grouping.Finish(removedAbove, groupOfComponent, groupSize);
  m_PeakExtraMemoryInBytes =
    std::max(m_PeakExtraMemoryInBytes,
             labeling.GetMemoryInBytes() + removedAbove.capacity() +
               removedAboveRuns.capacity() * sizeof(SmallIsoComponentRunLabeling::LineRun) + groupingBytes +
               groupOfComponent.capacity() * sizeof(SmallIsoComponentRunLabeling::ComponentIndexType));
  std::vector<SmallIsoComponentRunLabeling::LineRun>().swap(removedAboveRuns);
  std::vector<uint8_t> removedGroup(groupSize.size(), 0);
  SizeCounter          belowSizes;
  for (SizeValueType g = 0; g < groupSize.size(); ++g)
  {
    removedGroup[g] =
      removes(m_BelowStatistics, belowSizes, groupSize[g], m_Side != SideEnum::Above, threshold.AnyAbove());
  }
  m_BelowStatistics.Histogram = belowSizes.Histogram();
  std::vector<uint8_t> removedBelow(numberOfComponents, 0);
  for (SizeValueType c = 0; c < numberOfComponents; ++c)
  {
    removedBelow[c] = groupOfComponent[c] != SmallIsoComponentRunLabeling::NoGroup && removedGroup[groupOfComponent[c]];
  }
  m_PeakExtraMemoryInBytes = std::max(
    m_PeakExtraMemoryInBytes,
    labeling.GetMemoryInBytes() + removedAbove.capacity() + removedBelow.capacity() + removedGroup.capacity() +
      (groupOfComponent.capacity() + numberOfComponents) * sizeof(SmallIsoComponentRunLabeling::ComponentIndexType) +
      groupSize.capacity() * sizeof(SizeValueType));
  this->CheckAbort(0.85f);
  std::vector<SmallIsoComponentRunLabeling::LineRun> removedBelowRuns;
  if (m_BelowStatistics.RemovedComponents > 0)
  {
    // A removed group has at most K voxels, so all of its below components' runs are
    // candidates; its flipped components' runs are candidates too.
    removedBelowRuns = labeling.CollectCandidateRuns(removedBelow);
  }
  m_NumberOfModifiedVoxels += this->Repair(labeling, removedBelow, removedBelowRuns, false, 2, output, mask);
  this->UpdateProgress(1.0f);
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilter<TInputImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "IsoValue: " << m_IsoValue << std::endl;
  os << indent << "MaximumComponentSize: " << m_MaximumComponentSize << std::endl;
  os << indent << "MaximumComponentVolume: " << m_MaximumComponentVolume << std::endl;
  os << indent << "UseMaximumComponentVolume: " << (m_UseMaximumComponentVolume ? "On" : "Off") << std::endl;
  os << indent << "Side: " << m_Side << std::endl;
  os << indent << "FullyConnected: " << (m_FullyConnected ? "On" : "Off") << std::endl;
  os << indent << "EffectiveMaximumComponentSize: " << m_EffectiveMaximumComponentSize << std::endl;
  os << indent << "NumberOfComponents (above, below): " << m_AboveStatistics.Components << ", "
     << m_BelowStatistics.Components << std::endl;
  os << indent << "NumberOfRemovedComponents (above, below): " << m_AboveStatistics.RemovedComponents << ", "
     << m_BelowStatistics.RemovedComponents << std::endl;
  os << indent << "NumberOfRemovedVoxels (above, below): " << m_AboveStatistics.RemovedVoxels << ", "
     << m_BelowStatistics.RemovedVoxels << std::endl;
  os << indent << "NumberOfModifiedVoxels: " << m_NumberOfModifiedVoxels << std::endl;
  os << indent << "NumberOfUnrepairableVoxels: " << m_NumberOfUnrepairableVoxels << std::endl;
  os << indent << "PeakExtraMemoryInBytes: " << m_PeakExtraMemoryInBytes << std::endl;
}
} // end namespace itk

#endif
