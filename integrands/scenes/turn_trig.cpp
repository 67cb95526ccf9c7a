#include "integrands/scenes/turn_trig.h"

namespace pcbench::scene {

// Built for AVX-512, AVX2 and SSE2, chosen at run time; without contraction (CMakeLists.txt),
// since the AVX clones' fused multiply-adds would round the series differently from the scalar
// code.
[[gnu::target_clones("avx512f", "avx2", "default")]] void cos_sin_of_turns(
    std::span<const double> u, std::span<double> cos, std::span<double> sin) {
  for (std::size_t i = 0; i < u.size(); ++i) {
    const CosSin azimuth = cos_sin_of_turn(u[i]);
    cos[i] = azimuth.cos;
    sin[i] = azimuth.sin;
  }
}

}  // namespace pcbench::scene
