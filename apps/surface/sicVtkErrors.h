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
#ifndef sicVtkErrors_h
#define sicVtkErrors_h

#include "sicToolError.h"

#include "vtkCommand.h"

#include <string>

namespace sic
{
/** Observes a VTK object's ErrorEvent, so that the tools report the error themselves instead
 * of VTK printing it: whether one was raised, and the first message on one line. */
class VtkErrorCollector : public vtkCommand
{
public:
  static VtkErrorCollector *
  New()
  {
    return new VtkErrorCollector;
  }

  void
  Execute(vtkObject *, unsigned long, void * callData) override
  {
    if (callData != nullptr && Message.empty())
    {
      Message = OneLine(static_cast<const char *>(callData));
    }
    Raised = true;
  }

  bool        Raised{ false };
  std::string Message;
};
} // namespace sic

#endif
