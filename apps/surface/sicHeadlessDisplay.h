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
#ifndef sicHeadlessDisplay_h
#define sicHeadlessDisplay_h

#include <memory>
#include <optional>
#include <string>

namespace sic
{
class BackgroundProgram;

/** An X display for VTK's off-screen rendering. Debian's VTK renders through X (it has no
 * EGL or OSMesa back end), so on a machine without a display the tool starts its own virtual
 * one: if $DISPLAY is unset or cannot be opened, the constructor starts Xvfb on a free
 * display number, points $DISPLAY at it, and the destructor stops it. */
class HeadlessDisplay
{
public:
  /** Throws sic::ToolError, before any work is done, if there is neither a working $DISPLAY
   * nor an Xvfb program to start. */
  static void
  CheckAvailable();

  HeadlessDisplay();
  HeadlessDisplay(const HeadlessDisplay &) = delete;
  HeadlessDisplay &
  operator=(const HeadlessDisplay &) = delete;
  ~HeadlessDisplay();

private:
  /** The Xvfb this object started, if it started one. */
  std::unique_ptr<BackgroundProgram> m_Server;
  /** $DISPLAY before Xvfb replaced it; none when it was unset. */
  std::optional<std::string> m_PreviousDisplay;
};
} // namespace sic

#endif
