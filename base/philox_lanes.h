// The generator's ways of computing many blocks, one by one, for the tests and benchmarks that
// compare them: philox4x32_10_many (base/rng.h) takes the widest the CPU has, so on a machine
// with AVX-512 the AVX2 lanes would otherwise never run under test.
#pragma once

#include <cstddef>
#include <span>

#include "base/rng.h"

namespace pcbench {

enum class PhiloxLanes { kScalar, kAvx2, kAvx512 };

bool philox_lanes_supported(PhiloxLanes lanes);

// philox4x32_10_many computed with `lanes` (which must be supported).
void philox4x32_10_many_with(PhiloxLanes lanes, std::span<const PhiloxCounter> counters,
                             PhiloxKey key, std::span<PhiloxCounter> out);
// RandomStream::uniforms' blocks and numbers: the blocks of blocks.size() <= kPhiloxUniformGroup
// consecutive counters from `first` (word 0 counting up, wrapping as a stream's does), and
// u[2i], u[2i + 1] = RandomStream::uniform_of(blocks[i], 0 and 2), computed with `lanes` (which
// must be supported). u.size() must be 2 blocks.size().
constexpr std::size_t kPhiloxUniformGroup = 32;
void philox_uniforms_with(PhiloxLanes lanes, const PhiloxCounter& first, PhiloxKey key,
                          std::span<PhiloxCounter> blocks, std::span<double> u);

}  // namespace pcbench
