#include "base/rng.h"

namespace pcbench {
namespace {

// Round constants of Philox4x32 (Salmon et al. 2011, Section 4; the Random123 values).
constexpr std::uint32_t kMul0 = 0xD2511F53u;
constexpr std::uint32_t kMul1 = 0xCD9E8D57u;
constexpr std::uint32_t kWeyl0 = 0x9E3779B9u;  // golden ratio
constexpr std::uint32_t kWeyl1 = 0xBB67AE85u;  // sqrt(3) - 1

inline void mulhilo(std::uint32_t a, std::uint32_t b, std::uint32_t& hi, std::uint32_t& lo) {
  const std::uint64_t product = static_cast<std::uint64_t>(a) * b;
  hi = static_cast<std::uint32_t>(product >> 32);
  lo = static_cast<std::uint32_t>(product);
}

// SplitMix64 finaliser: a bijective 64-bit mixer (Steele et al. 2014).
inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

PhiloxCounter philox4x32_10(PhiloxCounter c, PhiloxKey k) {
  for (int round = 0; round < 10; ++round) {
    std::uint32_t hi0, lo0, hi1, lo1;
    mulhilo(kMul0, c[0], hi0, lo0);
    mulhilo(kMul1, c[2], hi1, lo1);
    c = {hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0};
    k[0] += kWeyl0;
    k[1] += kWeyl1;
  }
  return c;
}

std::uint64_t run_key(std::uint64_t seed, std::uint64_t run_id_hash) {
  return mix64(mix64(seed ^ 0x7063626E63685F31ull) ^ run_id_hash);
}

RandomStream::RandomStream(const StreamId& id)
    : key_{static_cast<std::uint32_t>(id.key), static_cast<std::uint32_t>(id.key >> 32)},
      // Counter layout: [block, path, sample, replicate (24 bits) | purpose (8 bits)].
      counter_{0u, id.path, id.sample,
               (id.replicate & 0x00FFFFFFu) | (static_cast<std::uint32_t>(id.purpose) << 24)} {}

void RandomStream::refill() {
  block_ = philox4x32_10(counter_, key_);
  ++counter_[0];
  next_ = 0;
}

}  // namespace pcbench
