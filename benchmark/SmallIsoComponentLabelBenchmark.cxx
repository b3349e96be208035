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

// SmallIsoComponentLabelBenchmark [--repeat N] [--warm-up MS] [--small] [DATA_DIR]
//
// Times the label-map filter against the chains of ITK filters that users run today (one label
// at a time, and ITK's components of equal values), on the label maps of DATA_DIR/labels and on
// synthetic ones, and prints their ratios. See docs/performance.md.

#include "itkSmallIsoComponentLabelImageFilter.h"
#include "itkBinaryThresholdImageFilter.h"
#include "itkConnectedComponentImageFilter.h"
#include "itkImageFileReader.h"
#include "itkImageIOFactory.h"
#include "itkRelabelComponentImageFilter.h"
#include "itkScalarConnectedComponentImageFilter.h"
#include "sicBenchmarkTiming.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace
{
using LabelType = uint16_t;
using LabelImageType = itk::Image<LabelType, 3>;
using WideLabelImageType = itk::Image<uint32_t, 3>;
constexpr itk::SizeValueType MaximumSize = 20;

/** How each peer is timed: the runs timed, and how long its untimed runs go on before each
 * (sic::TimeAfterWarmUp()). */
struct Timing
{
  unsigned int Repeat{ 5 };
  double       WarmUpMs{ 300 };
};

/** The labels of \a image but the background (0). */
template <typename TImage>
std::vector<typename TImage::PixelType>
ForegroundLabels(const TImage * image)
{
  using PixelType = typename TImage::PixelType;
  const PixelType * const   buffer = image->GetBufferPointer();
  const std::set<PixelType> labels(buffer, buffer + image->GetBufferedRegion().GetNumberOfPixels());
  std::vector<PixelType>    foreground(labels.begin(), labels.end());
  foreground.erase(std::remove(foreground.begin(), foreground.end(), PixelType{ 0 }), foreground.end());
  return foreground;
}

/** A new image of \a image's region and geometry, for a chain's output. */
template <typename TImage>
typename TImage::Pointer
NewImageLike(const TImage * image)
{
  auto output = TImage::New();
  output->CopyInformation(image);
  output->SetRegions(image->GetBufferedRegion());
  output->Allocate();
  return output;
}

/** The islands of every label but the background removed by ITK's own filters, one label at a
 * time, as the tools users have do it: each label thresholded, its components numbered and
 * those of at most K voxels found by relabelling, their voxels set to the background. One
 * pipeline, re-executed for each label, so that its buffers are reused. */
template <typename TImage>
class PerLabelChain
{
public:
  PerLabelChain(const TImage * input, unsigned int threads)
    : m_Input(input)
    , m_Labels(ForegroundLabels(input))
  {
    m_Threshold->SetInput(input);
    m_Threshold->SetInsideValue(1);
    m_Threshold->SetOutsideValue(0);
    m_Components->SetInput(m_Threshold->GetOutput());
    m_Relabel->SetInput(m_Components->GetOutput());
    m_Relabel->SetMinimumObjectSize(MaximumSize + 1);
    m_Threshold->SetNumberOfWorkUnits(threads);
    m_Components->SetNumberOfWorkUnits(threads);
    m_Relabel->SetNumberOfWorkUnits(threads);
    m_Output = NewImageLike(input);
  }

  void
  Run()
  {
    const itk::SizeValueType voxels = m_Input->GetBufferedRegion().GetNumberOfPixels();
    std::memcpy(m_Output->GetBufferPointer(), m_Input->GetBufferPointer(), voxels * sizeof(PixelType));
    for (const PixelType label : m_Labels)
    {
      m_Threshold->SetLowerThreshold(label);
      m_Threshold->SetUpperThreshold(label);
      m_Relabel->Update();
      const uint8_t * const  inside = m_Threshold->GetOutput()->GetBufferPointer();
      const uint32_t * const kept = m_Relabel->GetOutput()->GetBufferPointer();
      PixelType * const      output = m_Output->GetBufferPointer();
      for (itk::SizeValueType v = 0; v < voxels; ++v)
      {
        output[v] = inside[v] && !kept[v] ? PixelType{ 0 } : output[v];
      }
    }
  }

  const TImage *
  GetOutput() const
  {
    return m_Output;
  }

private:
  using PixelType = typename TImage::PixelType;
  using MaskType = itk::Image<uint8_t, 3>;
  using ComponentImageType = itk::Image<uint32_t, 3>;
  const TImage *                                                      m_Input;
  std::vector<PixelType>                                              m_Labels;
  typename itk::BinaryThresholdImageFilter<TImage, MaskType>::Pointer m_Threshold =
    itk::BinaryThresholdImageFilter<TImage, MaskType>::New();
  typename itk::ConnectedComponentImageFilter<MaskType, ComponentImageType>::Pointer m_Components =
    itk::ConnectedComponentImageFilter<MaskType, ComponentImageType>::New();
  typename itk::RelabelComponentImageFilter<ComponentImageType, ComponentImageType>::Pointer m_Relabel =
    itk::RelabelComponentImageFilter<ComponentImageType, ComponentImageType>::New();
  typename TImage::Pointer m_Output;
};

/** The islands of every label but the background removed with ITK's components of equal values:
 * ScalarConnectedComponentImageFilter with a distance of 0 (a component is a connected set of
 * one label), masked by the map itself so that the background is not labelled, then
 * relabelling, which drops the components of at most K voxels; their voxels are set to the
 * background. */
template <typename TImage>
class ScalarComponentsChain
{
public:
  ScalarComponentsChain(const TImage * input, unsigned int threads)
    : m_Input(input)
  {
    m_Components->SetInput(input);
    m_Components->SetMaskImage(input);
    m_Components->SetDistanceThreshold(0);
    m_Relabel->SetInput(m_Components->GetOutput());
    m_Relabel->SetMinimumObjectSize(MaximumSize + 1);
    m_Components->SetNumberOfWorkUnits(threads);
    m_Relabel->SetNumberOfWorkUnits(threads);
    m_Output = NewImageLike(input);
  }

  void
  Run()
  {
    m_Components->Modified();
    m_Relabel->Update();
    const itk::SizeValueType voxels = m_Input->GetBufferedRegion().GetNumberOfPixels();
    const PixelType * const  input = m_Input->GetBufferPointer();
    const uint32_t * const   kept = m_Relabel->GetOutput()->GetBufferPointer();
    PixelType * const        output = m_Output->GetBufferPointer();
    for (itk::SizeValueType v = 0; v < voxels; ++v)
    {
      output[v] = kept[v] == 0 ? PixelType{ 0 } : input[v];
    }
  }

  const TImage *
  GetOutput() const
  {
    return m_Output;
  }

private:
  using PixelType = typename TImage::PixelType;
  using ComponentImageType = itk::Image<uint32_t, 3>;
  const TImage *                                                                         m_Input;
  typename itk::ScalarConnectedComponentImageFilter<TImage, ComponentImageType>::Pointer m_Components =
    itk::ScalarConnectedComponentImageFilter<TImage, ComponentImageType>::New();
  typename itk::RelabelComponentImageFilter<ComponentImageType, ComponentImageType>::Pointer m_Relabel =
    itk::RelabelComponentImageFilter<ComponentImageType, ComponentImageType>::New();
  typename TImage::Pointer m_Output;
};

/** A label map of \a labels bands along a wavy surface, with a fraction \a noise of its voxels
 * set to random labels: islands of every label in every other, and holes. */
LabelImageType::Pointer
SyntheticLabels(itk::SizeValueType n, unsigned int labels, double noise, uint32_t seed)
{
  auto image = LabelImageType::New();
  image->SetRegions(LabelImageType::SizeType{ { n, n, n } });
  image->Allocate();
  std::mt19937                           random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  LabelType *                            buffer = image->GetBufferPointer();
  for (itk::SizeValueType z = 0, v = 0; z < n; ++z)
  {
    for (itk::SizeValueType y = 0; y < n; ++y)
    {
      for (itk::SizeValueType x = 0; x < n; ++x, ++v)
      {
        const double height = (z + 4.0 * std::sin(0.2 * x) * std::cos(0.15 * y)) / static_cast<double>(n);
        const auto   band = static_cast<LabelType>(std::min<double>(labels - 1, std::max(0.0, height * labels)));
        buffer[v] = uniform(random) < noise ? static_cast<LabelType>(random() % labels) : band;
      }
    }
  }
  return image;
}

/** The filter the benchmark times: the islands of every label but 0, K = MaximumSize, face connectivity, with the
 * mask. */
template <typename TImage>
typename itk::SmallIsoComponentLabelImageFilter<TImage>::Pointer
IslandsFilter(const TImage * input, unsigned int threads)
{
  auto filter = itk::SmallIsoComponentLabelImageFilter<TImage>::New();
  filter->SetInput(input);
  filter->SetMaximumComponentSize(MaximumSize);
  filter->SetSelection(itk::SmallIsoComponentLabelEnums::Selection::Islands);
  filter->SetNumberOfWorkUnits(threads);
  filter->GenerateRemovedMaskOn();
  return filter;
}

/** The columns every row of the table starts with. */
std::ostream &
StartRow(const std::string & name, itk::SizeValueType voxels, const std::string & peer, unsigned int threads)
{
  return std::cout << std::left << std::setw(28) << name << std::right << std::setw(11) << voxels << "  " << std::left
                   << std::setw(22) << peer << std::right << std::setw(3) << threads << std::fixed;
}

/** One row of the table: \a faults as text ("-" where they are not counted). */
void
PrintRow(const std::string & name,
         itk::SizeValueType  voxels,
         const std::string & peer,
         unsigned int        threads,
         double              ms,
         const std::string & faults,
         double              ratio)
{
  StartRow(name, voxels, peer, threads) << std::setprecision(2) << std::setw(10) << ms << std::setw(10) << faults
                                        << std::setprecision(3) << std::setw(9) << ratio << '\n';
}

/** A map of \a cells cells like a connectomics segmentation's: each voxel takes the cell of the nearest of seeds
 * jittered about a grid (of about \a cells points), with a fraction \a noise of the voxels set to random cells. The
 * cells are numbered 1, 2, 3, ... */
WideLabelImageType::Pointer
CellLabels(itk::SizeValueType n, itk::SizeValueType cells, double noise, uint32_t seed)
{
  const auto                             perAxis = static_cast<itk::SizeValueType>(std::cbrt(cells) + 0.5);
  const double                           step = static_cast<double>(n) / perAxis;
  std::mt19937                           random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<std::array<double, 3>>     seeds;
  for (itk::SizeValueType s = 0; s < perAxis * perAxis * perAxis; ++s)
  {
    const itk::SizeValueType cell[3] = { s % perAxis, s / perAxis % perAxis, s / perAxis / perAxis };
    seeds.push_back(
      { (cell[0] + uniform(random)) * step, (cell[1] + uniform(random)) * step, (cell[2] + uniform(random)) * step });
  }
  auto image = WideLabelImageType::New();
  image->SetRegions(WideLabelImageType::SizeType{ { n, n, n } });
  image->Allocate();
  uint32_t * buffer = image->GetBufferPointer();
  for (itk::SizeValueType v = 0; v < n * n * n; ++v)
  {
    const double at[3] = { v % n + 0.5, v / n % n + 0.5, v / n / n + 0.5 };
    double       nearest = 1e300;
    for (int d = 0; d < 27; ++d)
    {
      const int c[3] = { static_cast<int>(at[0] / step) + d % 3 - 1,
                         static_cast<int>(at[1] / step) + d / 3 % 3 - 1,
                         static_cast<int>(at[2] / step) + d / 9 - 1 };
      if (std::min({ c[0], c[1], c[2] }) < 0 || std::max({ c[0], c[1], c[2] }) >= static_cast<int>(perAxis))
      {
        continue;
      }
      const itk::SizeValueType s = (static_cast<itk::SizeValueType>(c[2]) * perAxis + c[1]) * perAxis + c[0];
      const double             distance =
        std::pow(at[0] - seeds[s][0], 2) + std::pow(at[1] - seeds[s][1], 2) + std::pow(at[2] - seeds[s][2], 2);
      if (distance < nearest)
      {
        nearest = distance;
        buffer[v] = static_cast<uint32_t>(s + 1);
      }
    }
    if (uniform(random) < noise)
    {
      buffer[v] = static_cast<uint32_t>(1 + random() % seeds.size());
    }
  }
  return image;
}

/** \a dense with its labels but 0 given sparse ids instead, spread up to 98 million in the order of the dense
 * ones. */
WideLabelImageType::Pointer
SparseIds(const WideLabelImageType * dense)
{
  auto image = WideLabelImageType::New();
  image->SetRegions(dense->GetBufferedRegion());
  image->Allocate();
  const itk::SizeValueType voxels = dense->GetBufferedRegion().GetNumberOfPixels();
  std::transform(dense->GetBufferPointer(),
                 dense->GetBufferPointer() + voxels,
                 image->GetBufferPointer(),
                 [](uint32_t label) { return label == 0 ? 0 : 98000000 - 38011 * label; });
  return image;
}

/** Times the filter on \a dense and on its sparse ids at 1 and 2 threads; returns false when they remove different
 * voxels. */
bool
MeasureSparseIds(const std::string & name, const WideLabelImageType * dense, const Timing & timing)
{
  using FilterType = itk::SmallIsoComponentLabelImageFilter<WideLabelImageType>;
  const auto sparse = SparseIds(dense);
  bool       agree = true;
  for (unsigned int threads : { 1u, 2u })
  {
    std::map<std::string, std::vector<double>> ms;
    std::vector<FilterType::Pointer>           filters;
    for (const WideLabelImageType * input : std::array<const WideLabelImageType *, 2>{ dense, sparse.GetPointer() })
    {
      auto filter = IslandsFilter(input, threads);
      filter->Update();
      filters.push_back(filter);
    }
    for (unsigned int r = 0; r < timing.Repeat; ++r)
    {
      for (std::size_t i = 0; i < filters.size(); ++i)
      {
        ms[i == 0 ? "smalliso-labels dense" : "smalliso-labels sparse"].push_back(
          sic::TimeAfterWarmUp([&] { filters[i]->Modified(); }, [&] { filters[i]->Update(); }, timing.WarmUpMs).Ms);
      }
    }
    const uint8_t * const    first = filters[0]->GetRemovedMask()->GetBufferPointer();
    const itk::SizeValueType voxels = dense->GetBufferedRegion().GetNumberOfPixels();
    agree = agree && std::equal(first, first + voxels, filters[1]->GetRemovedMask()->GetBufferPointer());
    const double denseMs = sic::Median(ms["smalliso-labels dense"]);
    for (const auto & [peer, times] : ms)
    {
      PrintRow(name, voxels, peer, threads, sic::Median(times), "-", sic::Median(times) / denseMs);
    }
  }
  if (!agree)
  {
    std::cerr << name << ": the dense and the sparse ids removed different voxels\n";
  }
  return agree;
}

/** The growth of the peak resident size over the first update of a new filter on \a input, without the mask, less
 * the output, in bytes per voxel (sic::PeakGrowthBytes()); -1 where the system does not say. */
template <typename TImage>
double
PeakBytesPerVoxel(const TImage * input, unsigned int threads)
{
  auto filter = IslandsFilter(input, threads);
  filter->GenerateRemovedMaskOff();
  const double growth = sic::PeakGrowthBytes([&] { filter->Update(); });
  const double voxels = static_cast<double>(input->GetBufferedRegion().GetNumberOfPixels());
  return growth < 0 ? -1 : (growth - voxels * sizeof(typename TImage::PixelType)) / voxels;
}

/** Times the peers on one label map; returns false when the filter and a chain remove different voxels. */
template <typename TImage>
bool
Measure(const std::string & name, const TImage * input, const Timing & timing)
{
  using PixelType = typename TImage::PixelType;
  const itk::SizeValueType voxels = input->GetBufferedRegion().GetNumberOfPixels();
  std::map<std::pair<std::string, unsigned int>, std::vector<sic::Sample>> samples;
  bool                                                                     agree = true;
  std::vector<PixelType>                                                   copy(voxels);
  // A copy of the map as 32-bit labels too, the width many label tools work in.
  std::vector<uint32_t> wide(voxels);
  std::vector<uint32_t> wideCopy(voxels);
  std::transform(input->GetBufferPointer(), input->GetBufferPointer() + voxels, wide.begin(), [](PixelType label) {
    return static_cast<uint32_t>(label);
  });
  for (unsigned int threads : { 1u, 2u })
  {
    auto                          filter = IslandsFilter(input, threads);
    PerLabelChain<TImage>         chain(input, threads);
    ScalarComponentsChain<TImage> scalar(input, threads);
    // The first update of each, whose new buffers take page faults as a one-off run's do.
    samples[{ "smalliso-labels first", threads }].push_back(sic::TimeMs([&] { filter->Update(); }));
    samples[{ "itk-per-label first", threads }].push_back(sic::TimeMs([&] { chain.Run(); }));
    samples[{ "itk-scalar-cc first", threads }].push_back(sic::TimeMs([&] { scalar.Run(); }));
    for (unsigned int r = 0; r < timing.Repeat; ++r)
    {
      samples[{ "smalliso-labels", threads }].push_back(
        sic::TimeAfterWarmUp([&] { filter->Modified(); }, [&] { filter->Update(); }, timing.WarmUpMs));
      samples[{ "itk-per-label", threads }].push_back(
        sic::TimeAfterWarmUp([] {}, [&] { chain.Run(); }, timing.WarmUpMs));
      samples[{ "itk-scalar-cc", threads }].push_back(
        sic::TimeAfterWarmUp([] {}, [&] { scalar.Run(); }, timing.WarmUpMs));
      samples[{ "memcpy", threads }].push_back(
        sic::TimeAfterWarmUp([] {},
                             [&] { std::memcpy(copy.data(), input->GetBufferPointer(), voxels * sizeof(PixelType)); },
                             timing.WarmUpMs));
      samples[{ "memcpy as uint32", threads }].push_back(sic::TimeAfterWarmUp(
        [] {}, [&] { std::memcpy(wideCopy.data(), wide.data(), voxels * sizeof(uint32_t)); }, timing.WarmUpMs));
    }
    // The same voxels removed: the chains set them to the background, the filter repairs them.
    const uint8_t * const   mask = filter->GetRemovedMask()->GetBufferPointer();
    const PixelType * const before = input->GetBufferPointer();
    const PixelType * const after = chain.GetOutput()->GetBufferPointer();
    const PixelType * const afterScalar = scalar.GetOutput()->GetBufferPointer();
    for (itk::SizeValueType v = 0; v < voxels; ++v)
    {
      agree = agree && (mask[v] != 0) == (before[v] != 0 && after[v] == 0) &&
              (mask[v] != 0) == (before[v] != 0 && afterScalar[v] == 0);
    }
  }
  for (const auto & entry : samples)
  {
    std::vector<double> ms;
    std::vector<double> faults;
    for (const sic::Sample & sample : entry.second)
    {
      ms.push_back(sample.Ms);
      faults.push_back(sample.Faults);
    }
    const bool   first = entry.first.first.find(" first") != std::string::npos;
    const double ours = [&] {
      std::vector<double> reference;
      for (const sic::Sample & sample :
           samples[{ first ? "smalliso-labels first" : "smalliso-labels", entry.first.second }])
      {
        reference.push_back(sample.Ms);
      }
      return sic::Median(reference);
    }();
    char faultsText[32];
    std::snprintf(faultsText, sizeof(faultsText), "%.1f", sic::Median(faults));
    PrintRow(name, voxels, entry.first.first, entry.first.second, sic::Median(ms), faultsText, sic::Median(ms) / ours);
  }
  for (unsigned int threads : { 1u, 2u })
  {
    StartRow(name, voxels, "smalliso-labels memory", threads)
      << std::setprecision(2) << std::setw(10) << PeakBytesPerVoxel(input, threads) << "  bytes per voxel\n";
  }
  if (!agree)
  {
    std::cerr << name << ": the filter and the ITK chains removed different voxels\n";
  }
  return agree;
}

/** Reads the label map at \a path in the pixel type its file stores and times the peers on it (Measure()); returns
 * false when they disagree or the type is not one of those timed. */
bool
MeasureFile(const std::string & name, const std::string & path, const Timing & timing)
{
  const auto measure = [&](auto pixel) {
    using ImageType = itk::Image<decltype(pixel), 3>;
    auto reader = itk::ImageFileReader<ImageType>::New();
    reader->SetFileName(path);
    reader->Update();
    return Measure(name, reader->GetOutput(), timing);
  };
  const itk::ImageIOBase::Pointer io =
    itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode);
  io->SetFileName(path);
  io->ReadImageInformation();
  using Component = itk::IOComponentEnum;
  switch (io->GetComponentType())
  {
    case Component::UCHAR:
      return measure(uint8_t{});
    case Component::SHORT:
      return measure(int16_t{});
    case Component::USHORT:
      return measure(uint16_t{});
    case Component::INT:
      return measure(int32_t{});
    case Component::UINT:
      return measure(uint32_t{});
    case Component::FLOAT:
      return measure(float{});
    default:
      std::cerr << path << ": pixel type " << io->GetComponentTypeAsString(io->GetComponentType())
                << " not timed; expected uint8, int16, uint16, int32, uint32 or float32\n";
      return false;
  }
}

/** Whether \a text is a finite number of milliseconds >= 0, the value --warm-up takes. */
bool
IsMilliseconds(const char * text)
{
  char *       end = nullptr;
  const double ms = std::strtod(text, &end);
  return end != text && *end == '\0' && ms >= 0 && std::isfinite(ms);
}
} // namespace

int
main(int argc, char * argv[])
{
  Timing      timing;
  bool        small = false;
  std::string dataDir = "../shared/data";
  for (int i = 1; i < argc; ++i)
  {
    const std::string argument = argv[i];
    if (argument == "--repeat" && i + 1 < argc && std::atoi(argv[i + 1]) > 0)
    {
      timing.Repeat = static_cast<unsigned int>(std::atoi(argv[++i]));
    }
    else if (argument == "--warm-up" && i + 1 < argc && IsMilliseconds(argv[i + 1]))
    {
      timing.WarmUpMs = std::strtod(argv[++i], nullptr);
    }
    else if (argument == "--small")
    {
      small = true;
    }
    else if (argument.rfind("--", 0) != 0)
    {
      dataDir = argument;
    }
    else
    {
      std::cerr << "Usage: SmallIsoComponentLabelBenchmark [--repeat N] [--warm-up MS] [--small] [DATA_DIR]\n"
                   "Times smalliso-labels (the islands of every label but 0 removed, K = 20, face connectivity)\n"
                   "against itk-per-label (ITK's threshold, connected components and relabel, one label at a\n"
                   "time, removed voxels set to 0), itk-scalar-cc (ITK's components of equal values and\n"
                   "relabel, removed voxels set to 0) and memcpy (of the map in its pixel type, and as uint32)\n"
                   "on the label maps of DATA_DIR/labels, each in the pixel type its file stores, and on\n"
                   "synthetic ones (uint16). Columns: median ms, median page faults, ratio to smalliso-labels at the\n"
                   "same thread count; the rows \"first\" time the first update of each, with its new buffers.\n"
                   "The rows \"memory\" give the growth of the peak resident size over a new filter's first\n"
                   "update (without the mask), less the output, in bytes per voxel (-1: not measurable here).\n"
                   "The cells map, 2,523 labels like a connectomics segmentation's, is timed with ids 1, 2, 3, ...\n"
                   "(dense) and with ids spread up to 98 million (sparse), ratio to dense, as uint32.\n"
                   "Each timed run follows untimed runs of the same peer for MS milliseconds (default 300; at\n"
                   "least one run; none with --small).\n"
                   "Exit status 1 if they remove different voxels.\n";
      return 2;
    }
  }
  std::cout << std::left << std::setw(28) << "volume" << std::right << std::setw(11) << "voxels"
            << "  " << std::left << std::setw(22) << "peer" << std::right << std::setw(3) << "thr" << std::setw(10)
            << "ms" << std::setw(10) << "faults" << std::setw(9) << "ratio" << '\n';
  bool agree = true;
  if (small)
  {
    timing.WarmUpMs = 0;
    return Measure("synthetic-40-noise", SyntheticLabels(40, 6, 0.02, 1).GetPointer(), timing) &&
               MeasureSparseIds("cells-40-64-ids-2%", CellLabels(40, 64, 0.02, 1), timing)
             ? 0
             : 1;
  }
  std::error_code error;
  for (const auto & file : std::filesystem::directory_iterator(dataDir + "/labels", error))
  {
    const std::string fileName = file.path().filename().string();
    // Label maps only: segmentations and atlases, not the CT they were made from.
    if (fileName.find(".nii") != std::string::npos &&
        (fileName.find("_seg") != std::string::npos || fileName.find("atlas") != std::string::npos))
    {
      agree = MeasureFile(fileName.substr(0, fileName.find('.')), file.path().string(), timing) && agree;
    }
  }
  agree = Measure("synthetic-256-6-labels-2%", SyntheticLabels(256, 6, 0.02, 1).GetPointer(), timing) && agree;
  // Connectomics-like ids: 2,523 cells (ratio to the same map with ids 1, 2, 3, ...).
  agree = MeasureSparseIds("cells-256-2523-ids-2%", CellLabels(256, 2523, 0.02, 1), timing) && agree;
  return agree ? 0 : 1;
}
