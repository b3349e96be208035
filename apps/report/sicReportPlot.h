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
#ifndef sicReportPlot_h
#define sicReportPlot_h

#include "sicReportTable.h"

#include <string>

namespace sic
{
/** Throws ToolError unless gnuplot can be run (an executable "gnuplot" on PATH). */
void
CheckPlotterAvailable();

/** Draws \a report into the PNG file \a path with gnuplot, 2 × 2 panels: components
 * removed and voxels modified against the isovalue at maximum size K = MaximumSizes[kIndex]
 * (top), and against K at isovalue Rows[rowIndex] (bottom), one curve per side. The data
 * and the gnuplot script go to a temporary directory, removed afterwards (and by a
 * termination signal). \a title heads the picture. Throws ToolError, naming \a finalPath
 * (where the picture goes in the end), when gnuplot is missing or fails or the PNG file it
 * wrote is incomplete. */
void
PlotReport(const Report &      report,
           size_t              kIndex,
           size_t              rowIndex,
           const std::string & path,
           const std::string & finalPath,
           const std::string & title);
} // namespace sic

#endif
