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
#include "sicPlatform.h"

#include "sicToolError.h"

#include <itksys/SystemTools.hxx>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <exception>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <new>
#include <stdexcept>

#ifdef _WIN32
#  include <io.h>
#  include <random>
#else
#  include <cerrno>
#  include <fcntl.h>
#  include <poll.h>
#  include <pthread.h>
#  include <signal.h>
#  include <spawn.h>
#  include <sys/wait.h>
#  include <thread>
#  include <unistd.h>

extern char ** environ;
#endif

namespace sic
{
namespace fs = std::filesystem;

namespace
{
#ifdef _WIN32
constexpr char     PathSeparator = ';';
const char * const DefaultPath = "";
const char * const ProgramSuffix = ".exe";
#else
constexpr char PathSeparator = ':';
// What the exec functions search when $PATH is unset.
const char * const DefaultPath = "/usr/bin:/bin";
const char * const ProgramSuffix = "";
#endif

struct TerminationActions
{
  std::mutex                                     Mutex;
  std::map<std::uint64_t, std::function<void()>> Actions;
  std::uint64_t                                  Next{ 0 };
};

/** Never destroyed: a signal may come while static objects are being destroyed. */
TerminationActions &
Registry()
{
  static auto * registry = new TerminationActions;
  return *registry;
}

/** Runs every action and leaves the registry locked, as the process is about to end: no action starts or ends
 * after the cleanup. */
void
RunTerminationActions()
{
  TerminationActions & registry = Registry();
  registry.Mutex.lock();
  for (auto & entry : registry.Actions)
  {
    entry.second();
  }
}

/** The tool that OnTerminate() names. */
std::string TerminatingTool;

[[noreturn]] void
OnTerminate()
{
  RunTerminationActions();
  std::string what = "out of memory or address space: a library could not go on (std::terminate)";
  if (const std::exception_ptr error = std::current_exception())
  {
    try
    {
      std::rethrow_exception(error);
    }
    catch (const std::bad_alloc &)
    {
      what = "out of memory";
    }
    catch (const std::exception & exception)
    {
      what = OneLine(exception.what());
    }
    catch (...)
    {}
  }
  std::fprintf(stderr, "%s: %s\n", TerminatingTool.c_str(), what.c_str());
  std::fflush(stderr);
  std::_Exit(ExitFailure);
}
} // namespace

void
HandleTerminate(const std::string & toolName)
{
  TerminatingTool = toolName;
  std::set_terminate(OnTerminate);
}

TerminationAction::TerminationAction(std::function<void()> action)
{
  TerminationActions &        registry = Registry();
  std::lock_guard<std::mutex> lock(registry.Mutex);
  m_Id = registry.Next++;
  registry.Actions.emplace(m_Id, std::move(action));
}

TerminationAction::~TerminationAction()
{
  TerminationActions &        registry = Registry();
  std::lock_guard<std::mutex> lock(registry.Mutex);
  registry.Actions.erase(m_Id);
}

fs::path
FindProgram(const std::string & name)
{
  const char *      path = std::getenv("PATH");
  const std::string directories = path != nullptr ? path : DefaultPath;
  size_t            begin = 0;
  while (begin <= directories.size())
  {
    const size_t   end = std::min(directories.find(PathSeparator, begin), directories.size());
    const fs::path directory = end == begin ? fs::path(".") : fs::path(directories.substr(begin, end - begin));
    const fs::path candidate = directory / (name + ProgramSuffix);
    if (itksys::SystemTools::FileIsExecutable(candidate.string()))
    {
      return candidate;
    }
    begin = end + 1;
  }
  return {};
}

namespace
{
// The C runtime's descriptor calls, spelled with an underscore on Windows.
#ifdef _WIN32
const auto Descriptor = _fileno;
const auto Duplicate = _dup;
const auto DuplicateOnto = _dup2;
const auto CloseDescriptor = _close;
const auto IsTerminal = _isatty;
#else
const auto         Descriptor = fileno;
const auto         Duplicate = dup;
const auto         DuplicateOnto = dup2;
const auto         CloseDescriptor = close;
const auto         IsTerminal = isatty;
#endif
} // namespace

StandardErrorCapture::StandardErrorCapture()
{
  std::cerr.flush();
  std::clog.flush();
  std::fflush(stderr);
  m_File = std::tmpfile();
  if (m_File == nullptr)
  {
    return;
  }
  m_Saved = Duplicate(Descriptor(stderr));
  if (m_Saved < 0 || DuplicateOnto(Descriptor(m_File), Descriptor(stderr)) < 0)
  {
    if (m_Saved >= 0)
    {
      CloseDescriptor(m_Saved);
    }
    std::fclose(m_File);
    m_File = nullptr;
  }
}

StandardErrorCapture::~StandardErrorCapture()
{
  Restore();
}

std::string
StandardErrorCapture::Restore()
{
  if (m_File == nullptr)
  {
    return {};
  }
  std::cerr.flush();
  std::clog.flush();
  std::fflush(stderr);
  DuplicateOnto(m_Saved, Descriptor(stderr));
  CloseDescriptor(m_Saved);
  std::string text;
  std::rewind(m_File);
  for (int c = std::fgetc(m_File); c != EOF; c = std::fgetc(m_File))
  {
    text += static_cast<char>(c);
  }
  std::fclose(m_File);
  m_File = nullptr;
  return text;
}

bool
StandardErrorIsTerminal()
{
  return IsTerminal(Descriptor(stderr)) != 0;
}

void
StandardErrorCapture::Replay()
{
  const std::string text = Restore();
  if (!text.empty())
  {
    std::cerr << text << std::flush;
  }
}

#ifdef _WIN32
// No POSIX here: std::filesystem and the C runtime where they do the job, a clear error where they do not.

namespace
{
std::string
NotSupported(const fs::path & program)
{
  return "cannot run " + program.filename().string() +
         ": starting other programs is not supported on this platform; expected a POSIX system";
}
extern "C" void
OnTerminationSignal(int received)
{
  RunTerminationActions();
  std::signal(received, SIG_DFL);
  std::raise(received);
}
} // namespace

void
HandleTerminationSignals()
{
  for (const int received : { SIGINT, SIGTERM })
  {
    std::signal(received, OnTerminationSignal);
  }
}

fs::path
CreateUniqueDirectory(const fs::path & parent, const std::string & prefix, std::error_code & error)
{
  const char         letters[] = "abcdefghijklmnopqrstuvwxyz0123456789";
  std::random_device seed;
  std::mt19937       random(seed());
  for (int attempt = 0; attempt < 100; ++attempt)
  {
    std::string name = prefix;
    for (int i = 0; i < 6; ++i)
    {
      name += letters[random() % (sizeof(letters) - 1)];
    }
    const fs::path directory = parent / name;
    // create_directory is false, without an error, when the directory exists already.
    if (fs::create_directory(directory, error))
    {
      return directory;
    }
    if (error)
    {
      return {};
    }
  }
  error = std::make_error_code(std::errc::file_exists);
  return {};
}

bool
CanStartPrograms()
{
  return false;
}

int
RunProgram(const fs::path & program, const std::vector<std::string> &, const fs::path &)
{
  throw ToolError(NotSupported(program));
}

struct BackgroundProgram::Process
{};

BackgroundProgram::BackgroundProgram(const fs::path & program, const std::string &, const std::vector<std::string> &)
{
  throw ToolError(NotSupported(program));
}

BackgroundProgram::~BackgroundProgram() = default;

std::string
BackgroundProgram::ReadLine(std::chrono::milliseconds)
{
  return {};
}

#else

namespace
{
/** Whether HandleTerminationSignals() blocked the termination signals, and the signal mask before it did. */
bool     SignalsBlocked = false;
sigset_t SignalMaskBefore;

/** Starts \a program with \a arguments, its standard output and error written to \a output (opened with \a flags)
 * and the descriptor \a unused (unless -1) closed. Returns 0 or the error number. The program gets the signal mask
 * the tool had before it blocked the termination signals: a program with them blocked could not be stopped. */
int
Spawn(pid_t &                  child,
      const fs::path &         program,
      std::vector<std::string> arguments,
      const char *             output,
      int                      flags,
      int                      unused)
{
  std::vector<char *> argv{ const_cast<char *>(program.c_str()) };
  for (std::string & argument : arguments)
  {
    argv.push_back(argument.data());
  }
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (unused >= 0)
  {
    posix_spawn_file_actions_addclose(&actions, unused);
  }
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, output, flags, 0600);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (SignalsBlocked)
  {
    posix_spawnattr_setsigmask(&attributes, &SignalMaskBefore);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
  }
  const int spawned = posix_spawn(&child, program.c_str(), &actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  return spawned;
}

/** The thread that waits for the termination signals. */
pthread_t Waiter;

/** SIGPIPE and SIGXFSZ are sent to the thread whose write failed, which sigwait() in another thread never sees:
 * this handler passes them on to the waiting thread. */
extern "C" void
PassOnToWaiter(int received)
{
  pthread_kill(Waiter, received);
}

/** The signals that end a process by default and ask it to stop: sent by a user, a batch system's limits (CPU
 * time, file size), or a failed write to a closed pipe. */
sigset_t
TerminationSignals()
{
  sigset_t signals;
  sigemptyset(&signals);
  for (const int candidate :
       { SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGXCPU, SIGXFSZ })
  {
    // An ignored signal stays ignored (nohup): blocked, it would be delivered to the waiting thread.
    struct sigaction current
    {};
    if (sigaction(candidate, nullptr, &current) == 0 && current.sa_handler != SIG_IGN)
    {
      sigaddset(&signals, candidate);
    }
  }
  return signals;
}

[[noreturn]] void
WaitForTermination(sigset_t signals)
{
  int received = 0;
  while (sigwait(&signals, &received) != 0)
  {}
  RunTerminationActions();
  std::signal(received, SIG_DFL);
  sigset_t only;
  sigemptyset(&only);
  sigaddset(&only, received);
  pthread_sigmask(SIG_UNBLOCK, &only, nullptr);
  // The signal's default action ends the process; the exit is only for a signal that somehow does not.
  raise(received);
  _exit(128 + received);
}
} // namespace

void
HandleTerminationSignals()
{
  static std::once_flag once;
  std::call_once(once, [] {
    const sigset_t signals = TerminationSignals();
    pthread_sigmask(SIG_BLOCK, &signals, &SignalMaskBefore);
    try
    {
      std::thread waiter(WaitForTermination, signals);
      Waiter = waiter.native_handle();
      waiter.detach();
    }
    catch (const std::system_error &)
    {
      pthread_sigmask(SIG_SETMASK, &SignalMaskBefore, nullptr);
      throw;
    }
    SignalsBlocked = true;
    // The signals sent to the thread that wrote are unblocked again here, and so in the threads started later.
    sigset_t directed;
    sigemptyset(&directed);
    for (const int candidate : { SIGPIPE, SIGXFSZ })
    {
      if (sigismember(&signals, candidate) == 1)
      {
        struct sigaction passOn
        {};
        passOn.sa_handler = PassOnToWaiter;
        sigemptyset(&passOn.sa_mask);
        passOn.sa_flags = SA_RESTART;
        sigaction(candidate, &passOn, nullptr);
        sigaddset(&directed, candidate);
      }
    }
    pthread_sigmask(SIG_UNBLOCK, &directed, nullptr);
  });
}

fs::path
CreateUniqueDirectory(const fs::path & parent, const std::string & prefix, std::error_code & error)
{
  std::string pattern = (parent / (prefix + "XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr)
  {
    error = std::error_code(errno, std::generic_category());
    return {};
  }
  error.clear();
  return pattern;
}

bool
CanStartPrograms()
{
  return true;
}

int
RunProgram(const fs::path & program, const std::vector<std::string> & arguments, const fs::path & log)
{
  pid_t child = 0;
  if (Spawn(child, program, arguments, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, -1) != 0)
  {
    return -1;
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
  {
    if (errno != EINTR)
    {
      return -1;
    }
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct BackgroundProgram::Process
{
  pid_t Id{ -1 };
  /** The read end of the program's pipe. */
  int Pipe{ -1 };
  /** Stops the program when a signal ends the tool first. */
  std::unique_ptr<TerminationAction> Stop;
};

BackgroundProgram::BackgroundProgram(const fs::path &                 program,
                                     const std::string &              pipeFlag,
                                     const std::vector<std::string> & arguments)
  : m_Process(std::make_unique<Process>())
{
  int channel[2];
  if (pipe(channel) != 0)
  {
    throw std::runtime_error("cannot start " + program.string() +
                             ": pipe failed: " + std::error_code(errno, std::generic_category()).message());
  }
  std::vector<std::string> all = { pipeFlag, std::to_string(channel[1]) };
  all.insert(all.end(), arguments.begin(), arguments.end());
  const int spawned = Spawn(m_Process->Id, program, std::move(all), "/dev/null", O_WRONLY, channel[0]);
  close(channel[1]);
  if (spawned != 0)
  {
    close(channel[0]);
    throw std::runtime_error("cannot start " + program.string() + ": " +
                             std::error_code(spawned, std::generic_category()).message());
  }
  m_Process->Pipe = channel[0];
  const pid_t id = m_Process->Id;
  m_Process->Stop = std::make_unique<TerminationAction>([id] { kill(id, SIGTERM); });
}

BackgroundProgram::~BackgroundProgram()
{
  m_Process->Stop.reset();
  close(m_Process->Pipe);
  kill(m_Process->Id, SIGTERM);
  waitpid(m_Process->Id, nullptr, 0);
}

std::string
BackgroundProgram::ReadLine(std::chrono::milliseconds timeout)
{
  std::string text;
  const auto  deadline = std::chrono::steady_clock::now() + timeout;
  while (text.find('\n') == std::string::npos)
  {
    const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    pollfd wait{ m_Process->Pipe, POLLIN, 0 };
    if (left <= 0 || poll(&wait, 1, static_cast<int>(left)) <= 0)
    {
      break;
    }
    char          chunk[32];
    const ssize_t got = read(m_Process->Pipe, chunk, sizeof(chunk));
    if (got <= 0)
    {
      break;
    }
    text.append(chunk, static_cast<size_t>(got));
  }
  text.erase(std::min(text.find_first_of("\r\n"), text.size()));
  return text;
}
#endif

namespace
{
/** The number after \a key in a "key: number unit" file such as /proc/self/status, in bytes (the unit is kB), or 0. */
std::uint64_t
KilobytesField(const char * path, const std::string & key)
{
  std::ifstream file(path);
  std::string   line;
  while (std::getline(file, line))
  {
    if (line.compare(0, key.size(), key) == 0)
    {
      return std::strtoull(line.c_str() + key.size(), nullptr, 10) * 1024;
    }
  }
  return 0;
}
} // namespace

std::uint64_t
PeakResidentBytes()
{
  return KilobytesField("/proc/self/status", "VmHWM:");
}

namespace
{
/** The first number in the file at \a path, or 0 (none, or "max"). */
std::uint64_t
NumberIn(const std::string & path)
{
  std::ifstream file(path);
  std::uint64_t value = 0;
  file >> value;
  return file ? value : 0;
}
} // namespace

std::uint64_t
AvailableMemoryBytes()
{
  std::uint64_t available = KilobytesField("/proc/meminfo", "MemAvailable:");
  // A memory limit of this process's control group (a container, a batch job) counts too.
  std::ifstream groups("/proc/self/cgroup");
  std::string   line;
  while (std::getline(groups, line))
  {
    // "id:controllers:group": the memory controller of cgroup v1, or the one line of v2, which names none.
    const auto colon = line.find(':');
    const auto path = line.find(':', colon + 1);
    const bool v1 = path != std::string::npos && line.compare(colon + 1, path - colon - 1, "memory") == 0;
    if (path == std::string::npos || (!v1 && path != colon + 1))
    {
      continue;
    }
    const std::string   files = (v1 ? "/sys/fs/cgroup/memory" : "/sys/fs/cgroup") + line.substr(path + 1) + "/memory.";
    const std::uint64_t limit = NumberIn(files + (v1 ? "limit_in_bytes" : "max"));
    const std::uint64_t usage = NumberIn(files + (v1 ? "usage_in_bytes" : "current"));
    if (limit > 0 && limit < (std::uint64_t{ 1 } << 60))
    {
      const std::uint64_t room = limit > usage ? limit - usage : 0;
      available = available == 0 ? room : std::min(available, room);
    }
  }
  return available;
}
} // namespace sic
