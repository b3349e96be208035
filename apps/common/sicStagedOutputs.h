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
#ifndef sicStagedOutputs_h
#define sicStagedOutputs_h

#include "sicPlatform.h"

#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace sic
{
/** Output files that appear all at once, or not at all.
 *
 * Each output is first written into a staging directory created beside its final path (same file system, so moving it
 * is a rename), named StagingDirectoryPrefix followed by six random characters; Commit() then renames every staged file
 * into place. An output whose format writes several files (.mhd + .zraw, .nhdr + .raw.gz) is staged under its final
 * file name, so the header's reference to its data file stays right. Until Commit(), the final paths are untouched; if
 * the tool fails before that, the destructor removes the staging directories, and so does a termination signal
 * (HandleTerminationSignals()), so neither leaves a half-written or partial output. Only a process killed outright
 * (SIGKILL) leaves its staging directories behind.
 *
 * Stage() checks a destination before any work is done: its directory must exist, it must not be a directory, and it
 * must be neither a protected file (a file of an input; compared by file identity, so links and other spellings of the
 * same file are caught) nor another output. Commit() checks every file that was written, data files included, in the
 * same way before it moves any. */
class StagedOutputs
{
public:
  /** The start of every staging directory's name (hidden on POSIX systems). */
  static constexpr const char * StagingDirectoryPrefix = ".SmallIsoComponent-";

  StagedOutputs();
  StagedOutputs(const StagedOutputs &) = delete;
  StagedOutputs &
  operator=(const StagedOutputs &) = delete;
  ~StagedOutputs();

  /** Refuses to write over any of \a files, an input's header and data files, described to the user as \a what
   * (e.g. "the input image") for the first and as its data files for the others. */
  void
  Protect(const std::vector<std::filesystem::path> & files, const std::string & what);

  /** Checks that \a finalPath may receive the output described as \a what (e.g. "output
   * image") and returns the path to write it to. Throws ToolError saying what is wrong. */
  std::string
  Stage(const std::string & finalPath, const std::string & what);

  /** Renames every staged file into place. Throws ToolError if that fails. */
  void
  Commit();

private:
  struct Protected
  {
    std::filesystem::path Path;
    std::string           What;
  };
  struct Staged
  {
    std::filesystem::path Final;
    std::string           What;
    std::filesystem::path Directory;
  };

  void
  CheckNotProtected(const std::filesystem::path & destination, const std::string & what) const;

  /** Removes every staging directory and forgets them. */
  void
  RemoveStaged();

  std::vector<Protected> m_Protected;
  /** Guards m_Staged, which a termination signal's cleanup reads from another thread. */
  std::mutex          m_StagedMutex;
  std::vector<Staged> m_Staged;
  /** Declared last, so that it is destroyed first: no cleanup runs on destroyed members. */
  std::unique_ptr<TerminationAction> m_Cleanup;
};

/** \a text (a message) with \a stagedPath, and the staging directory it is in, replaced by \a finalPath and its
 * directory: the names the user gave. */
std::string
ShowFinalPaths(const std::string & text, const std::string & stagedPath, const std::string & finalPath);

/** Writes \a text to \a path, where the output described as \a what (e.g. "report") is
 * staged. Throws ToolError, naming the output's \a finalPath, if that fails. */
void
WriteTextFile(const std::string & path,
              const std::string & finalPath,
              const std::string & what,
              const std::string & text);
} // namespace sic

#endif
