// FNV-1a over a sequence of texts, with a separator after each so that ("ab", "c") and
// ("a", "bc") hash differently. Run ids and reference-cache keys are made with it: both must be
// the same on every machine and every build, which std::hash does not promise.
#pragma once

#include <cstdint>
#include <string_view>

namespace pcbench {

inline constexpr std::uint64_t kFnvOffset = 0xCBF29CE484222325ull;

constexpr std::uint64_t fnv1a(std::uint64_t hash, std::string_view text) {
  constexpr std::uint64_t kFnvPrime = 0x100000001B3ull;
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= kFnvPrime;
  }
  // A separator byte that UTF-8 text cannot produce.
  hash ^= 0xFF;
  return hash * kFnvPrime;
}

}  // namespace pcbench
