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

// SmallIsoComponentBenchmark [--json FILE] [--repeat N] [--only NAMES] [--small] [--smalliso-only] [DATA_DIR]
//
// Measures, in one process and interleaved, the median wall time of the filter and of its
// peers on real and synthetic volumes, and prints their ratios. See docs/performance.md.

#include "itkSmallIsoComponentImageFilter.h"
#include "itkBinaryThresholdImageFilter.h"
#include "itkCommand.h"
#include "itkConnectedComponentImageFilter.h"
#include "itkImageFileReader.h"
#include "itkMultiThreaderBase.h"
#include "itkRelabelComponentImageFilter.h"
#include "itkVersion.h"
#include "VoxelUnionFind.h"
#include "sicBenchmarkTiming.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <memory>
#include <thread>
#include <type_traits>
#include <vector>

namespace
{
using sic::Median;
using sic::Sample;
using sic::TimeAfterWarmUp;
using sic::TimeMs;
constexpr unsigned int Dimension = 3;
constexpr std::size_t  MaximumSize = 20;

struct Row
{
  std::string  Dataset;
  std::size_t  Voxels;
  std::string  Peer;
  unsigned int Threads;
  double       MedianMs;
  std::size_t  PeakExtraBytes;
  double       MedianFaults;
  /** The growth of the peak resident size over a new filter's first update, less the output;
   * NaN where it is not measured. */
  double MeasuredExtraBytes{ std::numeric_limits<double>::quiet_NaN() };
};

/** The row's measured bytes per voxel to three decimals, or "-" where they are not measured. */
std::string
MeasuredPerVoxel(const Row & row)
{
  if (std::isnan(row.MeasuredExtraBytes))
  {
    return "-";
  }
  std::ostringstream text;
  text << std::fixed << std::setprecision(3) << row.MeasuredExtraBytes / static_cast<double>(row.Voxels);
  return text.str();
}

/** The filter's phases (SmallIsoComponentEnums::Phase), as the benchmark's columns name them. */
const std::vector<std::pair<const char *, itk::SmallIsoComponentEnums::Phase>> Phases{
  { "encode", itk::SmallIsoComponentEnums::Phase::Encoding },
  { "link", itk::SmallIsoComponentEnums::Phase::Linking },
  { "seams", itk::SmallIsoComponentEnums::Phase::Seams },
  { "number", itk::SmallIsoComponentEnums::Phase::Numbering },
  { "decide", itk::SmallIsoComponentEnums::Phase::Deciding },
  { "repair", itk::SmallIsoComponentEnums::Phase::Repair },
  { "write", itk::SmallIsoComponentEnums::Phase::Writes }
};

/** Milliseconds of each phase of the last update of \a filter. */
template <typename TFilter>
std::vector<double>
PhaseMs(const TFilter & filter)
{
  std::vector<double> ms;
  for (const auto & phase : Phases)
  {
    ms.push_back(1000.0 * filter.GetPhaseSeconds(phase.second));
  }
  return ms;
}

/** A deterministic 64-bit generator (splitmix64), so volumes are the same everywhere. */
struct SplitMix
{
  uint64_t State;
  uint64_t
  Next()
  {
    uint64_t z = (State += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  double
  Uniform()
  {
    return static_cast<double>(Next() >> 11) * (1.0 / 9007199254740992.0);
  }
};

template <typename T>
using ImageType = itk::Image<T, Dimension>;

template <typename T>
typename ImageType<T>::Pointer
NewImage(std::size_t nx, std::size_t ny, std::size_t nz)
{
  auto                            image = ImageType<T>::New();
  typename ImageType<T>::SizeType size{ { nx, ny, nz } };
  image->SetRegions(size);
  image->Allocate();
  return image;
}

/** Smooth value noise: random values on a lattice of the given spacing, trilinearly
 * interpolated, mixed with a fraction of white noise, scaled to [0, maximum]. */
template <typename T>
typename ImageType<T>::Pointer
SmoothNoise(std::size_t nx,
            std::size_t ny,
            std::size_t nz,
            std::size_t spacing,
            double      whiteFraction,
            double      maximum,
            uint64_t    seed)
{
  SplitMix           random{ seed };
  const std::size_t  lx = nx / spacing + 2, ly = ny / spacing + 2, lz = nz / spacing + 2;
  std::vector<float> lattice(lx * ly * lz);
  for (auto & v : lattice)
  {
    v = static_cast<float>(random.Uniform());
  }
  auto image = NewImage<T>(nx, ny, nz);
  T *  out = image->GetBufferPointer();
  for (std::size_t z = 0; z < nz; ++z)
  {
    const std::size_t iz = z / spacing;
    const float       fz = static_cast<float>(z % spacing) / spacing;
    for (std::size_t y = 0; y < ny; ++y)
    {
      const std::size_t iy = y / spacing;
      const float       fy = static_cast<float>(y % spacing) / spacing;
      for (std::size_t x = 0; x < nx; ++x)
      {
        const std::size_t ix = x / spacing;
        const float       fx = static_cast<float>(x % spacing) / spacing;
        const auto   at = [&](std::size_t a, std::size_t b, std::size_t c) { return lattice[(c * ly + b) * lx + a]; };
        const float  c00 = at(ix, iy, iz) * (1 - fx) + at(ix + 1, iy, iz) * fx;
        const float  c10 = at(ix, iy + 1, iz) * (1 - fx) + at(ix + 1, iy + 1, iz) * fx;
        const float  c01 = at(ix, iy, iz + 1) * (1 - fx) + at(ix + 1, iy, iz + 1) * fx;
        const float  c11 = at(ix, iy + 1, iz + 1) * (1 - fx) + at(ix + 1, iy + 1, iz + 1) * fx;
        const float  c0 = c00 * (1 - fy) + c10 * fy;
        const float  c1 = c01 * (1 - fy) + c11 * fy;
        const double smooth = c0 * (1 - fz) + c1 * fz;
        *out++ =
          static_cast<T>(std::lround(((1 - whiteFraction) * smooth + whiteFraction * random.Uniform()) * maximum));
      }
    }
  }
  return image;
}

/** Sparse blobs: dense balls on a low, noisy background, with rare impulse noise that
 * makes specks outside and bubbles inside the balls. */
template <typename T>
typename ImageType<T>::Pointer
SparseBlobs(std::size_t nx, std::size_t ny, std::size_t nz, uint64_t seed)
{
  SplitMix          random{ seed };
  auto              image = NewImage<T>(nx, ny, nz);
  T *               buffer = image->GetBufferPointer();
  const std::size_t count = nx * ny * nz;
  for (std::size_t i = 0; i < count; ++i)
  {
    buffer[i] = static_cast<T>(100 + random.Next() % 60);
  }
  const std::size_t balls = count / 200000;
  for (std::size_t b = 0; b < balls; ++b)
  {
    const double cx = random.Uniform() * nx, cy = random.Uniform() * ny, cz = random.Uniform() * nz;
    const double r = 3 + random.Uniform() * 17;
    for (auto z = static_cast<std::ptrdiff_t>(std::max(0.0, cz - r)); z < std::min<double>(nz, cz + r + 1); ++z)
    {
      for (auto y = static_cast<std::ptrdiff_t>(std::max(0.0, cy - r)); y < std::min<double>(ny, cy + r + 1); ++y)
      {
        for (auto x = static_cast<std::ptrdiff_t>(std::max(0.0, cx - r)); x < std::min<double>(nx, cx + r + 1); ++x)
        {
          if ((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) <= r * r)
          {
            buffer[(z * ny + y) * nx + x] = static_cast<T>(900 + random.Next() % 200);
          }
        }
      }
    }
  }
  for (std::size_t i = 0; i < count / 1000; ++i)
  {
    const std::size_t v = random.Next() % count;
    buffer[v] = buffer[v] > 500 ? T(50) : T(1000);
  }
  return image;
}

/** The memory worst case: sides alternate at every voxel, so every voxel is a run and,
 * with face connectivity, a component of its own. */
template <typename T>
typename ImageType<T>::Pointer
Checkerboard(std::size_t n)
{
  auto image = NewImage<T>(n, n, n);
  T *  out = image->GetBufferPointer();
  for (std::size_t z = 0; z < n; ++z)
  {
    for (std::size_t y = 0; y < n; ++y)
    {
      for (std::size_t x = 0; x < n; ++x)
      {
        *out++ = (x + y + z) % 2 ? T(200) : T(10);
      }
    }
  }
  return image;
}

/** Independent random voxels, each above \a isoValue with probability 1/2: every component is
 * tiny except one percolating cluster per side, the hardest input for the labelling. uint8
 * voxels are 0 or 255; wider types take every value of their range. */
template <typename T>
typename ImageType<T>::Pointer
RandomVoxels(std::size_t n, uint64_t seed)
{
  SplitMix          random{ seed };
  auto              image = NewImage<T>(n, n, n);
  T *               out = image->GetBufferPointer();
  const std::size_t count = n * n * n;
  for (std::size_t i = 0; i < count; ++i)
  {
    const uint64_t bits = random.Next();
    *out++ = std::is_same<T, uint8_t>::value ? static_cast<T>((bits & 1) ? 255 : 0) : static_cast<T>(bits);
  }
  return image;
}

/** The isovalue half way between the median and the next value, for smooth noise. */
template <typename T>
double
MedianIsoValue(const ImageType<T> * image)
{
  std::map<T, std::size_t> histogram;
  const std::size_t        count = image->GetBufferedRegion().GetNumberOfPixels();
  for (std::size_t i = 0; i < count; ++i)
  {
    ++histogram[image->GetBufferPointer()[i]];
  }
  std::size_t seen = 0;
  for (const auto & entry : histogram)
  {
    seen += entry.second;
    if (seen >= count / 2)
    {
      return static_cast<double>(entry.first) + 0.5;
    }
  }
  return 0.5;
}

struct Options
{
  std::string  Json;
  unsigned int Repeat{ 5 };
  bool         Small{ false };
  /** --smalliso-only: times smalliso and memcpy alone, for comparing two builds of the filter. */
  bool        SmallIsoOnly{ false };
  std::string DataDir;
  /** Names of the volumes to measure (--only); empty: all of them. */
  std::vector<std::string> Only;

  bool
  Wants(const std::string & name) const
  {
    return Only.empty() || std::find(Only.begin(), Only.end(), name) != Only.end();
  }
};

class Benchmark
{
public:
  explicit Benchmark(const Options & options)
    : m_Options(options)
  {}

  template <typename T>
  void
  Run(const std::string & name, const ImageType<T> * input, double isoValue)
  {
    const unsigned int machineThreads = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t  voxels = input->GetBufferedRegion().GetNumberOfPixels();
    const auto &       region = input->GetBufferedRegion();
    std::cerr << "  " << name << " (" << region.GetSize() << ", isovalue " << isoValue << ")" << std::endl;

    auto copy = NewImage<T>(region.GetSize()[0], region.GetSize()[1], region.GetSize()[2]);
    std::map<std::pair<std::string, unsigned int>, std::vector<Sample>>              times;
    std::map<std::pair<std::string, unsigned int>, std::vector<std::vector<double>>> phases;
    std::map<std::pair<std::string, unsigned int>, std::size_t>                      extra;
    std::vector<unsigned int>                                                        threadCounts{ 1 };
    if (machineThreads > 1)
    {
      threadCounts.push_back(machineThreads);
    }

    // Each peer's pipeline is built once and re-executed, so every peer reuses its
    // buffers between repetitions, as a pipeline that re-executes does.
    using SmallIsoType = itk::SmallIsoComponentImageFilter<ImageType<T>>;
    using BinaryImageType = itk::Image<uint8_t, Dimension>;
    using LabelImageType = itk::Image<uint32_t, Dimension>;
    using ThresholdType = itk::BinaryThresholdImageFilter<ImageType<T>, BinaryImageType>;
    using ConnectedType = itk::ConnectedComponentImageFilter<BinaryImageType, LabelImageType>;
    using RelabelType = itk::RelabelComponentImageFilter<LabelImageType, LabelImageType>;
    std::map<unsigned int, typename SmallIsoType::Pointer>  smallIso;
    std::map<unsigned int, typename SmallIsoType::Pointer>  smallIsoAbove;
    std::map<unsigned int, typename ThresholdType::Pointer> threshold;
    std::map<unsigned int, typename ConnectedType::Pointer> connected;
    std::map<unsigned int, typename RelabelType::Pointer>   relabel;
    const auto newSmallIso = [&](unsigned int threads, itk::SmallIsoComponentEnums::Side side) {
      auto filter = SmallIsoType::New();
      filter->SetInput(input);
      filter->SetIsoValue(isoValue);
      filter->SetMaximumComponentSize(MaximumSize);
      filter->SetSide(side);
      filter->SetNumberOfWorkUnits(threads);
      return filter;
    };
    for (const unsigned int threads : threadCounts)
    {
      smallIso[threads] = newSmallIso(threads, itk::SmallIsoComponentEnums::Side::Both);
      smallIsoAbove[threads] = newSmallIso(threads, itk::SmallIsoComponentEnums::Side::Above);

      threshold[threads] = ThresholdType::New();
      threshold[threads]->SetInput(input);
      threshold[threads]->SetLowerThreshold(static_cast<T>(std::ceil(isoValue)));
      threshold[threads]->SetInsideValue(1);
      threshold[threads]->SetOutsideValue(0);
      threshold[threads]->SetNumberOfWorkUnits(threads);
      connected[threads] = ConnectedType::New();
      connected[threads]->SetInput(threshold[threads]->GetOutput());
      connected[threads]->SetNumberOfWorkUnits(threads);
      relabel[threads] = RelabelType::New();
      relabel[threads]->SetInput(connected[threads]->GetOutput());
      // RelabelComponentImageFilter drops objects smaller than MinimumObjectSize: K + 1.
      relabel[threads]->SetMinimumObjectSize(MaximumSize + 1);
      relabel[threads]->SetNumberOfWorkUnits(threads);
    }
    VoxelUnionFind::Peer<T> peer;
    std::vector<T>          voxelUnionFindOutput(voxels);
    const std::size_t       size[3] = { region.GetSize()[0], region.GetSize()[1], region.GetSize()[2] };

    for (unsigned int repetition = 0; repetition < m_Options.Repeat; ++repetition)
    {
      for (const unsigned int threads : threadCounts)
      {
        itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(threads);
        for (auto * filters : { &smallIso, &smallIsoAbove })
        {
          const std::string peer = filters == &smallIso ? "smalliso" : "smalliso-above";
          SmallIsoType *    filter = (*filters)[threads];
          times[{ peer, threads }].push_back(TimeAfterWarmUp([&] { filter->Modified(); }, [&] { filter->Update(); }));
          extra[{ peer, threads }] = filter->GetPeakExtraMemoryInBytes();
          phases[{ peer, threads }].push_back(PhaseMs(*filter));
        }

        if (m_Options.SmallIsoOnly)
        {
          continue;
        }
        times[{ "itk-cc-relabel", threads }].push_back(
          TimeAfterWarmUp([&] { threshold[threads]->Modified(); }, [&] { relabel[threads]->Update(); }));
        extra[{ "itk-cc-relabel", threads }] = voxels * (sizeof(uint8_t) + 2 * sizeof(uint32_t));
      }

      if (!m_Options.SmallIsoOnly)
      {
        times[{ "voxel-union-find", 1 }].push_back(TimeAfterWarmUp(
          [&] {
            std::copy(input->GetBufferPointer(), input->GetBufferPointer() + voxels, voxelUnionFindOutput.begin());
          },
          [&] { peer.Run(voxelUnionFindOutput.data(), size, isoValue, MaximumSize); }));
        extra[{ "voxel-union-find", 1 }] = peer.ExtraBytes();
      }

      times[{ "memcpy", 1 }].push_back(TimeAfterWarmUp(
        [] {}, [&] { std::memcpy(copy->GetBufferPointer(), input->GetBufferPointer(), voxels * sizeof(T)); }));
      extra[{ "memcpy", 1 }] = 0;
    }
    // The memory of a first update, measured with a new filter after the timed runs.
    std::map<std::pair<std::string, unsigned int>, double> measured;
    for (const unsigned int threads : threadCounts)
    {
      itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(threads);
      for (const auto side : { itk::SmallIsoComponentEnums::Side::Both, itk::SmallIsoComponentEnums::Side::Above })
      {
        auto         filter = newSmallIso(threads, side);
        const double growth = sic::PeakGrowthBytes([&] { filter->Update(); });
        measured[{ side == itk::SmallIsoComponentEnums::Side::Both ? "smalliso" : "smalliso-above", threads }] =
          growth < 0 ? std::numeric_limits<double>::quiet_NaN() : growth - static_cast<double>(voxels * sizeof(T));
      }
    }
    const unsigned int                   most = threadCounts.back();
    const typename ImageType<T>::Pointer smallIsoOutput = smallIso[most]->GetOutput();
    const std::size_t                    smallIsoRemovedAbove =
      smallIso[most]->GetNumberOfRemovedComponents(itk::SmallIsoComponentEnums::Side::Above);
    const std::size_t ccRemovedAbove = connected[most]->GetObjectCount() - relabel[most]->GetNumberOfObjects();
    using Side = itk::SmallIsoComponentEnums::Side;
    std::cerr << "    components above/below: " << smallIso[most]->GetNumberOfComponents(Side::Above) << " / "
              << smallIso[most]->GetNumberOfComponents(Side::Below) << ", modified voxels "
              << smallIso[most]->GetNumberOfModifiedVoxels() << std::endl;

    // The peers that do the same job must agree to the voxel.
    if (m_Options.SmallIsoOnly)
    {
      std::cerr << "    (--smalliso-only: not checked against the peers)" << std::endl;
    }
    else if (!std::equal(voxelUnionFindOutput.begin(), voxelUnionFindOutput.end(), smallIsoOutput->GetBufferPointer()))
    {
      std::cerr << "ERROR: smalliso and voxel-union-find disagree on " << name << std::endl;
      m_Failed = true;
    }
    if (!m_Options.SmallIsoOnly && ccRemovedAbove != smallIsoRemovedAbove)
    {
      std::cerr << "ERROR: smalliso removed " << smallIsoRemovedAbove << " above components on " << name
                << ", itk-cc-relabel dropped " << ccRemovedAbove << std::endl;
      m_Failed = true;
    }

    for (const auto & entry : times)
    {
      std::vector<double> ms;
      std::vector<double> faults;
      for (const Sample & sample : entry.second)
      {
        ms.push_back(sample.Ms);
        faults.push_back(sample.Faults);
      }
      const auto found = measured.find(entry.first);
      m_Rows.push_back({ name,
                         voxels,
                         entry.first.first,
                         entry.first.second,
                         Median(ms),
                         extra[entry.first],
                         Median(faults),
                         found == measured.end() ? std::numeric_limits<double>::quiet_NaN() : found->second });
    }
    for (const auto & entry : phases)
    {
      PhaseRow row{ name, voxels, entry.first.first, entry.first.second, {} };
      for (std::size_t phase = 0; phase < Phases.size(); ++phase)
      {
        std::vector<double> ms;
        for (const auto & run : entry.second)
        {
          ms.push_back(run[phase]);
        }
        row.MedianMs.push_back(Median(ms));
      }
      m_PhaseRows.push_back(row);
    }
  }

  void
  Print(std::ostream & os) const
  {
    os << std::left << std::setw(22) << "dataset" << std::right << std::setw(11) << "voxels"
       << "  " << std::left << std::setw(17) << "peer" << std::right << std::setw(7) << "threads" << std::setw(11)
       << "median ms" << std::setw(8) << "ns/vox" << std::setw(10) << "Mvox/s" << std::setw(11) << "x memcpy"
       << std::setw(12) << "x smalliso" << std::setw(12) << "extra B/vox" << std::setw(10) << "RSS B/vox"
       << std::setw(10) << "faults"
       << "\n";
    for (const Row & row : m_Rows)
    {
      const double memcpyMs = this->Find(row.Dataset, "memcpy", 1);
      const double smallIsoMs = this->Find(row.Dataset, "smalliso", row.Peer == "smalliso" ? 1 : row.Threads);
      os << std::left << std::setw(22) << row.Dataset << std::right << std::setw(11) << row.Voxels << "  " << std::left
         << std::setw(17) << row.Peer << std::right << std::setw(7) << row.Threads << std::fixed << std::setprecision(2)
         << std::setw(11) << row.MedianMs << std::setw(8) << row.MedianMs * 1e6 / row.Voxels << std::setprecision(0)
         << std::setw(10) << row.Voxels / row.MedianMs / 1000.0 << std::setprecision(2) << std::setw(11)
         << row.MedianMs / memcpyMs << std::setw(12) << row.MedianMs / smallIsoMs << std::setprecision(3)
         << std::setw(12) << static_cast<double>(row.PeakExtraBytes) / row.Voxels << std::setw(10)
         << MeasuredPerVoxel(row) << std::setprecision(0) << std::setw(10) << row.MedianFaults << "\n";
    }
    os << "x smalliso: ratio to smalliso at the same thread count (1 thread for smalliso rows and single-threaded "
          "peers); smalliso-above: Side Above; extra B/vox: what the filter counts it holds beyond input and output "
          "(the ITK chain's images, the voxel union-find's arrays); RSS B/vox: the growth of the peak resident size "
          "over a new filter's first update, less the output, measured; faults: page faults of the process during the "
          "timed run\n";
    os << "\nsmalliso's phases, median ms (ns/voxel of the whole update in the last column):\n"
       << std::left << std::setw(22) << "dataset" << std::setw(17) << "peer" << std::right << std::setw(7) << "threads";
    for (const auto & phase : Phases)
    {
      os << std::setw(9) << phase.first;
    }
    os << std::setw(8) << "ns/vox\n";
    for (const PhaseRow & row : m_PhaseRows)
    {
      os << std::left << std::setw(22) << row.Dataset << std::setw(17) << row.Peer << std::right << std::setw(7)
         << row.Threads << std::fixed << std::setprecision(2);
      double total = 0;
      for (const double ms : row.MedianMs)
      {
        os << std::setw(9) << ms;
        total += ms;
      }
      os << std::setw(8) << total * 1e6 / row.Voxels << "\n";
    }
  }

  void
  WriteJson(std::ostream & os) const
  {
    os << "{\"machine\": {\"hardware_threads\": " << std::thread::hardware_concurrency() << ", \"cpu\": \""
       << CpuModel() << "\", \"compiler\": \"" << __VERSION__ << "\", \"itk\": \"" << itk::Version::GetITKVersion()
       << "\", \"repeat\": " << m_Options.Repeat << "},\n \"rows\": [";
    for (std::size_t i = 0; i < m_Rows.size(); ++i)
    {
      const Row & row = m_Rows[i];
      os << (i ? ",\n  " : "\n  ") << "{\"dataset\": \"" << row.Dataset << "\", \"voxels\": " << row.Voxels
         << ", \"peer\": \"" << row.Peer << "\", \"threads\": " << row.Threads
         << ", \"median_ms\": " << std::setprecision(6) << row.MedianMs
         << ", \"peak_extra_bytes\": " << row.PeakExtraBytes << ", \"measured_extra_bytes\": "
         << (std::isnan(row.MeasuredExtraBytes) ? std::string("null") : std::to_string(row.MeasuredExtraBytes))
         << ", \"median_page_faults\": " << row.MedianFaults << "}";
    }
    os << "\n],\n \"phases\": [";
    for (std::size_t i = 0; i < m_PhaseRows.size(); ++i)
    {
      const PhaseRow & row = m_PhaseRows[i];
      os << (i ? ",\n  " : "\n  ") << "{\"dataset\": \"" << row.Dataset << "\", \"peer\": \"" << row.Peer
         << "\", \"threads\": " << row.Threads;
      for (std::size_t phase = 0; phase < Phases.size(); ++phase)
      {
        os << ", \"" << Phases[phase].first << "_ms\": " << std::setprecision(6) << row.MedianMs[phase];
      }
      os << "}";
    }
    os << "\n]}\n";
  }

  bool
  Failed() const
  {
    return m_Failed;
  }

private:
  static std::string
  CpuModel()
  {
    std::ifstream info("/proc/cpuinfo");
    std::string   line;
    while (std::getline(info, line))
    {
      if (line.rfind("model name", 0) == 0)
      {
        std::string model = line.substr(line.find(':') + 2);
        model.erase(std::remove(model.begin(), model.end(), '"'), model.end());
        return model;
      }
    }
    return "unknown";
  }

  double
  Find(const std::string & dataset, const std::string & peer, unsigned int threads) const
  {
    for (const Row & row : m_Rows)
    {
      if (row.Dataset == dataset && row.Peer == peer && row.Threads == threads)
      {
        return row.MedianMs;
      }
    }
    return std::nan("");
  }

  struct PhaseRow
  {
    std::string         Dataset;
    std::size_t         Voxels;
    std::string         Peer;
    unsigned int        Threads;
    std::vector<double> MedianMs;
  };

  Options               m_Options;
  std::vector<Row>      m_Rows;
  std::vector<PhaseRow> m_PhaseRows;
  bool                  m_Failed{ false };
};

bool
IsDirectory(const std::string & path)
{
  std::error_code error;
  return std::filesystem::is_directory(path, error);
}

template <typename T>
typename ImageType<T>::Pointer
Read(const std::string & path)
{
  auto reader = itk::ImageFileReader<ImageType<T>>::New();
  reader->SetFileName(path);
  reader->Update();
  return reader->GetOutput();
}

int
Usage(std::ostream & os, int status)
{
  os << "Usage: SmallIsoComponentBenchmark [--json FILE] [--repeat N] [--only NAMES] [--small]\n"
        "                                  [--smalliso-only] [DATA_DIR]\n"
        "Times smalliso (Side Both, and Side Above as smalliso-above; K = 20, face connectivity) against\n"
        "itk-cc-relabel, voxel-union-find and memcpy on every volume of DATA_DIR (default ../shared/data,\n"
        "if present) and on synthetic volumes, and prints medians, ratios, page faults and the median time\n"
        "of each of smalliso's phases. Each timed run follows an untimed run of the same peer at the same\n"
        "thread count. --only aneurism,lobster measures only the volumes named (real\n"
        "or synthetic, as the table names them). --small uses two small synthetic volumes only (a smoke test).\n"
        "--smalliso-only times smalliso and memcpy alone, unchecked: for comparing two builds of the filter.\n"
        "Exit status 1 if smalliso and voxel-union-find disagree, 2 on bad arguments.\n";
  return status;
}
} // namespace

int
main(int argc, char * argv[])
{
  Options options;
  options.DataDir = "../shared/data";
  for (int i = 1; i < argc; ++i)
  {
    const std::string argument = argv[i];
    if (argument == "--json" && i + 1 < argc)
    {
      options.Json = argv[++i];
    }
    else if (argument == "--repeat" && i + 1 < argc)
    {
      const int repeat = std::atoi(argv[++i]);
      if (repeat < 1)
      {
        std::cerr << "SmallIsoComponentBenchmark: --repeat needs a whole number >= 1, got '" << argv[i] << "'\n";
        return 2;
      }
      options.Repeat = static_cast<unsigned int>(repeat);
    }
    else if (argument == "--only" && i + 1 < argc)
    {
      std::stringstream names(argv[++i]);
      for (std::string name; std::getline(names, name, ',');)
      {
        if (!name.empty())
        {
          options.Only.push_back(name);
        }
      }
      if (options.Only.empty())
      {
        std::cerr << "SmallIsoComponentBenchmark: --only needs volume names separated by commas, got '" << argv[i]
                  << "'\n";
        return 2;
      }
    }
    else if (argument == "--smalliso-only")
    {
      options.SmallIsoOnly = true;
    }
    else if (argument == "--small")
    {
      options.Small = true;
    }
    else if (argument == "--help" || argument == "-h")
    {
      return Usage(std::cout, 0);
    }
    else if (!argument.empty() && argument[0] == '-')
    {
      std::cerr << "SmallIsoComponentBenchmark: unknown option '" << argument << "'\n";
      return Usage(std::cerr, 2);
    }
    else
    {
      options.DataDir = argument;
    }
  }

  // Isovalues from the literature (aneurism, bonsai, lobster) and chosen for the others.
  const std::vector<std::pair<std::string, double>> volumes{
    { "aneurism", 30.5 },      { "bonsai", 50.5 }, { "lobster", 20.5 },  { "engine", 100.5 },
    { "boston_teapot", 40.5 }, { "frog", 30.5 },   { "tooth", 120.5 },   { "hydrogen_atom", 20.5 },
    { "silicium", 100.5 },     { "fuel", 20.5 },   { "mr_head", 1300.5 }
  };
  const std::vector<std::string> synthetic{ "noise-256-u8",        "noise-512x512x463-u16", "blobs-512x512x463-u16",
                                            "checkerboard-256-u8", "random-384-u8",         "random-384-u16" };
  for (const std::string & name : options.Only)
  {
    const bool real = std::any_of(volumes.begin(), volumes.end(), [&](const auto & v) { return v.first == name; });
    if (!real && std::find(synthetic.begin(), synthetic.end(), name) == synthetic.end())
    {
      std::cerr << "SmallIsoComponentBenchmark: --only names an unknown volume '" << name << "'; known volumes:";
      for (const auto & v : volumes)
      {
        std::cerr << ' ' << v.first;
      }
      for (const auto & v : synthetic)
      {
        std::cerr << ' ' << v;
      }
      std::cerr << '\n';
      return 2;
    }
  }

  Benchmark benchmark(options);
  if (options.Small)
  {
    auto noise = SmoothNoise<uint8_t>(64, 64, 64, 2, 0.2, 255, 1);
    benchmark.Run<uint8_t>("noise-64-u8", noise, MedianIsoValue<uint8_t>(noise));
    // Output and mask of 6 MiB: the filter writes them with streaming stores, which the
    // exactness check then covers.
    auto blobs = SparseBlobs<uint16_t>(128, 128, 128, 5);
    benchmark.Run<uint16_t>("blobs-128-u16", blobs, 500.5);
  }
  else
  {
    if (IsDirectory(options.DataDir))
    {
      std::cerr << "Real volumes from " << options.DataDir << ":" << std::endl;
      for (const auto & volume : volumes)
      {
        if (!options.Wants(volume.first))
        {
          continue;
        }
        const std::string path = options.DataDir + "/" + volume.first + ".nrrd";
        if (!itksys::SystemTools::FileExists(path))
        {
          std::cerr << "  " << volume.first << ": not found, skipped" << std::endl;
          continue;
        }
        if (volume.first == "mr_head")
        {
          benchmark.Run<uint16_t>(volume.first, Read<uint16_t>(path), volume.second);
        }
        else
        {
          benchmark.Run<uint8_t>(volume.first, Read<uint8_t>(path), volume.second);
        }
      }
    }
    else
    {
      std::cerr << "No real volumes: data directory '" << options.DataDir
                << "' not found; measuring synthetic volumes only." << std::endl;
    }
    std::cerr << "Synthetic volumes:" << std::endl;
    if (options.Wants("noise-256-u8"))
    {
      // Lattice spacing 2 and 20% white noise: hundreds of thousands of components at the median.
      auto noise = SmoothNoise<uint8_t>(256, 256, 256, 2, 0.2, 255, 1);
      benchmark.Run<uint8_t>("noise-256-u8", noise, MedianIsoValue<uint8_t>(noise));
    }
    if (options.Wants("noise-512x512x463-u16"))
    {
      auto noise = SmoothNoise<uint16_t>(512, 512, 463, 2, 0.2, 4095, 2);
      benchmark.Run<uint16_t>("noise-512x512x463-u16", noise, MedianIsoValue<uint16_t>(noise));
    }
    if (options.Wants("blobs-512x512x463-u16"))
    {
      auto blobs = SparseBlobs<uint16_t>(512, 512, 463, 3);
      benchmark.Run<uint16_t>("blobs-512x512x463-u16", blobs, 500.5);
    }
    if (options.Wants("checkerboard-256-u8"))
    {
      benchmark.Run<uint8_t>("checkerboard-256-u8", Checkerboard<uint8_t>(256), 100.5);
    }
    // cc3d's benchmark volume: 384^3 random binary voxels, half of them above.
    if (options.Wants("random-384-u8"))
    {
      benchmark.Run<uint8_t>("random-384-u8", RandomVoxels<uint8_t>(384, 4), 127.5);
    }
    if (options.Wants("random-384-u16"))
    {
      benchmark.Run<uint16_t>("random-384-u16", RandomVoxels<uint16_t>(384, 5), 32767.5);
    }
  }

  benchmark.Print(std::cout);
  if (!options.Json.empty())
  {
    std::ofstream json(options.Json);
    benchmark.WriteJson(json);
    if (!json)
    {
      std::cerr << "SmallIsoComponentBenchmark: could not write " << options.Json << std::endl;
      return 2;
    }
  }
  return benchmark.Failed() ? 1 : 0;
}
