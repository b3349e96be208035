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

// The run labelling on its own: the components of both sides against a voxel flood fill
// in 1-D to 4-D with either connectivity, the same numbering whatever the number of slabs
// (so the seams between slabs are linked right), components numbered in the order of
// their first run, the candidate runs, the same numbering when it is shared among work
// units, full connectivity through a single corner, the memory it reports, and the same
// numbering whichever way lines are linked.

#include "itkSmallIsoComponentInternalsTestUtilities.h"
#include "gtest/gtest.h"

#include <array>
#include <sstream>
#include <vector>

namespace
{
using namespace itk::SmallIsoComponentTest;
using itk::SizeValueType;
using RunLabeling = itk::SmallIsoComponentDetail::RunLabeling;

/** The labelling with the ways of working that only the tests choose. */
class TestRunLabeling : public RunLabeling
{
public:
  using RunLabeling::LineLinking;
  using RunLabeling::SetLineLinking;
  using RunLabeling::SetLinesPerClaim;
  using RunLabeling::SetMinimumRunsToShareNumbering;
};

/** Random sides: voxels above with a random density, in runs along axis 0 of random
 * length, so that lines have a few long runs or many short ones. */
std::vector<uint8_t>
RandomSides(RandomSource & random, SizeValueType voxels)
{
  const double         density = random.Pick(std::array<double, 4>{ 0.05, 0.3, 0.5, 0.9 });
  const double         changeRate = random.Pick(std::array<double, 3>{ 0.1, 0.5, 1.0 });
  std::vector<uint8_t> values(voxels);
  bool                 above = random.Chance(density);
  for (auto & value : values)
  {
    if (random.Chance(changeRate))
    {
      above = random.Chance(density);
    }
    value = above ? 200 : 10;
  }
  return values;
}

/** Empty when the labeling of \a values agrees with a flood fill of each side. */
template <unsigned int VDimension>
std::string
LabelingDifference(const RunLabeling &                 labeling,
                   const std::vector<uint8_t> &        values,
                   const Reference::Grid<VDimension> & grid,
                   const std::vector<SizeValueType> &  voxelComponent)
{
  std::ostringstream out;
  SizeValueType      components = 0;
  for (const bool above : { true, false })
  {
    std::vector<uint8_t> member(values.size());
    for (SizeValueType v = 0; v < values.size(); ++v)
    {
      member[v] = (values[v] >= 100) == above ? 1 : 0;
    }
    std::vector<SizeValueType> sizes;
    const auto                 expected = Reference::LabelComponents(grid, member, sizes);
    components += sizes.size();
    const std::string difference = PartitionDifference(voxelComponent, expected);
    if (!difference.empty())
    {
      out << (above ? "above: " : "below: ") << difference << "; ";
    }
    for (SizeValueType v = 0; v < values.size() && difference.empty(); ++v)
    {
      if (!member[v])
      {
        continue;
      }
      const auto component = static_cast<RunLabeling::ComponentIndexType>(voxelComponent[v]);
      if (labeling.GetComponents().GetComponentSize(component) != sizes[expected[v]] ||
          labeling.GetComponents().IsComponentAbove(component) != above)
      {
        out << "component " << component << " has " << labeling.GetComponents().GetComponentSize(component)
            << " voxels, above " << labeling.GetComponents().IsComponentAbove(component) << "; the flood fill finds "
            << sizes[expected[v]] << "; ";
        break;
      }
    }
  }
  if (labeling.GetComponents().GetNumberOfComponents() != components)
  {
    out << labeling.GetComponents().GetNumberOfComponents() << " components, the flood fill finds " << components
        << "; ";
  }
  return out.str();
}

/** The runs of the run table split every line into maximal pieces of one side. */
std::string
RunTableDifference(const RunLabeling & labeling, const std::vector<uint8_t> & values)
{
  const RunLabeling::RunTable runs = labeling.GetRunTable();
  for (SizeValueType line = 0; line < labeling.GetNumberOfLines(); ++line)
  {
    bool above = runs.LineFirstAbove[line] != 0;
    for (SizeValueType run = runs.LineBegin[line]; run < runs.LineBegin[line + 1]; ++run, above = !above)
    {
      const SizeValueType first = line * runs.LineLength + runs.Start[run];
      const SizeValueType end = line * runs.LineLength + runs.End(run, line);
      bool                right = first < end && (run > runs.LineBegin[line] || runs.Start[run] == 0);
      for (SizeValueType v = first; v < end; ++v)
      {
        right = right && (values[v] >= 100) == above;
      }
      right = right && (runs.End(run, line) == runs.LineLength || (values[end] >= 100) != above);
      if (!right)
      {
        std::ostringstream out;
        out << "run " << run << " of line " << line << " is not a maximal run of one side";
        return out.str();
      }
    }
  }
  return "";
}

/** How many shared numberings of the random grids the first stage helped sum. */
SizeValueType &
SharedNumberingHelped()
{
  static SizeValueType helped = 0;
  return helped;
}

/** Random sides on \a grid (for ForEachRandomGrid), labelled in one slab, two and eight:
 * the runs, the components, their numbering, the candidates and the memory reported. */
template <unsigned int VDimension>
void
CheckRandomVolume(RandomSource &                      random,
                  const Reference::Grid<VDimension> & grid,
                  bool                                fullyConnected,
                  const std::string &                 where)
{
  const std::vector<uint8_t> values = RandomSides(random, grid.NumberOfVoxels());
  const auto                 candidateSize = static_cast<SizeValueType>(random.Between(0, 30));
  std::ostringstream         trace;
  trace << where << " extent";
  for (const auto e : grid.Size())
  {
    trace << " " << e;
  }
  SCOPED_TRACE(trace.str());

  // One slab, two, and as many as the work units of 8 give (one plane each when the
  // volume has fewer): every one numbers the components alike.
  std::vector<SizeValueType> firstNumbering;
  for (const unsigned int slabUnits : { 1u, 2u, 8u })
  {
    RunLabeling labeling;
    Label(labeling, values, ExtentOf(grid), 100.0, fullyConnected, slabUnits, candidateSize, slabUnits == 8 ? 1 : 2);
    const std::vector<SizeValueType> voxelComponent = VoxelComponents(labeling);
    if (slabUnits == 1)
    {
      ASSERT_EQ(RunTableDifference(labeling, values), "");
      ASSERT_EQ(LabelingDifference(labeling, values, grid, voxelComponent), "");
      firstNumbering = voxelComponent;

      // Numbered in order of their first run: a new component is the next number.
      const RunLabeling::RunTable runs = labeling.GetRunTable();
      SizeValueType               numbered = 0;
      const SizeValueType         lastRun = runs.LineBegin[labeling.GetNumberOfLines()];
      for (SizeValueType run = 0; run < lastRun; ++run)
      {
        ASSERT_LE(runs.Component[run], numbered) << "run " << run;
        numbered += runs.Component[run] == numbered ? 1 : 0;
      }

      // The candidates of the selected components: their runs while the component has
      // at most candidateSize voxels up to and including the run, in run order.
      std::vector<uint8_t> selected(labeling.GetComponents().GetNumberOfComponents());
      for (auto & s : selected)
      {
        s = random.Chance(0.5) ? 1 : 0;
      }
      std::vector<RunLabeling::LineRun> expected;
      std::vector<SizeValueType>        sizeSoFar(labeling.GetComponents().GetNumberOfComponents(), 0);
      for (SizeValueType line = 0; line < labeling.GetNumberOfLines(); ++line)
      {
        for (SizeValueType run = runs.LineBegin[line]; run < runs.LineBegin[line + 1]; ++run)
        {
          const auto component = runs.Component[run];
          sizeSoFar[component] += runs.End(run, line) - runs.Start[run];
          if (selected[component] && sizeSoFar[component] <= candidateSize)
          {
            expected.push_back(
              { static_cast<RunLabeling::RunIndexType>(run), static_cast<RunLabeling::RunIndexType>(line) });
          }
        }
      }
      // Alone, and shared among the work units of teams of one to three, into the same
      // arrays each time (as the filter reuses its own).
      std::vector<std::vector<RunLabeling::LineRun>> collections{ labeling.GetComponents().CollectCandidateRuns(
        selected) };
      std::vector<uint8_t>                           marked;
      std::vector<RunLabeling::LineRun>              reused;
      for (const unsigned int units : { 1u, 2u, 3u })
      {
        auto threader = itk::MultiThreaderBase::New();
        threader->SetNumberOfWorkUnits(units);
        itk::SmallIsoComponentDetail::WorkTeam team(threader, units);
        labeling.GetComponents().CollectCandidateRuns(selected, team, marked, reused);
        collections.push_back(reused);
      }
      std::vector<std::vector<RunLabeling::LineRun>> expectedOf(collections.size(), expected);
      // With candidates kept for one side only, the same runs of that side's components.
      for (const bool above : { true, false })
      {
        RunLabeling oneSide;
        Label(oneSide, values, ExtentOf(grid), 100.0, fullyConnected, 1, candidateSize, 2, above, !above);
        std::vector<RunLabeling::LineRun> expectedOfSide;
        for (const auto & run : expected)
        {
          if (labeling.GetComponents().IsComponentAbove(runs.Component[run.Run]) == above)
          {
            expectedOfSide.push_back(run);
          }
        }
        collections.push_back(oneSide.GetComponents().CollectCandidateRuns(selected));
        expectedOf.push_back(expectedOfSide);
      }
      for (SizeValueType c = 0; c < collections.size(); ++c)
      {
        const auto & collected = collections[c];
        const auto & expectedRuns = expectedOf[c];
        ASSERT_EQ(collected.size(), expectedRuns.size()) << "collection " << c;
        for (SizeValueType i = 0; i < expectedRuns.size(); ++i)
        {
          ASSERT_EQ(collected[i].Run, expectedRuns[i].Run);
          ASSERT_EQ(collected[i].Line, expectedRuns[i].Line);
        }
      }

      // The memory it reports covers the bytes per run, line, component and candidate
      // that its class documentation states.
      std::vector<uint8_t> all(labeling.GetComponents().GetNumberOfComponents(), 1);
      const SizeValueType  candidates = labeling.GetComponents().CollectCandidateRuns(all).size();
      EXPECT_GE(labeling.GetMemoryInBytes(),
                8 * lastRun + 9 * labeling.GetNumberOfLines() + 9 * labeling.GetComponents().GetNumberOfComponents() +
                  8 * candidates);
    }
    else
    {
      ASSERT_EQ(voxelComponent, firstNumbering) << slabUnits << " work units' slabs number differently";
    }
  }

  // The numbering shared among two and three work units, whatever the number of runs,
  // and with the first stage's help (one line per claim): the components of every run,
  // their sizes and sides, and the candidates of the serial numbering (with the help,
  // every run of the small components, and among the others some of the serial
  // numbering's, in run order).
  {
    RunLabeling serial;
    Label(serial, values, ExtentOf(grid), 100.0, fullyConnected, 2, candidateSize, 1);
    const RunLabeling::RunTable serialRuns = serial.GetRunTable();
    const SizeValueType         lastRun = serialRuns.LineBegin[serial.GetNumberOfLines()];
    std::vector<uint8_t>        all(serial.GetComponents().GetNumberOfComponents(), 1);
    std::vector<uint8_t>        small(serial.GetComponents().GetNumberOfComponents(), 0);
    for (SizeValueType c = 0; c < small.size(); ++c)
    {
      small[c] =
        serial.GetComponents().GetComponentSize(static_cast<RunLabeling::ComponentIndexType>(c)) <= candidateSize ? 1
                                                                                                                  : 0;
    }
    const auto serialCandidates = serial.GetComponents().CollectCandidateRuns(all);
    const auto serialSmall = serial.GetComponents().CollectCandidateRuns(small);
    for (const unsigned int units : { 2u, 3u })
    {
      // No help; help with room for every run; help with room for a quarter of the voxels.
      for (const unsigned int help : { 0u, 1u, 4u })
      {
        SCOPED_TRACE(testing::Message() << units << " units, help " << help);
        TestRunLabeling shared;
        shared.SetMinimumRunsToShareNumbering(0);
        shared.SetLinesPerClaim(1);
        std::vector<RunLabeling::ComponentIndexType> partialSizes;
        std::vector<RunLabeling::LineRun>            partialCandidates;
        if (help > 0)
        {
          partialCandidates.reserve(grid.NumberOfVoxels() / help);
        }
        const SizeValueType room = partialCandidates.capacity();
        Label(shared,
              values,
              ExtentOf(grid),
              100.0,
              fullyConnected,
              2,
              candidateSize,
              units,
              true,
              true,
              help > 0 ? &partialSizes : nullptr,
              help > 0 ? &partialCandidates : nullptr);
        // The helper sized its partial sums if it took any lines, and took no memory.
        SharedNumberingHelped() += partialSizes.empty() ? 0 : 1;
        EXPECT_TRUE(partialCandidates.empty());
        EXPECT_EQ(partialCandidates.capacity(), room);
        const RunLabeling::RunTable sharedRuns = shared.GetRunTable();
        for (SizeValueType run = 0; run < lastRun; ++run)
        {
          ASSERT_EQ(sharedRuns.Component[run], serialRuns.Component[run]) << "run " << run;
        }
        ASSERT_EQ(shared.GetComponents().GetNumberOfComponents(), serial.GetComponents().GetNumberOfComponents());
        for (SizeValueType c = 0; c < serial.GetComponents().GetNumberOfComponents(); ++c)
        {
          const auto component = static_cast<RunLabeling::ComponentIndexType>(c);
          ASSERT_EQ(shared.GetComponents().GetComponentSize(component),
                    serial.GetComponents().GetComponentSize(component))
            << "component " << c;
          ASSERT_EQ(shared.GetComponents().IsComponentAbove(component),
                    serial.GetComponents().IsComponentAbove(component))
            << "component " << c;
        }
        const auto sharedCandidates = shared.GetComponents().CollectCandidateRuns(all);
        const auto sharedSmall = shared.GetComponents().CollectCandidateRuns(small);
        ASSERT_EQ(sharedSmall.size(), serialSmall.size());
        for (SizeValueType i = 0; i < serialSmall.size(); ++i)
        {
          ASSERT_EQ(sharedSmall[i].Run, serialSmall[i].Run);
          ASSERT_EQ(sharedSmall[i].Line, serialSmall[i].Line);
        }
        if (help == 0)
        {
          ASSERT_EQ(sharedCandidates.size(), serialCandidates.size());
          for (SizeValueType i = 0; i < serialCandidates.size(); ++i)
          {
            ASSERT_EQ(sharedCandidates[i].Run, serialCandidates[i].Run);
            ASSERT_EQ(sharedCandidates[i].Line, serialCandidates[i].Line);
          }
        }
        // In run order, and among the serial numbering's.
        SizeValueType next = 0;
        for (SizeValueType i = 0; i < sharedCandidates.size(); ++i)
        {
          const RunLabeling::LineRun candidate = sharedCandidates[i];
          while (next < serialCandidates.size() && serialCandidates[next].Run < candidate.Run)
          {
            ++next;
          }
          ASSERT_LT(next, serialCandidates.size()) << "candidate " << i << " is not the serial numbering's";
          ASSERT_EQ(serialCandidates[next].Run, candidate.Run) << "candidate " << i;
          ASSERT_EQ(serialCandidates[next].Line, candidate.Line) << "candidate " << i;
          ++next;
        }
      }
    }
  }

  // Lines linked by a merge of their runs, by their boundary bits with a ring of every
  // line a line reaches back to, and with rings of four lines (for lines of one word) and of
  // two lines (lines written again when they fell out, pairs in one slot merged): the same
  // numbering.
  using Linking = TestRunLabeling::LineLinking;
  for (const auto & choice : { std::make_pair(Linking::Merge, itk::SmallIsoComponentDetail::Tuning::BitsCacheBytes),
                               std::make_pair(Linking::Bits, itk::SmallIsoComponentDetail::Tuning::BitsCacheBytes),
                               std::make_pair(Linking::Bits, SizeValueType{ 40 }),
                               std::make_pair(Linking::Bits, SizeValueType{ 1 }) })
  {
    TestRunLabeling labeling;
    labeling.SetLineLinking(choice.first, choice.second);
    Label(labeling, values, ExtentOf(grid), 100.0, fullyConnected, 2, candidateSize);
    ASSERT_EQ(VoxelComponents(labeling), firstNumbering) << "linking " << static_cast<int>(choice.first) << " with "
                                                         << choice.second << " bytes of bits numbers differently";
  }
}

/** Two above voxels at \a first and \a second in an image of extent \a extent, the rest
 * below: how many above components each connectivity finds. */
template <unsigned int VDimension>
std::array<SizeValueType, 2>
AboveComponentsOfTwoVoxels(const std::array<SizeValueType, VDimension> &        extent,
                           const std::array<itk::OffsetValueType, VDimension> & first,
                           const std::array<itk::OffsetValueType, VDimension> & second)
{
  std::array<SizeValueType, 2> counts{};
  for (const bool fullyConnected : { false, true })
  {
    const Reference::Grid<VDimension> grid(extent, fullyConnected);
    std::vector<uint8_t>              values(grid.NumberOfVoxels(), 10);
    values[grid.Linear(first)] = 200;
    values[grid.Linear(second)] = 200;
    RunLabeling labeling;
    Label(labeling, values, ExtentOf(grid), 100.0, fullyConnected, 2, 0);
    for (SizeValueType c = 0; c < labeling.GetComponents().GetNumberOfComponents(); ++c)
    {
      counts[fullyConnected ? 1 : 0] +=
        labeling.GetComponents().IsComponentAbove(static_cast<RunLabeling::ComponentIndexType>(c)) ? 1 : 0;
    }
  }
  return counts;
}
} // namespace

TEST(SmallIsoComponentRunLabeling, ComponentsOfBothSidesAsAFloodFillFindsThem)
{
  ForEachRandomGrid<1>(101, 60, 300, CheckRandomVolume<1>);
  ForEachRandomGrid<2>(102, 200, 30, CheckRandomVolume<2>);
  ForEachRandomGrid<3>(103, 200, 12, CheckRandomVolume<3>);
  ForEachRandomGrid<4>(104, 100, 6, CheckRandomVolume<4>);
  // Lines of several 64-voxel words of boundary bits.
  ForEachRandomGrid<2>(105, 20, 300, CheckRandomVolume<2>);
  ForEachRandomGrid<3>(106, 8, 140, CheckRandomVolume<3>);
  // The first stage's help, which depends on timing, was taken on some of them at least.
  EXPECT_GT(SharedNumberingHelped(), 0U);
}

TEST(SmallIsoComponentRunLabeling, FullConnectivityJoinsVoxelsThatShareOnlyACorner)
{
  using Counts = std::array<SizeValueType, 2>;
  // Diagonal along axes 0 and 1 (a one-voxel overlap of runs in neighbouring lines).
  EXPECT_EQ((AboveComponentsOfTwoVoxels<2>({ 5, 5 }, { 1, 1 }, { 2, 2 })), (Counts{ 2, 1 }));
  EXPECT_EQ((AboveComponentsOfTwoVoxels<2>({ 5, 5 }, { 2, 1 }, { 1, 2 })), (Counts{ 2, 1 }));
  // Corners in 3-D and 4-D: a diagonal line neighbour plus the overlap along axis 0.
  EXPECT_EQ((AboveComponentsOfTwoVoxels<3>({ 4, 4, 4 }, { 1, 1, 1 }, { 2, 2, 2 })), (Counts{ 2, 1 }));
  EXPECT_EQ((AboveComponentsOfTwoVoxels<3>({ 4, 4, 4 }, { 2, 1, 2 }, { 1, 2, 1 })), (Counts{ 2, 1 }));
  EXPECT_EQ((AboveComponentsOfTwoVoxels<4>({ 3, 3, 3, 3 }, { 0, 0, 0, 0 }, { 1, 1, 1, 1 })), (Counts{ 2, 1 }));
  // Diagonal in a plane across lines only (same x), at a slab seam of a 3-D volume.
  EXPECT_EQ((AboveComponentsOfTwoVoxels<3>({ 3, 4, 8 }, { 1, 1, 3 }, { 1, 2, 4 })), (Counts{ 2, 1 }));
  // Two voxels apart touch under neither.
  EXPECT_EQ((AboveComponentsOfTwoVoxels<3>({ 5, 5, 5 }, { 1, 1, 1 }, { 3, 1, 1 })), (Counts{ 2, 2 }));
}

TEST(SmallIsoComponentRunLabeling, LinesOfNoVoxelsAreAnError)
{
  RunLabeling labeling;
  EXPECT_THROW(labeling.Initialize({ 0, 4 }, false, 1), itk::ExceptionObject);
  EXPECT_THROW(labeling.Initialize({}, false, 1), itk::ExceptionObject);
}
