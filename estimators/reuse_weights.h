// The resampling (MIS) weights of spatial reuse: how a camera sample c that resamples from the
// reservoirs of its sources S = {c, n_1 .. n_k} (itself first, then k neighbours) shares the
// credit for a point x among them. In generalized RIS (Lin et al. 2022, "Generalized Resampled
// Importance Sampling", Sec. 4) the reuse is unbiased when, at every x where c's target
// p̂_c(x) > 0, the weights of the sources that can produce x (p̂_s(x) > 0) sum to 1:
//     Σ_{s in S, p̂_s(x) > 0} m_s(x) = 1.
// Every form below is computed from the sources' targets at x, T_s = p̂_s(x):
//   balance   m_s = T_s / Σ_t T_t (the generalized balance heuristic; every source holds M
//             candidates, so the confidence counts cancel). Sums to 1 wherever some T > 0.
//   pairwise  defensive pairwise MIS (Bitterli 2022, thesis, Sec. 9.1; Wyman et al. 2023,
//             ReSTIR course notes): m_c = (1 + Σ_r T_c / (T_c + T_r)) / (k + 1),
//             m_r = (T_r / (T_c + T_r)) / (k + 1) for each neighbour r. Sums to 1 wherever
//             T_c > 0, which is where it must; O(k) per sample instead of balance's O(k²).
//   count     m_s = 1[T_s > 0] / Z, Z = #{t: T_t > 0} (Bitterli et al. 2020's unbiased 1/Z).
//   uniform   m_s = 1 / (k + 1) whatever the targets (Bitterli et al. 2020's biased 1/Σ M):
//             the sources that cannot produce x still take their share, so where a neighbour's
//             target is 0 and c's is not the weights sum to less than 1 (too dark). Only the
//             negative control ctl-naive-reuse uses it, blended with count by its severity.
// The targets must include whatever zeroes p̂ (visibility): weights computed from targets whose
// support is larger than the sources' own (ctl-reuse-unshadowed) no longer sum to 1 over the
// sources that can produce x.
#pragma once

#include <cstddef>
#include <span>

namespace pcbench {

enum class ReuseWeights { kBalance, kPairwise, kCount, kUniform };

struct ReuseWeighting {
  ReuseWeights form = ReuseWeights::kBalance;
  // For kUniform: m = (1 - naive_share) count + naive_share / (k + 1); 0 leaves it honest.
  double naive_share = 1.0;
};

// m_s(x) of source `s` (0 is the canonical sample c), from every source's target at x,
// `targets[t]` = T_t (targets.size() = k + 1).
double reuse_mis_weight(const ReuseWeighting& weighting, std::span<const double> targets,
                        std::size_t s);

}  // namespace pcbench
