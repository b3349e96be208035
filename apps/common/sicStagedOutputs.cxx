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
#include "sicStagedOutputs.h"
#include "sicPlatform.h"
#include "sicStrings.h"
#include "sicToolError.h"

#include "itksys/SystemTools.hxx"

#include <fstream>

namespace sic
{
namespace fs = std::filesystem;

namespace
{
/** Whether \a a and \a b name the same file: by identity (device and inode) when both
 * exist, by their resolved absolute paths otherwise. */
bool
SameFile(const fs::path & a, const fs::path & b)
{
  std::error_code error;
  const bool      aExists = fs::exists(a, error);
  const bool      bExists = fs::exists(b, error);
  if (aExists || bExists)
  {
    return aExists && bExists && fs::equivalent(a, b, error);
  }
  return fs::weakly_canonical(fs::absolute(a), error) == fs::weakly_canonical(fs::absolute(b), error);
}

/** Throws unless an output may replace what is at \a destination: nothing, a regular file or a link to one (or to
 * nothing). A rename would replace a directory's entry, a FIFO, a device or a socket, or the link to one (such
 * as /dev/stdout), where the user meant to write into it. */
void
CheckReplaceable(const fs::path & destination, const std::string & what)
{
  std::error_code       error;
  const fs::file_status found = fs::status(destination, error);
  if (!fs::exists(found) || fs::is_regular_file(found))
  {
    return;
  }
  const std::string kind = fs::is_directory(found)                                    ? "a directory"
                           : fs::is_fifo(found)                                       ? "a FIFO"
                           : fs::is_socket(found)                                     ? "a socket"
                           : fs::is_character_file(found) || fs::is_block_file(found) ? "a device"
                                                                                      : "a special file";
  const bool        linked = fs::is_symlink(fs::symlink_status(destination, error));
  throw ToolError("cannot write the " + what + " to " + Quoted(destination) + ": it is " +
                  (linked ? "a link to " : "") + kind + "; expected a regular file or a new path");
}
} // namespace

StagedOutputs::StagedOutputs()
  : m_Cleanup(std::make_unique<TerminationAction>([this] { RemoveStaged(); }))
{}

StagedOutputs::~StagedOutputs()
{
  RemoveStaged();
}

void
StagedOutputs::RemoveStaged()
{
  std::lock_guard<std::mutex> lock(m_StagedMutex);
  for (const Staged & staged : m_Staged)
  {
    std::error_code ignored;
    fs::remove_all(staged.Directory, ignored);
  }
  m_Staged.clear();
}

void
StagedOutputs::Protect(const std::vector<fs::path> & files, const std::string & what)
{
  for (size_t i = 0; i < files.size(); ++i)
  {
    m_Protected.push_back({ files[i], i == 0 ? what : "a data file of " + what });
  }
}

void
StagedOutputs::CheckNotProtected(const fs::path & destination, const std::string & what) const
{
  for (const Protected & file : m_Protected)
  {
    if (SameFile(destination, file.Path))
    {
      throw ToolError("refusing to write the " + what + " to " + Quoted(destination) + ": it is " + file.What +
                      "; expected a different path");
    }
  }
}

std::string
StagedOutputs::Stage(const std::string & finalPath, const std::string & what)
{
  const fs::path destination(finalPath);
  const fs::path name = destination.filename();
  if (finalPath.empty() || name.empty() || name == "." || name == "..")
  {
    throw ToolError("cannot write the " + what + " to " + Quoted(destination) + ": expected a file path");
  }
  CheckReplaceable(destination, what);
  std::error_code error;
  const fs::path  directory = destination.has_parent_path() ? destination.parent_path() : fs::path(".");
  if (!fs::exists(directory, error))
  {
    throw ToolError("cannot write the " + what + " to " + Quoted(destination) + ": the directory " + Quoted(directory) +
                    " does not exist; expected a path in an existing directory");
  }
  if (!fs::is_directory(directory, error))
  {
    throw ToolError("cannot write the " + what + " to " + Quoted(destination) + ": " + Quoted(directory) +
                    " is not a directory");
  }
  CheckNotProtected(destination, what);
  std::lock_guard<std::mutex> lock(m_StagedMutex);
  for (const Staged & other : m_Staged)
  {
    if (SameFile(destination, other.Final))
    {
      throw ToolError("the " + what + " and the " + other.What + " are both " + Quoted(destination) +
                      "; expected different paths");
    }
  }

  // The directory's name does not grow with the output's, so that any name the file system takes works.
  const fs::path staging = CreateUniqueDirectory(directory, StagingDirectoryPrefix, error);
  if (staging.empty())
  {
    throw ToolError("cannot write the " + what + " to " + Quoted(destination) + ": cannot create a file in " +
                    Quoted(directory) + " (" + error.message() + ")");
  }
  m_Staged.push_back({ destination, what, staging });
  return (staging / name).string();
}

void
StagedOutputs::Commit()
{
  // Everything is checked before anything is moved; a termination signal's cleanup waits until all is moved.
  std::lock_guard<std::mutex>                   lock(m_StagedMutex);
  std::vector<std::vector<fs::path>>            files(m_Staged.size());
  std::vector<std::pair<fs::path, std::string>> destinations;
  for (size_t i = 0; i < m_Staged.size(); ++i)
  {
    const Staged &  staged = m_Staged[i];
    const fs::path  main = staged.Directory / staged.Final.filename();
    std::error_code error;
    if (!fs::is_regular_file(main, error))
    {
      throw ToolError("the " + staged.What + " " + Quoted(staged.Final) + " was not written");
    }
    for (const fs::directory_entry & entry : fs::directory_iterator(staged.Directory, error))
    {
      if (entry.path() != main)
      {
        files[i].push_back(entry.path());
      }
    }
    // A header goes last, after the data files it names.
    files[i].push_back(main);
    for (const fs::path & file : files[i])
    {
      const fs::path destination = staged.Final.parent_path() / file.filename();
      CheckReplaceable(destination, staged.What);
      CheckNotProtected(destination, staged.What);
      for (const auto & [other, otherWhat] : destinations)
      {
        if (SameFile(destination, other))
        {
          throw ToolError("the " + staged.What + " and the " + otherWhat + " both write " + Quoted(destination) +
                          "; expected outputs whose files have different names");
        }
      }
      destinations.emplace_back(destination, staged.What);
    }
  }
  for (size_t i = 0; i < m_Staged.size(); ++i)
  {
    const Staged & staged = m_Staged[i];
    for (const fs::path & file : files[i])
    {
      const fs::path  destination = staged.Final.parent_path() / file.filename();
      std::error_code error;
      fs::rename(file, destination, error);
      if (error)
      {
        throw ToolError("cannot move the " + staged.What + " into place at " + Quoted(destination) + ": " +
                        error.message());
      }
    }
    std::error_code ignored;
    fs::remove(staged.Directory, ignored);
  }
  m_Staged.clear();
}

std::string
ShowFinalPaths(const std::string & text, const std::string & stagedPath, const std::string & finalPath)
{
  if (stagedPath == finalPath)
  {
    return text;
  }
  const std::string staging = fs::path(stagedPath).parent_path().string();
  const std::string directory = fs::path(finalPath).parent_path().string();
  std::string       shown = text;
  itksys::SystemTools::ReplaceString(shown, stagedPath, finalPath);
  itksys::SystemTools::ReplaceString(
    shown, (fs::path(staging) / "").string(), directory.empty() ? "" : (fs::path(directory) / "").string());
  itksys::SystemTools::ReplaceString(shown, staging, directory.empty() ? "." : directory);
  return shown;
}

void
WriteTextFile(const std::string & path,
              const std::string & finalPath,
              const std::string & what,
              const std::string & text)
{
  std::ofstream file(path);
  file << text;
  file.close();
  if (!file)
  {
    throw ToolError("cannot write the " + what + " to " + Quoted(finalPath));
  }
}
} // namespace sic
