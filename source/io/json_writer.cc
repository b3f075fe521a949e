/**
 * @file json_writer.cc
 * Implementation of the minimal JSON writer.
 */
#include <twinflow/io/json_writer.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace twinflow::io
{
  std::string
  json_quote(const std::string &s)
  {
    std::string r;
    r.reserve(s.size() + 2);
    r += '"';
    for (const char ch : s)
      {
        const auto c = static_cast<unsigned char>(ch);
        switch (c)
          {
            case '"':
              r += "\\\"";
              break;
            case '\\':
              r += "\\\\";
              break;
            case '\b':
              r += "\\b";
              break;
            case '\f':
              r += "\\f";
              break;
            case '\n':
              r += "\\n";
              break;
            case '\r':
              r += "\\r";
              break;
            case '\t':
              r += "\\t";
              break;
            default:
              if (c < 0x20 || c == 0x7f)
                {
                  char buf[8];
                  std::snprintf(buf, sizeof(buf), "\\u%04x", static_cast<unsigned int>(c));
                  r += buf;
                }
              else
                r += ch; // UTF-8 bytes pass through unchanged
          }
      }
    r += '"';
    return r;
  }

  std::string
  json_number(const double v)
  {
    if (!std::isfinite(v))
      return "null";
    char       buf[64];
    const auto res = std::to_chars(buf, buf + sizeof(buf), v);
    if (res.ec != std::errc())
      throw std::runtime_error("json_number: formatting failed");
    return std::string(buf, res.ptr);
  }

  JsonWriter::JsonWriter(std::ostream &out, const unsigned int indent)
    : out(out)
    , indent(indent)
  {}

  void
  JsonWriter::newline_and_indent(const std::size_t depth)
  {
    out << '\n' << std::string(depth * indent, ' ');
  }

  void
  JsonWriter::before_value()
  {
    if (after_key)
      {
        after_key = false;
        return;
      }
    if (stack.empty())
      return;
    if (stack.back().is_object)
      throw std::logic_error("JsonWriter: value inside an object without key()");
    if (!stack.back().empty)
      out << ',';
    stack.back().empty = false;
    newline_and_indent(stack.size());
  }

  void
  JsonWriter::key(const std::string &name)
  {
    if (stack.empty() || !stack.back().is_object || after_key)
      throw std::logic_error("JsonWriter: key() outside an object or twice in a row");
    if (!stack.back().empty)
      out << ',';
    stack.back().empty = false;
    newline_and_indent(stack.size());
    out << json_quote(name) << ": ";
    after_key = true;
  }

  void
  JsonWriter::begin_object()
  {
    before_value();
    out << '{';
    stack.push_back({true, true});
  }

  void
  JsonWriter::begin_array()
  {
    before_value();
    out << '[';
    stack.push_back({false, true});
  }

  void
  JsonWriter::close(const bool is_object, const char bracket)
  {
    if (stack.empty() || stack.back().is_object != is_object || after_key)
      throw std::logic_error("JsonWriter: unbalanced end_object()/end_array()");
    const bool empty = stack.back().empty;
    stack.pop_back();
    if (!empty)
      newline_and_indent(stack.size());
    out << bracket;
    if (stack.empty())
      out << '\n';
  }

  void
  JsonWriter::end_object()
  {
    close(true, '}');
  }

  void
  JsonWriter::end_array()
  {
    close(false, ']');
  }

  void
  JsonWriter::raw_value(const std::string &text)
  {
    before_value();
    out << text;
  }

  void
  JsonWriter::value(const double v)
  {
    raw_value(json_number(v));
  }

  void
  JsonWriter::value(const bool v)
  {
    raw_value(v ? "true" : "false");
  }

  void
  JsonWriter::value(const std::string &v)
  {
    raw_value(json_quote(v));
  }

  void
  JsonWriter::value(const char *v)
  {
    raw_value(v ? json_quote(v) : std::string("null"));
  }

  void
  JsonWriter::null()
  {
    raw_value("null");
  }
} // namespace twinflow::io
