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
#include "sicRender.h"

#include "sicImageFiles.h"
#include "sicPlatform.h"
#include "sicToolError.h"
#include "sicVtkErrors.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkPNGWriter.h"
#include "vtkPolyData.h"
#include "vtkCellData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataNormals.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <vector>

namespace sic
{
namespace
{
bool
HasTriangles(vtkPolyData * surface)
{
  return surface != nullptr && surface->GetPolys() != nullptr && surface->GetPolys()->GetNumberOfCells() > 0;
}

/** An actor drawing \a surface smoothly shaded in \a colour. */
vtkSmartPointer<vtkActor>
SurfaceActor(vtkPolyData * surface, const std::array<double, 3> & colour, double opacity)
{
  auto normals = vtkSmartPointer<vtkPolyDataNormals>::New();
  normals->SetInputData(surface);
  normals->SplittingOff();
  normals->ConsistencyOff();
  normals->ComputeCellNormalsOff();
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputConnection(normals->GetOutputPort());
  // A label surface carries each triangle's colour (ColourLabels()); other surfaces take the panel's colour.
  if (surface->GetCellData()->GetScalars() != nullptr)
  {
    mapper->SetScalarModeToUseCellData();
    mapper->SetColorModeToDirectScalars();
  }
  else
  {
    mapper->ScalarVisibilityOff();
  }
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(colour[0], colour[1], colour[2]);
  actor->GetProperty()->SetSpecular(0.15);
  actor->GetProperty()->SetSpecularPower(20.0);
  actor->GetProperty()->SetOpacity(opacity);
  return actor;
}

} // namespace

void
RenderPanels(const RenderScene & scene, const std::string & path, const std::string & finalPath)
{
  // One camera for all four panels, framing everything that is drawn anywhere.
  double bounds[6] = { std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                       std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                       std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest() };
  bool   anything = false;
  for (vtkPolyData * surface : { scene.Before, scene.After, scene.RemovedSpecks, scene.RemovedBubbles })
  {
    if (!HasTriangles(surface))
    {
      continue;
    }
    double own[6];
    surface->GetBounds(own);
    for (int axis = 0; axis < 3; ++axis)
    {
      bounds[2 * axis] = std::min(bounds[2 * axis], own[2 * axis]);
      bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], own[2 * axis + 1]);
    }
    anything = true;
  }
  if (!anything)
  {
    std::fill(bounds, bounds + 6, 0.0);
    bounds[1] = bounds[3] = bounds[5] = 1.0;
  }
  auto camera = vtkSmartPointer<vtkCamera>::New();
  // ITK's physical space is LPS: look at the front (from anterior, -y) with superior (+z) up,
  // turned a little so that depth shows.
  camera->SetFocalPoint(0.0, 0.0, 0.0);
  camera->SetPosition(0.0, -1.0, 0.0);
  camera->SetViewUp(0.0, 0.0, 1.0);
  camera->Azimuth(30.0);
  camera->Elevation(20.0);
  camera->OrthogonalizeViewUp();

  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(scene.Width, scene.Height);

  const double viewports[4][4] = {
    { 0.0, 0.5, 0.5, 1.0 }, { 0.5, 0.5, 1.0, 1.0 }, { 0.0, 0.0, 0.5, 0.5 }, { 0.5, 0.0, 1.0, 0.5 }
  };
  std::vector<vtkSmartPointer<vtkRenderer>> renderers;
  for (int panel = 0; panel < 4; ++panel)
  {
    auto renderer = vtkSmartPointer<vtkRenderer>::New();
    renderer->SetViewport(viewports[panel]);
    renderer->SetBackground(BackgroundColour[0], BackgroundColour[1], BackgroundColour[2]);
    renderer->SetActiveCamera(camera);
    const auto add = [&renderer](vtkPolyData * surface, const std::array<double, 3> & colour, double opacity) {
      if (HasTriangles(surface))
      {
        renderer->AddActor(SurfaceActor(surface, colour, opacity));
      }
    };
    if (panel == 0)
    {
      add(scene.Before, SurfaceColour, 1.0);
    }
    if (panel == 1)
    {
      add(scene.After, SurfaceColour, 1.0);
    }
    if (panel == 3)
    {
      // Translucent, so that the bubbles inside the object show.
      add(scene.After, SurfaceColour, 0.45);
    }
    if (panel >= 2)
    {
      add(scene.RemovedSpecks, SpeckColour, 1.0);
      add(scene.RemovedBubbles, BubbleColour, 1.0);
    }
    auto label = vtkSmartPointer<vtkTextActor>::New();
    label->SetInput(scene.Labels[static_cast<size_t>(panel)].c_str());
    label->GetTextProperty()->SetFontSize(std::max(12, scene.Height / 40));
    label->GetTextProperty()->SetColor(1.0, 1.0, 1.0);
    label->GetTextProperty()->SetFontFamilyToArial();
    label->GetTextProperty()->SetVerticalJustificationToTop();
    label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    label->GetPositionCoordinate()->SetValue(0.02, 0.97);
    renderer->AddActor2D(label);
    window->AddRenderer(renderer);
    renderers.push_back(renderer);
  }
  renderers.front()->ResetCamera(bounds);
  for (const auto & renderer : renderers)
  {
    renderer->ResetCameraClippingRange(bounds);
  }
  window->Render();

  auto capture = vtkSmartPointer<vtkWindowToImageFilter>::New();
  capture->SetInput(window);
  capture->SetInputBufferTypeToRGB();
  capture->ReadFrontBufferOff();
  capture->Update();

  auto writer = vtkSmartPointer<vtkPNGWriter>::New();
  auto failed = vtkSmartPointer<VtkErrorCollector>::New();
  writer->AddObserver(vtkCommand::ErrorEvent, failed);
  writer->SetInputConnection(capture->GetOutputPort());
  writer->SetFileName(path.c_str());
  // libpng prints its own lines about a failed write; the error below says it in one.
  StandardErrorCapture messages;
  writer->Write();
  std::error_code error;
  if (failed->Raised || writer->GetErrorCode() != 0 || !std::filesystem::exists(path, error))
  {
    throw ToolError("cannot write the rendering to '" + finalPath + "'");
  }
  CheckWrittenImageFile(path, finalPath, "rendering");
  messages.Replay();
}
} // namespace sic
