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

#include <filesystem>
#include <string>
#include <vector>

namespace sic
{
/** Output files that appear all at once, or not at all.
 *
 * Each output is first written into a staging directory created beside its final path
 * (same file system, so moving it is a rename); Commit() then renames every staged file
 * into place. An output whose format writes several files (.mhd + .zraw, .nhdr + .raw.gz)
 * is staged under its final file name, so the header's reference to its data file stays
 * right. Until Commit(), the final paths are untouched; if the tool fails before that,
 * the destructor removes the staging directories, so a failure never leaves a
 * half-written or partial output.
 *
 * Stage() checks a destination before any work is done: its directory must exist, it
 * must not be a directory, and it must be neither a protected file (an input; compared by
 * file identity, so links and other spellings of the same file are caught) nor another
 * output. */
class StagedOutputs
{
public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs &) = delete;
  StagedOutputs &
  operator=(const StagedOutputs &) = delete;
  ~StagedOutputs();

  /** Refuses to write over \a path, described to the user as \a what (e.g. "the input"). */
  void
  Protect(const std::string & path, const std::string & what);

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

  std::vector<Protected> m_Protected;
  std::vector<Staged>    m_Staged;
};

/** Writes \a text to \a path, where the output described as \a what (e.g. "report") is
 * staged. Throws ToolError, naming the output's \a finalPath, if that fails. */
void
WriteTextFile(const std::string & path,
              const std::string & finalPath,
              const std::string & what,
              const std::string & text);
} // namespace sic

#endif
