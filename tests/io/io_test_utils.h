// Helpers shared by the twinflow::io tests: scratch directories, file reading,
// a check for /usr/bin/python3 modules and a strict JSON syntax checker.
#pragma once

#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace twinflow_test
{
  namespace fs = std::filesystem;

  /// A fresh scratch directory, removed on destruction.
  struct TempDir
  {
    static int
    next_id()
    {
      static int counter = 0;
      return counter++;
    }
    fs::path path;
    TempDir()
    {
      path = fs::temp_directory_path() / ("twinflow_test_io_" + std::to_string(::getpid()) + "_" +
                                          std::to_string(next_id()));
      fs::remove_all(path);
      fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string
    operator/(const std::string &name) const
    {
      return (path / name).string();
    }
  };

  inline std::string
  slurp(const std::string &path)
  {
    std::ifstream      in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  inline std::vector<std::string>
  lines_of(const std::string &path)
  {
    std::ifstream            in(path);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);)
      lines.push_back(l);
    return lines;
  }

  inline bool
  have_python_with(const std::string &module)
  {
    return std::system(("/usr/bin/python3 -c 'import " + module + "' >/dev/null 2>&1").c_str()) ==
           0;
  }

  /// Minimal strict JSON syntax check (RFC 8259 grammar, no semantic checks).
  class JsonChecker
  {
  public:
    explicit JsonChecker(const std::string &text)
      : s(text)
    {}
    bool
    valid()
    {
      ws();
      if (!value())
        return false;
      ws();
      return i == s.size();
    }

  private:
    const std::string &s;
    std::size_t        i = 0;
    void
    ws()
    {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\n' || s[i] == '\r' || s[i] == '\t'))
        ++i;
    }
    bool
    lit(const char *w)
    {
      const std::string word(w);
      if (s.compare(i, word.size(), word) != 0)
        return false;
      i += word.size();
      return true;
    }
    bool
    string()
    {
      if (s[i] != '"')
        return false;
      for (++i; i < s.size(); ++i)
        {
          const auto c = static_cast<unsigned char>(s[i]);
          if (c == '"')
            return ++i, true;
          if (c < 0x20)
            return false;
          if (c == '\\')
            {
              if (++i >= s.size())
                return false;
              if (s[i] == 'u')
                {
                  for (int k = 0; k < 4; ++k)
                    if (++i >= s.size() || !std::isxdigit(static_cast<unsigned char>(s[i])))
                      return false;
                }
              else if (std::string("\"\\/bfnrt").find(s[i]) == std::string::npos)
                return false;
            }
        }
      return false;
    }
    bool
    number()
    {
      static const std::regex re(R"(^-?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?)");
      std::smatch             m;
      const std::string       rest = s.substr(i, 40);
      if (!std::regex_search(rest, m, re) || m.length(0) == 0)
        return false;
      i += m.length(0);
      return true;
    }
    template <typename Item>
    bool
    sequence(char close, Item item)
    {
      ++i;
      ws();
      if (i < s.size() && s[i] == close)
        return ++i, true;
      while (true)
        {
          ws();
          if (!item())
            return false;
          ws();
          if (i < s.size() && s[i] == ',')
            ++i;
          else
            return i < s.size() && s[i++] == close;
        }
    }
    bool
    value()
    {
      if (i >= s.size())
        return false;
      switch (s[i])
        {
          case '{':
            return sequence('}', [this] {
              if (i >= s.size() || !string())
                return false;
              ws();
              if (i >= s.size() || s[i++] != ':')
                return false;
              ws();
              return value();
            });
          case '[':
            return sequence(']', [this] { return value(); });
          case '"':
            return string();
          case 't':
            return lit("true");
          case 'f':
            return lit("false");
          case 'n':
            return lit("null");
          default:
            return number();
        }
    }
  };
} // namespace twinflow_test
