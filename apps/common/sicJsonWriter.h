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
#ifndef sicJsonWriter_h
#define sicJsonWriter_h

#include <cstdint>
#include <ostream>
#include <string_view>
#include <vector>

namespace sic
{
/** Writes one JSON document to a stream, indented, with members and elements separated
 * as they are added. Numbers are written so that they read back exactly: integers in
 * full, doubles in their shortest round-trip form; NaN and infinities, which JSON cannot
 * express, are written as null. Strings are escaped (quotes, backslashes, control
 * characters); other bytes pass through, so UTF-8 stays UTF-8.
 *
 * Arrays whose elements are numbers or strings stay on one line; arrays of arrays or
 * objects put each element on its own line. */
class JsonWriter
{
public:
  explicit JsonWriter(std::ostream & stream);

  JsonWriter &
  BeginObject();
  JsonWriter &
  EndObject();
  JsonWriter &
  BeginArray();
  JsonWriter &
  EndArray();

  /** Names the next value; only inside an object. */
  JsonWriter &
  Key(std::string_view key);

  JsonWriter &
  String(std::string_view value);
  JsonWriter &
  Number(double value);
  JsonWriter &
  Number(std::uint64_t value);
  JsonWriter &
  Number(std::int64_t value);
  JsonWriter &
  Null();

  /** Ends the document with a newline. */
  void
  Finish();

private:
  struct Level
  {
    bool IsObject;
    bool Empty;
    bool Multiline;
  };

  /** Separator and indentation before a value (or a key in an object). */
  void
  BeforeValue(bool isContainer);
  void
  Indent();
  JsonWriter &
  End(bool isObject);
  void
  Raw(std::string_view text);
  void
  WriteEscaped(std::string_view text);

  std::ostream &     m_Stream;
  std::vector<Level> m_Levels;
  bool               m_AfterKey{ false };
};
} // namespace sic

#endif
