// pcbench_exr_pixel_hash FILE.exr...: one line per file, "<hash> <file>", the hash (64-bit
// FNV-1a, hex) of the size, every channel's name and the bits of its pixel values, in the file's
// channel order. It hashes what the file holds, not how it is compressed or which header
// attributes it carries, for tests/estimator_hashes.py (the bit-for-bit record of the scene
// estimators' images).
#include <cstdint>
#include <cstring>
#include <exception>
#include <iomanip>
#include <iostream>
#include <vector>

#include "results/exr_file.h"

namespace {

class Fnv1a {
 public:
  void add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ = (hash_ ^ bytes[i]) * 0x100000001b3ULL;
    }
  }
  void add_u32(std::uint32_t v) {
    const unsigned char bytes[4] = {
        static_cast<unsigned char>(v), static_cast<unsigned char>(v >> 8),
        static_cast<unsigned char>(v >> 16), static_cast<unsigned char>(v >> 24)};
    add(bytes, 4);
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

}  // namespace

int main(int argc, char** argv) {
  try {
    for (int i = 1; i < argc; ++i) {
      std::uint32_t width = 0, height = 0;
      const std::vector<pcbench::ExrChannel> channels = pcbench::read_exr(argv[i], width, height);
      Fnv1a h;
      h.add_u32(width);
      h.add_u32(height);
      for (const pcbench::ExrChannel& c : channels) {
        h.add(c.name.data(), c.name.size() + 1);  // with its terminating zero
        for (float v : c.values) {
          std::uint32_t bits = 0;
          std::memcpy(&bits, &v, sizeof bits);
          h.add_u32(bits);
        }
      }
      std::cout << std::hex << std::setw(16) << std::setfill('0') << h.value() << std::dec << ' '
                << argv[i] << '\n';
    }
  } catch (const std::exception& e) {
    std::cerr << "pcbench_exr_pixel_hash: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
