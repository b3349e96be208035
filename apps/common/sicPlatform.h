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
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace sic
{
/** Creates a new directory in \a parent, named \a prefix followed by six random characters, that no other process
 * creates too, and returns its path. On failure returns an empty path and sets \a error. */
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

/** Makes the signals that ask a process to stop (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM,
 * SIGVTALRM, SIGXCPU, and SIGPIPE and SIGXFSZ of a failed write; those of them not ignored) run every
 * TerminationAction first; then the signal ends the process as it would have, so its exit status still says which
 * signal ended it. On POSIX systems a thread of its own waits for them, blocked in every other thread (SIGPIPE and
 * SIGXFSZ, which go to the thread that wrote, are passed on to it), so the actions run as ordinary code: call this
 * first in main, before any other thread starts (programs started with RunProgram() and BackgroundProgram get the
 * signals unblocked). Throws std::system_error when that thread cannot start. Elsewhere a signal handler runs the
 * actions (SIGINT and SIGTERM). A second call does nothing. */
void
HandleTerminationSignals();

/** Makes std::terminate() (a library that gives up, e.g. ITK's thread pool when one of its threads cannot start)
 * run every TerminationAction, print one line prefixed with \a toolName and end the process with status 1 (out of
 * memory, or the exception's message where there is one) instead of aborting. */
void
HandleTerminate(const std::string & toolName);

/** What to undo when a termination signal ends the process (see HandleTerminationSignals()), from construction
 * to destruction; destruction waits for the action when it is running. The action runs on another thread: it
 * must lock what it shares with the rest of the program, and must not throw. */
class TerminationAction
{
public:
  explicit TerminationAction(std::function<void()> action);
  TerminationAction(const TerminationAction &) = delete;
  TerminationAction &
  operator=(const TerminationAction &) = delete;
  ~TerminationAction();

private:
  std::uint64_t m_Id;
};

/** Diverts everything the process writes to its standard error (C++ streams, C stdio, libraries' own prints) from
 * construction until Replay() writes it where it would have gone, or destruction drops it. ITK's, VTK's and their
 * libraries' writers print their own lines about a failure that the tools report as one line of their own; after
 * a success their messages are replayed. Captures nothing when no temporary file can be made. */
class StandardErrorCapture
{
public:
  StandardErrorCapture();
  StandardErrorCapture(const StandardErrorCapture &) = delete;
  StandardErrorCapture &
  operator=(const StandardErrorCapture &) = delete;
  ~StandardErrorCapture();

  /** Ends the capture and writes what was captured to the standard error. */
  void
  Replay();

private:
  /** Ends the capture and returns what was captured. */
  std::string
  Restore();

  int         m_Saved{ -1 };
  std::FILE * m_File{ nullptr };
};

/** Whether the standard error stream is a terminal (where a progress bar can be redrawn). */
bool
StandardErrorIsTerminal();

/** Whether the tools can start other programs here (RunProgram(), BackgroundProgram): on POSIX systems only. */
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

/** A program running in the background, its output discarded, until this object is destroyed, which terminates it and
 * waits for it to end. The program is given the write end of a pipe, whose descriptor number follows \a pipeFlag on its
 * command line, before \a arguments (Xvfb -displayfd N ...); ReadLine() reads what it writes there. */
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
