// Files written whole or not at all: the text goes to a temporary file in the same folder, which
// is then renamed over the target, so a reader (or a run killed mid-write) never sees half a file.
#pragma once

#include <filesystem>
#include <string>

namespace pcbench {

// Writes `text` to `path` atomically (temporary file + rename), creating parent folders.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace pcbench
