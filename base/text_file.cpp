#include "base/text_file.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "base/errors.h"

namespace pcbench {

std::string read_text_file(const std::filesystem::path& path, const std::string& what) {
  // C stdio rather than std::ifstream: POSIX defines errno for fopen and fread, so the message
  // can give the operating system's reason. fopen opens a folder; the first fread then fails
  // with EISDIR.
  errno = 0;
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  const auto reason = [] { return errno != 0 ? std::strerror(errno) : "unknown error"; };
  if (!file) {
    throw InputError(fmt::format("{}: cannot open {}: {}", path.string(), what, reason()));
  }
  std::string text;
  char buffer[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) text.append(buffer, got);
  if (std::ferror(file.get())) {
    throw InputError(fmt::format("{}: cannot read {}: {}", path.string(), what, reason()));
  }
  return text;
}

}  // namespace pcbench
