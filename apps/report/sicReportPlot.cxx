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
#include "sicReportPlot.h"

#include "sicImageFiles.h"
#include "sicPlatform.h"
#include "sicStagedOutputs.h"
#include "sicToolError.h"

#include <filesystem>
#include <fstream>

namespace sic
{
namespace
{
namespace fs = std::filesystem;

const char * const Plotter = "gnuplot";

/** A gnuplot single-quoted string: inside one, a quote is written twice. */
std::string
Quoted(const std::string & text)
{
  std::string quoted = "'";
  for (const char c : text)
  {
    quoted += c == '\'' ? std::string("''") : std::string(1, c);
  }
  return quoted + "'";
}

/** A directory of its own under the system's temporary directory, removed with it or by a termination signal. */
class TemporaryDirectory
{
public:
  TemporaryDirectory()
  {
    std::error_code error;
    m_Path = CreateUniqueDirectory(fs::temp_directory_path(), "SmallIsoComponentReport.", error);
    if (m_Path.empty())
    {
      throw ToolError("cannot create a temporary directory for the plot in " + fs::temp_directory_path().string() +
                      " (" + error.message() + ")");
    }
    m_Cleanup = std::make_unique<TerminationAction>([path = m_Path] {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    });
  }
  TemporaryDirectory(const TemporaryDirectory &) = delete;
  TemporaryDirectory &
  operator=(const TemporaryDirectory &) = delete;
  ~TemporaryDirectory()
  {
    m_Cleanup.reset();
    std::error_code ignored;
    fs::remove_all(m_Path, ignored);
  }
  const fs::path &
  Path() const
  {
    return m_Path;
  }

private:
  fs::path                           m_Path;
  std::unique_ptr<TerminationAction> m_Cleanup;
};

/** gnuplot's path on PATH; throws ToolError when it cannot be run. */
fs::path
FindPlotter()
{
  if (!CanStartPrograms())
  {
    throw ToolError("--plot runs gnuplot, and starting other programs is not supported on this platform; leave out "
                    "--plot");
  }
  const fs::path plotter = FindProgram(Plotter);
  if (plotter.empty())
  {
    throw ToolError("--plot needs gnuplot, which is not on PATH; install it (Debian: apt-get install gnuplot-nox) "
                    "or leave out --plot");
  }
  return plotter;
}

/** The first line of gnuplot's messages that says something, for the error. */
std::string
FirstMessage(const fs::path & log)
{
  std::ifstream file(log);
  std::string   line;
  std::string   message;
  while (std::getline(file, line))
  {
    const std::string text = OneLine(line);
    if (!text.empty() && text != "^")
    {
      message += (message.empty() ? "" : " ") + text;
    }
  }
  return message.empty() ? std::string("no message") : message;
}

void
WritePanel(std::ostream &      script,
           const std::string & data,
           const std::string & xLabel,
           const std::string & yLabel,
           const std::string & title,
           int                 aboveColumn,
           int                 belowColumn)
{
  script << "set title " << Quoted(title) << "\n"
         << "set xlabel " << Quoted(xLabel) << "\n"
         << "set ylabel " << Quoted(yLabel) << "\n"
         << "plot " << Quoted(data) << " using 1:" << aboveColumn
         << " with linespoints pt 7 ps 0.6 lw 2 title 'above (>= S)', '' using 1:" << belowColumn
         << " with linespoints pt 5 ps 0.6 lw 2 title 'below (< S)'\n";
}
} // namespace

void
CheckPlotterAvailable()
{
  FindPlotter();
}

void
PlotReport(const Report &      report,
           size_t              kIndex,
           size_t              rowIndex,
           const std::string & path,
           const std::string & finalPath,
           const std::string & title)
{
  const fs::path           plotter = FindPlotter();
  const TemporaryDirectory directory;
  const fs::path           byIsoValue = directory.Path() / "by-isovalue.dat";
  const fs::path           bySize = directory.Path() / "by-size.dat";
  {
    std::ofstream data(byIsoValue);
    data << "# isovalue above_removed below_removed above_voxels below_voxels\n";
    for (const ReportRow & row : report.Rows)
    {
      data << NumberText(row.IsoValue) << ' ' << row.Above.RemovedComponents[kIndex] << ' '
           << row.Below.RemovedComponents[kIndex] << ' ' << row.Above.ModifiedVoxels[kIndex] << ' '
           << row.Below.ModifiedVoxels[kIndex] << '\n';
    }
  }
  {
    std::ofstream     data(bySize);
    const ReportRow & row = report.Rows[rowIndex];
    data << "# max_size above_removed below_removed above_voxels below_voxels\n";
    for (size_t k = 0; k < report.MaximumSizes.size(); ++k)
    {
      data << report.MaximumSizes[k] << ' ' << row.Above.RemovedComponents[k] << ' ' << row.Below.RemovedComponents[k]
           << ' ' << row.Above.ModifiedVoxels[k] << ' ' << row.Below.ModifiedVoxels[k] << '\n';
    }
  }

  const std::string K = std::to_string(report.MaximumSizes[kIndex]);
  const std::string S = NumberText(report.Rows[rowIndex].IsoValue);
  const fs::path    scriptPath = directory.Path() / "plot.gp";
  {
    std::ofstream script(scriptPath);
    script << "set terminal pngcairo noenhanced size 1400,1000 font 'sans,11'\n"
           << "set output " << Quoted(path) << "\n"
           << "set datafile commentschars '#'\n"
           << "set grid\nset key top right opaque box\nset autoscale xfix\nset offsets 0, 0, graph 0.05, 0\n"
           << "set yrange [0:*]\nset format y '%.0f'\n"
           << "set multiplot layout 2,2 title " << Quoted(title) << "\n";
    WritePanel(script,
               byIsoValue.string(),
               "isovalue S",
               "components removed",
               "Components of <= " + K + " voxels, by isovalue",
               2,
               3);
    WritePanel(script,
               byIsoValue.string(),
               "isovalue S",
               "voxels modified",
               "Voxels in components of <= " + K + " voxels, by isovalue",
               4,
               5);
    WritePanel(script,
               bySize.string(),
               "maximum size K (voxels)",
               "components removed",
               "Components of <= K voxels at isovalue " + S,
               2,
               3);
    WritePanel(script,
               bySize.string(),
               "maximum size K (voxels)",
               "voxels modified",
               "Voxels in components of <= K voxels at isovalue " + S,
               4,
               5);
    script << "unset multiplot\nset output\n";
    if (!script)
    {
      throw ToolError("cannot write the gnuplot script in " + directory.Path().string());
    }
  }
  const fs::path log = directory.Path() / "gnuplot.log";
  const int      status = RunProgram(plotter, { scriptPath.string() }, log);
  if (status != 0)
  {
    throw ToolError("gnuplot failed to draw '" + finalPath + "' (" +
                    (status < 0 ? std::string("it could not be run") : "exit status " + std::to_string(status)) +
                    "): " + ShowFinalPaths(FirstMessage(log), path, finalPath));
  }
  std::error_code error;
  if (fs::file_size(path, error) == 0 || error)
  {
    throw ToolError("gnuplot wrote no picture to '" + finalPath + "'");
  }
  // gnuplot exits 0 when it could write only part of the picture (a full disk).
  CheckWrittenImageFile(path, finalPath, "plot");
}
} // namespace sic
