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
#include "sicHeadlessDisplay.h"

#include "sicPlatform.h"
#include "sicToolError.h"

// Before Xlib.h, whose macros (Status, None) would clash with newer KWSys headers.
#include <itksys/SystemTools.hxx>

#include <X11/Xlib.h>

#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace sic
{
namespace
{
/** Whether the display $DISPLAY names can be opened. */
bool
DisplayWorks()
{
  const char * name = std::getenv("DISPLAY");
  if (name == nullptr || *name == '\0')
  {
    return false;
  }
  Display * display = XOpenDisplay(nullptr);
  if (display == nullptr)
  {
    return false;
  }
  XCloseDisplay(display);
  return true;
}

const char * const Xvfb = "Xvfb";

const char * const MissingDisplay =
  "rendering needs an X display and there is none ($DISPLAY is unset or cannot be opened) and no Xvfb "
  "program on $PATH to start one; expected Xvfb (Debian package xvfb, installed by scripts/setup.sh) or a "
  "working $DISPLAY";
} // namespace

void
HeadlessDisplay::CheckAvailable()
{
  if (!DisplayWorks() && FindProgram(Xvfb).empty())
  {
    throw ToolError(MissingDisplay);
  }
}

HeadlessDisplay::HeadlessDisplay()
{
  if (DisplayWorks())
  {
    return;
  }
  const std::filesystem::path xvfb = FindProgram(Xvfb);
  if (xvfb.empty())
  {
    throw ToolError(MissingDisplay);
  }
  // Xvfb writes the display number it chose to its pipe once it accepts connections.
  auto server = std::make_unique<BackgroundProgram>(
    xvfb, "-displayfd", std::vector<std::string>{ "-screen", "0", "1920x1080x24", "-nolisten", "tcp", "-noreset" });
  const std::string number = server->ReadLine(std::chrono::seconds(30));
  if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos)
  {
    throw std::runtime_error("cannot render: " + xvfb.string() + " did not start a virtual display within 30 s");
  }
  if (const char * previous = std::getenv("DISPLAY"))
  {
    m_PreviousDisplay = previous;
  }
  m_Server = std::move(server);
  itksys::SystemTools::PutEnv("DISPLAY=:" + number);
}

HeadlessDisplay::~HeadlessDisplay()
{
  if (!m_Server)
  {
    return;
  }
  m_Server.reset();
  if (m_PreviousDisplay)
  {
    itksys::SystemTools::PutEnv("DISPLAY=" + *m_PreviousDisplay);
  }
  else
  {
    itksys::SystemTools::UnPutEnv("DISPLAY");
  }
}
} // namespace sic
