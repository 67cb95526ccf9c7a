#include "harness/plan/image_file_reader.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>

#include "base/errors.h"

#ifndef PCBENCH_IMAGE_MODULE
#error "PCBENCH_IMAGE_MODULE must name the built pcbench_image_io module (CMakeLists.txt)"
#endif

namespace pcbench {
namespace {

// The module's entry point, loaded once per process; the module stays loaded until exit.
OpenImageFileFunction load_module() {
  const char* overridden = std::getenv("PCBENCH_IMAGE_MODULE");
  const std::string path = overridden != nullptr ? overridden : PCBENCH_IMAGE_MODULE;
  void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (module == nullptr) {
    const char* why = dlerror();
    throw InputError(
        fmt::format("cannot load pcbench's image reader {} ({}); build the pcbench target, or set "
                    "PCBENCH_IMAGE_MODULE to the module's path",
                    path, why != nullptr ? why : "unknown error"));
  }
  void* entry = dlsym(module, kOpenImageFileSymbol);
  if (entry == nullptr) {
    throw InputError(
        fmt::format("{}: not pcbench's image reader (no symbol {})", path, kOpenImageFileSymbol));
  }
  return reinterpret_cast<OpenImageFileFunction>(entry);
}

}  // namespace

std::unique_ptr<ImageFileReader> open_image_file(const std::string& path, std::string& error) {
  // A function-local static: loaded by the first caller, thread-safe, and a failed load is tried
  // again by the next caller (the exception leaves the static uninitialised).
  static const OpenImageFileFunction open = load_module();
  return std::unique_ptr<ImageFileReader>(open(path.c_str(), &error));
}

}  // namespace pcbench
