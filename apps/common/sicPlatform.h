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
#ifndef sicPlatform_h
#define sicPlatform_h

// What the tools need from the operating system beyond standard C++. POSIX systems (Linux,
// macOS) have all of it; elsewhere what has no simple equivalent (starting other programs)
// throws ToolError saying so, so that the tools still build wherever ITK builds.

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <cstdint>
#include <vector>

namespace sic
{
/** Creates a new directory in \a parent, named \a prefix followed by six random characters,
 * that no other process creates too, and returns its path. On failure returns an empty path
 * and sets \a error. */
std::filesystem::path
CreateUniqueDirectory(const std::filesystem::path & parent, const std::string & prefix, std::error_code & error);

/** The most memory this process has held at once (its peak resident set), in bytes, or 0 where
 * the system does not tell. */
std::uint64_t
PeakResidentBytes();

/** The memory the system could give this process now without swapping (Linux: MemAvailable), in
 * bytes, or 0 where the system does not tell. */
std::uint64_t
AvailableMemoryBytes();

/** Whether the standard error stream is a terminal (where a progress bar can be redrawn). */
bool
StandardErrorIsTerminal();

/** Sets the environment variable \a name to \a value for this process and the programs it
 * starts. */
void
SetEnvironmentVariable(const std::string & name, const std::string & value);

/** Removes the environment variable \a name. */
void
UnsetEnvironmentVariable(const std::string & name);

/** Whether the tools can start other programs here (RunProgram(), BackgroundProgram): on
 * POSIX systems only. */
bool
CanStartPrograms();

/** The executable \a name in the first directory of $PATH that has it (the system's default
 * path when $PATH is unset), or an empty path. */
std::filesystem::path
FindProgram(const std::string & name);

/** Runs \a program with \a arguments, its standard output and error written to the file
 * \a log, and waits for it. Returns its exit status, or -1 when it could not be started or
 * did not exit normally. Throws ToolError where programs cannot be started. */
int
RunProgram(const std::filesystem::path &    program,
           const std::vector<std::string> & arguments,
           const std::filesystem::path &    log);

/** A program running in the background, its output discarded, until this object is
 * destroyed, which terminates it and waits for it to end. The program is given the write
 * end of a pipe, whose descriptor number follows \a pipeFlag on its command line, before
 * \a arguments (Xvfb -displayfd N ...); ReadLine() reads what it writes there. */
class BackgroundProgram
{
public:
  /** Throws std::runtime_error if the program cannot be started, and ToolError where
   * programs cannot be started at all. */
  BackgroundProgram(const std::filesystem::path &    program,
                    const std::string &              pipeFlag,
                    const std::vector<std::string> & arguments);
  BackgroundProgram(const BackgroundProgram &) = delete;
  BackgroundProgram &
  operator=(const BackgroundProgram &) = delete;
  ~BackgroundProgram();

  /** What the program writes to its pipe up to the first line end, waiting at most
   * \a timeout (all it wrote when it closed the pipe or the time ran out first). */
  std::string
  ReadLine(std::chrono::milliseconds timeout);

private:
  struct Process;
  std::unique_ptr<Process> m_Process;
};
} // namespace sic

#endif
