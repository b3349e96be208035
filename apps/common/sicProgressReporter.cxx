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
#include "sicProgressReporter.h"
#include "sicPlatform.h"
#include "sicStrings.h"

#include "itkProcessObject.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace sic
{
namespace
{
constexpr int BarWidth = 30;
} // namespace

ProgressReporter::ProgressReporter(bool quiet, bool slicerXml, std::string name, std::string comment)
  : m_Style(quiet       ? Style::Silent
            : slicerXml ? Style::SlicerXml
                        : (StandardErrorIsTerminal() ? Style::Bar : Style::Lines))
  , m_Name(std::move(name))
  , m_Start(std::chrono::steady_clock::now())
{
  m_Observer = itk::MemberCommand<ProgressReporter>::New();
  m_Observer->SetCallbackFunction(this, &ProgressReporter::OnProgress);
  if (m_Style == Style::SlicerXml)
  {
    std::cout << "<filter-start><filter-name>" << XmlEscaped(m_Name) << "</filter-name><filter-comment>"
              << XmlEscaped(comment) << "</filter-comment></filter-start>" << std::endl;
  }
}

ProgressReporter::~ProgressReporter()
{
  ClearBar();
}

void
ProgressReporter::ClearBar()
{
  if (m_BarDrawn)
  {
    std::cerr << "\r\x1b[K" << std::flush;
    m_BarDrawn = false;
  }
}

void
ProgressReporter::Stage(const std::string & description, double begin, double end)
{
  m_StageDescription = description;
  m_StageBegin = begin;
  m_StageEnd = end;
  if (m_Style == Style::Lines)
  {
    std::cerr << m_Name << ": " << description << std::endl;
  }
  m_Shown = -1;
  Update(0.0);
}

void
ProgressReporter::Update(double fraction)
{
  fraction = std::clamp(fraction, 0.0, 1.0);
  m_Progress = std::max(m_Progress, m_StageBegin + fraction * (m_StageEnd - m_StageBegin));
  // Redraw only when the shown percentage changes.
  const int percent = static_cast<int>(m_Progress * 100.0);
  if (percent == m_Shown)
  {
    return;
  }
  m_Shown = percent;
  if (m_Style == Style::Bar)
  {
    const int filled = static_cast<int>(m_Progress * BarWidth);
    std::cerr << '\r' << m_Name << " [" << std::string(filled, '#') << std::string(BarWidth - filled, '.') << "] "
              << percent << "% " << m_StageDescription << "\x1b[K" << std::flush;
    m_BarDrawn = true;
  }
  else if (m_Style == Style::SlicerXml)
  {
    char text[32];
    std::snprintf(text, sizeof(text), "%.2f", m_Progress);
    std::cout << "<filter-progress>" << text << "</filter-progress>" << std::endl;
  }
}

itk::Command *
ProgressReporter::Observer()
{
  return m_Observer.GetPointer();
}

void
ProgressReporter::OnProgress(itk::Object * caller, const itk::EventObject & event)
{
  const auto * process = dynamic_cast<itk::ProcessObject *>(caller);
  if (process && itk::ProgressEvent().CheckEvent(&event))
  {
    Update(process->GetProgress());
  }
}

void
ProgressReporter::Finish()
{
  m_StageBegin = m_StageEnd = 1.0;
  Update(1.0);
  ClearBar();
  if (m_Style == Style::SlicerXml)
  {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_Start).count();
    std::cout << "<filter-end><filter-name>" << XmlEscaped(m_Name) << "</filter-name><filter-time>" << seconds
              << "</filter-time></filter-end>" << std::endl;
  }
}
} // namespace sic
