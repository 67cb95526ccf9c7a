// Comma-separated lists on the command line (--images a.exr,b.exr, --constant R,G,B,
// --param M=4,16): one splitter, so that every option treats "a,,b" and a trailing comma alike.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace pcbench {

// Every part between commas, empty ones kept ("a,,b" gives "a", "", "b"; "" gives one ""), so
// that the caller can refuse an empty part with its own message.
inline std::vector<std::string> split_commas(std::string_view text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    parts.emplace_back(text.substr(start, comma - start));
    if (comma == std::string_view::npos) return parts;
    start = comma + 1;
  }
}

}  // namespace pcbench
