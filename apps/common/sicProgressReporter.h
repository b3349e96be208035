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
#ifndef sicProgressReporter_h
#define sicProgressReporter_h

#include "itkCommand.h"

#include <chrono>
#include <string>

namespace sic
{
/** Tells the user how far a tool has got, in one of four styles:
 * - Silent: nothing (--quiet);
 * - Bar: a bar on stderr, redrawn in place, when stderr is a terminal;
 * - Lines: one line on stderr per stage, when stderr is a file or a pipe;
 * - SlicerXml: the lines 3D Slicer reads from a CLI module's stdout
 *   (<filter-start>, <filter-progress>, <filter-end>), flushed as they are written.
 *
 * The work is split into stages, each covering a part [begin, end] of the whole; Update()
 * and the ITK observer report the fraction done within the current stage. */
class ProgressReporter
{
public:
  /** Silent when \a quiet, SlicerXml when \a slicerXml, else Bar or Lines depending on whether stderr is a terminal.
   * \a name names the tool, \a comment says what it does (Slicer shows both). */
  ProgressReporter(bool quiet, bool slicerXml, std::string name, std::string comment);
  ProgressReporter(const ProgressReporter &) = delete;
  ProgressReporter &
  operator=(const ProgressReporter &) = delete;
  /** Clears an unfinished bar, so that an error message starts on a clean line. */
  ~ProgressReporter();

  /** Starts a stage described as \a description covering [begin, end] of the work. */
  void
  Stage(const std::string & description, double begin, double end);

  /** Reports that \a fraction (0 to 1) of the current stage is done. */
  void
  Update(double fraction);

  /** An observer for itk::ProgressEvent that reports the process object's progress within the current stage. */
  itk::Command *
  Observer();

  /** Ends the report after success. */
  void
  Finish();

private:
  enum class Style
  {
    Silent,
    Bar,
    Lines,
    SlicerXml
  };

  void
  OnProgress(itk::Object * caller, const itk::EventObject & event);
  void
  ClearBar();

  Style                                         m_Style;
  std::string                                   m_Name;
  std::string                                   m_StageDescription;
  double                                        m_StageBegin{ 0.0 };
  double                                        m_StageEnd{ 0.0 };
  double                                        m_Progress{ 0.0 };
  int                                           m_Shown{ -1 };
  bool                                          m_BarDrawn{ false };
  std::chrono::steady_clock::time_point         m_Start;
  itk::MemberCommand<ProgressReporter>::Pointer m_Observer;
};
} // namespace sic

#endif
