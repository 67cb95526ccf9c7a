// Reading a whole input file into memory, with one error for every reader: the path, what the
// file was meant to be, and the operating system's reason.
#pragma once

#include <filesystem>
#include <string>

namespace pcbench {

// The bytes of `path`. Throws InputError "PATH: cannot open WHAT: REASON" (missing file, no
// permission) or "PATH: cannot read WHAT: REASON" (a folder, an I/O error), where WHAT names the
// file's role ("the suite file") and REASON is strerror(errno).
std::string read_text_file(const std::filesystem::path& path, const std::string& what);

}  // namespace pcbench
