#pragma once
/// @file errors.h  Input errors: what is wrong, where, and what is allowed.
#include <stdexcept>
#include <string>

namespace twinflow
{
  /// Thrown for bad input (malformed file, impossible geometry, ...). The message names
  /// the entry (with its subsection path), the offending value and the allowed values.
  class InputError : public std::runtime_error
  {
  public:
    explicit InputError(const std::string &message) : std::runtime_error(message) {}
  };

  /// Throws InputError("<entry> = <value>: <allowed>") if @p condition is false.
  inline void require(bool condition, const std::string &entry, const std::string &value,
                      const std::string &allowed)
  {
    if (!condition)
      throw InputError("invalid value for '" + entry + "' = '" + value + "': " + allowed);
  }
} // namespace twinflow
