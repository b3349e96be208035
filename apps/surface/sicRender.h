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
#ifndef sicRender_h
#define sicRender_h

#include <array>
#include <string>

class vtkPolyData;

namespace sic
{
/** What the four panels of --render show, all surfaces in physical coordinates. */
struct RenderScene
{
  vtkPolyData * Before{ nullptr };
  vtkPolyData * After{ nullptr };
  vtkPolyData * RemovedSpecks{ nullptr };
  vtkPolyData * RemovedBubbles{ nullptr };
  /** The labels of the panels: original, filtered, removed, filtered + removed. */
  std::array<std::string, 4> Labels;
  /** Size of the whole picture in pixels (four panels of half that size). */
  int Width{ 1600 };
  int Height{ 1200 };
};

/** The colours of the panels (RGB in [0, 1]); the tests look for them. */
constexpr std::array<double, 3> SurfaceColour{ { 0.90, 0.86, 0.78 } };
constexpr std::array<double, 3> SpeckColour{ { 0.95, 0.12, 0.10 } };
constexpr std::array<double, 3> BubbleColour{ { 0.10, 0.35, 1.00 } };
constexpr std::array<double, 3> BackgroundColour{ { 0.12, 0.13, 0.16 } };

/** Renders \a scene off screen into a PNG at \a path: the original surface (top left), the
 * filtered one (top right), only the removed triangles with specks and bubbles in their two
 * colours (bottom left), and the filtered surface, translucent so that bubbles inside show,
 * with the removed triangles (bottom right), each panel labelled, one
 * camera for all four. Needs an X display (see HeadlessDisplay). Throws sic::ToolError if the
 * PNG cannot be written. */
void
RenderPanels(const RenderScene & scene, const std::string & path, const std::string & finalPath);
} // namespace sic

#endif
