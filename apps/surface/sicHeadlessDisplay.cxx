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

#include "sicToolError.h"

#include <X11/Xlib.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

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

/** The path of the Xvfb program on $PATH, or empty. */
std::string
FindXvfb()
{
  const char * path = std::getenv("PATH");
  std::string  directories = path != nullptr ? path : "/usr/bin:/bin";
  size_t       start = 0;
  while (start <= directories.size())
  {
    const size_t      end = std::min(directories.find(':', start), directories.size());
    const std::string directory = directories.substr(start, end - start);
    const std::string candidate = (directory.empty() ? std::string(".") : directory) + "/Xvfb";
    if (access(candidate.c_str(), X_OK) == 0)
    {
      return candidate;
    }
    start = end + 1;
  }
  return "";
}

const char * const MissingDisplay =
  "rendering needs an X display and there is none ($DISPLAY is unset or cannot be opened) and no Xvfb "
  "program on $PATH to start one; expected Xvfb (Debian package xvfb, installed by scripts/setup.sh) or a "
  "working $DISPLAY";
} // namespace

void
HeadlessDisplay::CheckAvailable()
{
  if (!DisplayWorks() && FindXvfb().empty())
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
  const std::string xvfb = FindXvfb();
  if (xvfb.empty())
  {
    throw ToolError(MissingDisplay);
  }
  const char * previous = std::getenv("DISPLAY");
  m_HadDisplay = previous != nullptr;
  m_PreviousDisplay = previous != nullptr ? previous : "";

  int channel[2];
  if (pipe(channel) != 0)
  {
    throw std::runtime_error(std::string("cannot start Xvfb: pipe failed: ") + std::strerror(errno));
  }
  const pid_t child = fork();
  if (child < 0)
  {
    close(channel[0]);
    close(channel[1]);
    throw std::runtime_error(std::string("cannot start Xvfb: fork failed: ") + std::strerror(errno));
  }
  if (child == 0)
  {
    // Xvfb writes the display number it chose to the pipe once it accepts connections.
    close(channel[0]);
    const int quiet = open("/dev/null", O_WRONLY);
    if (quiet >= 0)
    {
      dup2(quiet, STDOUT_FILENO);
      dup2(quiet, STDERR_FILENO);
    }
    const std::string fd = std::to_string(channel[1]);
    execl(xvfb.c_str(),
          "Xvfb",
          "-displayfd",
          fd.c_str(),
          "-screen",
          "0",
          "1920x1080x24",
          "-nolisten",
          "tcp",
          "-noreset",
          static_cast<char *>(nullptr));
    _exit(127);
  }
  close(channel[1]);
  m_Server = child;

  std::string number;
  const auto  deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (number.find('\n') == std::string::npos)
  {
    const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    pollfd wait{ channel[0], POLLIN, 0 };
    if (left <= 0 || poll(&wait, 1, static_cast<int>(left)) <= 0)
    {
      break;
    }
    char      text[32];
    const int got = static_cast<int>(read(channel[0], text, sizeof(text)));
    if (got <= 0)
    {
      break;
    }
    number.append(text, static_cast<size_t>(got));
  }
  close(channel[0]);
  while (!number.empty() && (number.back() == '\n' || number.back() == '\r'))
  {
    number.pop_back();
  }
  if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos)
  {
    kill(m_Server, SIGTERM);
    waitpid(m_Server, nullptr, 0);
    m_Server = -1;
    throw std::runtime_error("cannot render: " + xvfb + " did not start a virtual display within 30 s");
  }
  setenv("DISPLAY", (":" + number).c_str(), 1);
}

HeadlessDisplay::~HeadlessDisplay()
{
  if (m_Server <= 0)
  {
    return;
  }
  kill(m_Server, SIGTERM);
  waitpid(m_Server, nullptr, 0);
  if (m_HadDisplay)
  {
    setenv("DISPLAY", m_PreviousDisplay.c_str(), 1);
  }
  else
  {
    unsetenv("DISPLAY");
  }
}
} // namespace sic
