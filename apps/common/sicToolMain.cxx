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
#include "sicToolMain.h"
#include "sicPlatform.h"
#include "sicToolError.h"

#include "itkMacro.h"
#include "itkObjectFactory.h"
#include "itkOutputWindow.h"

#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>
#include <system_error>

namespace sic
{
namespace
{
/** ITK's messages, but none while an exception unwinds: in ITK 5.4, every ITK object destroyed
 * then because its constructor failed (a thread that could not start) warns of its reference count,
 * and a failed run says what failed in one line. */
class OutputWindowOutsideUnwinding : public itk::OutputWindow
{
public:
  using Pointer = itk::SmartPointer<OutputWindowOutsideUnwinding>;
  itkNewMacro(OutputWindowOutsideUnwinding);

  void
  DisplayText(const char * text) override
  {
    if (std::uncaught_exceptions() == 0)
    {
      itk::OutputWindow::DisplayText(text);
    }
  }
};

int
RunTool(const ToolDescription &                               tool,
        int                                                   argc,
        char *                                                argv[],
        const std::function<int(const ParsedCommandLine &)> & run)
{
  try
  {
    // Before any thread starts: a termination signal then removes the staged outputs first.
    HandleTerminationSignals();
    const ParsedCommandLine arguments = ParseCommandLine(tool, argc, argv);
    if (arguments.Has("--help"))
    {
      std::cout << HelpText(tool);
      return ExitSuccess;
    }
    // Only a tool that offers --xml gets past the parser with it.
    if (arguments.Has("--xml"))
    {
      std::cout << SlicerDescriptionXml(tool);
      return ExitSuccess;
    }
    return run(arguments);
  }
  catch (const ToolError & error)
  {
    std::cerr << tool.Name << ": " << error.what() << std::endl;
    return ExitUsage;
  }
  catch (const itk::MemoryAllocationError &)
  {
    std::cerr << tool.Name << ": out of memory" << std::endl;
    return ExitFailure;
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << tool.Name << ": " << ItkErrorText(error.GetDescription()) << std::endl;
    return ExitFailure;
  }
  catch (const std::bad_alloc &)
  {
    std::cerr << tool.Name << ": out of memory" << std::endl;
    return ExitFailure;
  }
  catch (const std::system_error & error)
  {
    // EAGAIN is what std::thread throws when a thread cannot start (no memory or address space for its stack).
    const bool thread = error.code() == std::errc::resource_unavailable_try_again;
    std::cerr << tool.Name << ": " << (thread ? "cannot start a thread (out of memory or address space): " : "")
              << OneLine(error.what()) << std::endl;
    return ExitFailure;
  }
  catch (const std::exception & error)
  {
    std::cerr << tool.Name << ": " << OneLine(error.what()) << std::endl;
    return ExitFailure;
  }
}
} // namespace

int
ToolMain(const ToolDescription &                               tool,
         int                                                   argc,
         char *                                                argv[],
         const std::function<int(const ParsedCommandLine &)> & run)
{
  HandleTerminate(tool.Name);
  itk::OutputWindow::SetInstance(OutputWindowOutsideUnwinding::New());
  const int status = RunTool(tool, argc, argv, run);
  if (status != ExitSuccess)
  {
    // A failure can leave ITK's singletons half made (a thread pool whose threads could not all start), and
    // destroying them would crash: a failed run ends without the static destructors. Its outputs are gone already.
    std::cout.flush();
    std::cerr.flush();
    std::_Exit(status);
  }
  return status;
}
} // namespace sic
