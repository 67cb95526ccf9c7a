// The generator's ways of computing many blocks, one by one, for the tests and benchmarks that
// compare them: philox4x32_10_many (base/rng.h) takes the widest the CPU has, so on a machine
// with AVX-512 the AVX2 lanes would otherwise never run under test.
#pragma once

#include <span>

#include "base/rng.h"

namespace pcbench {

enum class PhiloxLanes { kScalar, kAvx2, kAvx512 };

bool philox_lanes_supported(PhiloxLanes lanes);

// philox4x32_10_many computed with `lanes` (which must be supported).
void philox4x32_10_many_with(PhiloxLanes lanes, std::span<const PhiloxCounter> counters,
                             PhiloxKey key, std::span<PhiloxCounter> out);
// philox4x32_10_consecutive computed with `lanes` (which must be supported).
void philox4x32_10_consecutive_with(PhiloxLanes lanes, const PhiloxCounter& first, PhiloxKey key,
                                    std::span<PhiloxCounter> out);

}  // namespace pcbench
