#pragma once
/**
 * @file json_writer.h
 * A minimal streaming writer of pretty-printed JSON (used by RunSummary).
 * Strings are escaped per RFC 8259; non-finite numbers are written as null.
 *
 * @code
 * JsonWriter json(out);
 * json.begin_object();
 * json.key("method"); json.value("fem");
 * json.key("dofs");   json.begin_object(); json.key("u"); json.value(1234); json.end_object();
 * json.end_object();
 * @endcode
 */
#include <cstdint>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

namespace twinflow::io
{
  /// @p s as a quoted JSON string literal (with ", \ and control characters escaped).
  std::string
  json_quote(const std::string &s);

  /// Shortest round-trip representation of @p v, or `null` if @p v is NaN or infinite.
  std::string
  json_number(double v);

  /// Streaming JSON writer with indentation; the caller nests begin/end correctly.
  class JsonWriter
  {
  public:
    explicit JsonWriter(std::ostream &out, unsigned int indent = 2);

    void
    begin_object();
    void
    end_object();
    void
    begin_array();
    void
    end_array();

    /// Name of the next member; only valid directly inside an object.
    void
    key(const std::string &name);

    void
    value(double v);
    void
    value(bool v);
    void
    value(const std::string &v);
    void
    value(const char *v);
    void
    null();

    /// Any integer type except bool, written exactly.
    template <typename Int,
              std::enable_if_t<std::is_integral_v<Int> && !std::is_same_v<Int, bool>, int> = 0>
    void
    value(const Int v)
    {
      if constexpr (std::is_signed_v<Int>)
        raw_value(std::to_string(static_cast<long long>(v)));
      else
        raw_value(std::to_string(static_cast<unsigned long long>(v)));
    }

    /// Write an already-formatted JSON value (number, literal) verbatim.
    void
    raw_value(const std::string &text);

  private:
    struct Frame
    {
      bool is_object;
      bool empty;
    };

    void
    before_value();
    void
    newline_and_indent(std::size_t depth);
    void
    close(bool is_object, char bracket);

    std::ostream &     out;
    unsigned int       indent;
    std::vector<Frame> stack;
    bool               after_key = false;
  };
} // namespace twinflow::io
