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
#include "sicJsonWriter.h"

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sic
{
JsonWriter::JsonWriter(std::ostream & stream)
  : m_Stream(stream)
{}

void
JsonWriter::Raw(std::string_view text)
{
  m_Stream.write(text.data(), static_cast<std::streamsize>(text.size()));
}

void
JsonWriter::Indent()
{
  m_Stream.put('\n');
  for (size_t i = 0; i < m_Levels.size(); ++i)
  {
    Raw("  ");
  }
}

void
JsonWriter::BeforeValue(bool isContainer)
{
  if (m_AfterKey)
  {
    m_AfterKey = false;
    return;
  }
  if (m_Levels.empty())
  {
    return;
  }
  Level & level = m_Levels.back();
  if (level.IsObject)
  {
    throw std::logic_error("JsonWriter: a value inside an object needs a Key() first");
  }
  if (!level.Empty)
  {
    Raw(level.Multiline || isContainer ? "," : ", ");
  }
  if (isContainer)
  {
    level.Multiline = true;
  }
  if (level.Multiline)
  {
    Indent();
  }
  level.Empty = false;
}

JsonWriter &
JsonWriter::Key(std::string_view key)
{
  if (m_Levels.empty() || !m_Levels.back().IsObject || m_AfterKey)
  {
    throw std::logic_error("JsonWriter: Key() belongs directly inside an object");
  }
  Level & level = m_Levels.back();
  if (!level.Empty)
  {
    Raw(",");
  }
  Indent();
  level.Empty = false;
  WriteEscaped(key);
  Raw(": ");
  m_AfterKey = true;
  return *this;
}

JsonWriter &
JsonWriter::BeginObject()
{
  BeforeValue(true);
  Raw("{");
  m_Levels.push_back({ true, true, true });
  return *this;
}

JsonWriter &
JsonWriter::BeginArray()
{
  BeforeValue(true);
  Raw("[");
  m_Levels.push_back({ false, true, false });
  return *this;
}

JsonWriter &
JsonWriter::End(bool isObject)
{
  if (m_Levels.empty() || m_Levels.back().IsObject != isObject || m_AfterKey)
  {
    throw std::logic_error("JsonWriter: unbalanced EndObject()/EndArray()");
  }
  const Level level = m_Levels.back();
  m_Levels.pop_back();
  if (level.Multiline && !level.Empty)
  {
    Indent();
  }
  Raw(isObject ? "}" : "]");
  return *this;
}

JsonWriter &
JsonWriter::EndObject()
{
  return End(true);
}

JsonWriter &
JsonWriter::EndArray()
{
  return End(false);
}

JsonWriter &
JsonWriter::String(std::string_view value)
{
  BeforeValue(false);
  WriteEscaped(value);
  return *this;
}

void
JsonWriter::WriteEscaped(std::string_view text)
{
  std::string escaped;
  escaped.reserve(text.size() + 2);
  escaped += '"';
  for (const char c : text)
  {
    switch (c)
    {
      case '"':
        escaped += "\\\"";
        break;
      case '\\':
        escaped += "\\\\";
        break;
      case '\n':
        escaped += "\\n";
        break;
      case '\r':
        escaped += "\\r";
        break;
      case '\t':
        escaped += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
        {
          static const char hex[] = "0123456789abcdef";
          escaped += "\\u00";
          escaped += hex[(c >> 4) & 0xf];
          escaped += hex[c & 0xf];
        }
        else
        {
          escaped += c;
        }
    }
  }
  escaped += '"';
  Raw(escaped);
}

JsonWriter &
JsonWriter::Number(double value)
{
  if (!std::isfinite(value))
  {
    return Null();
  }
  BeforeValue(false);
  char       buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  Raw(std::string_view(buffer, static_cast<size_t>(result.ptr - buffer)));
  return *this;
}

JsonWriter &
JsonWriter::Number(std::uint64_t value)
{
  BeforeValue(false);
  Raw(std::to_string(value));
  return *this;
}

JsonWriter &
JsonWriter::Number(std::int64_t value)
{
  BeforeValue(false);
  Raw(std::to_string(value));
  return *this;
}

JsonWriter &
JsonWriter::Null()
{
  BeforeValue(false);
  Raw("null");
  return *this;
}

void
JsonWriter::Finish()
{
  if (!m_Levels.empty() || m_AfterKey)
  {
    throw std::logic_error("JsonWriter: Finish() with an open object or array");
  }
  m_Stream.put('\n');
}
} // namespace sic
