// Error kinds that decide the exit status (INTERFACE.md): bad input stops before any work and
// exits 2; a failure inside one run is recorded in that run and the suite goes on.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace pcbench {

// Bad input: a file, key, name or value the user supplied. The message names the location and,
// where there is a closed set, the valid choices.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "LINE:COLUMN" (1-based) of the byte before offset `byte` of `text`: where nlohmann-json's
// parse_error::byte points, for error messages about JSON input.
inline std::string line_and_column(std::string_view text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

// The message for a number nlohmann-json cannot hold as a double ("1e999", its out_of_range
// error 406), as "FILE:LINE:COLUMN: ..." at the first place `text` has the number its message
// quotes, or "FILE: ..." when it has none.
inline std::string json_number_error(std::string_view text, std::string_view file,
                                     const std::string& message) {
  const std::size_t open = message.find('\''), close = message.rfind('\'');
  const std::size_t at =
      open < close ? text.find(message.substr(open + 1, close - open - 1)) : std::string_view::npos;
  std::string out(file);
  if (at != std::string_view::npos) {
    out += ':';
    out += line_and_column(text, at + 1);
  }
  out += ": ";
  out += message;
  return out;
}

// A key as a JSON pointer token (RFC 6901): '~' and '/' escaped.
inline std::string json_pointer_token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

// Joins names as "a, b, c" for "valid choices" messages.
template <typename Range>
std::string join_names(const Range& names, const char* separator = ", ") {
  std::string out;
  for (const auto& name : names) {
    if (!out.empty()) out += separator;
    out += name;
  }
  return out;
}

}  // namespace pcbench
