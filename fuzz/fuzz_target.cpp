// The libFuzzer driver, built once per target (fuzz/CMakeLists.txt sets PCBENCH_FUZZ_TARGET to
// "suite", "scene" or "expression"): each input goes to that target's check (fuzz/fuzz_inputs.h).
// A documented rejection is an ordinary outcome; any other exception aborts, so that libFuzzer
// saves the input as a crash, with the exception's type and message.
#include <stdlib.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <typeinfo>

#include "fuzz/fuzz_inputs.h"

namespace {

// OBJ files the scene target writes; one folder per process, so parallel jobs do not share it.
std::filesystem::path& scratch() {
  static std::filesystem::path folder;
  return folder;
}

void remove_scratch() {
  std::error_code ignored;
  std::filesystem::remove_all(scratch(), ignored);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::string pattern = (std::filesystem::temp_directory_path() / "pcbench-fuzz-XXXXXX").string();
  if (!mkdtemp(pattern.data())) {
    std::perror("pcbench fuzz: mkdtemp");
    std::abort();
  }
  scratch() = pattern;
  std::atexit(remove_scratch);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    pcbench::fuzz::check_input(PCBENCH_FUZZ_TARGET, text, scratch());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcbench fuzz: unexpected exception %s: %s\n", typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr,
                 "pcbench fuzz: unexpected exception of a type not derived from "
                 "std::exception\n");
    std::abort();
  }
  return 0;
}
