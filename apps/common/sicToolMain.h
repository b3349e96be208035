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
#ifndef sicToolMain_h
#define sicToolMain_h

#include "sicCommandLine.h"

#include <functional>

namespace sic
{
/** The main() of a tool: parses the command line against \a tool, prints --help (and, for a tool that offers it, the
 * Slicer description for --xml), then calls \a run. Every error becomes one line on stderr, prefixed with the tool's
 * name, and an exit status: ExitUsage for a ToolError (a wrong command line, an input or output that cannot be used),
 * ExitFailure for anything else (out of memory, a thread that cannot start), std::terminate() included
 * (HandleTerminate()). After a failure the process ends at once, without static destructors. */
int
ToolMain(const ToolDescription &                               tool,
         int                                                   argc,
         char *                                                argv[],
         const std::function<int(const ParsedCommandLine &)> & run);
} // namespace sic

#endif
