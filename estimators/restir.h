// restir: resampled importance sampling with spatial reuse across the camera samples of a batch
// (Bitterli et al. 2020, "Spatiotemporal reservoir resampling"), weighted as generalized RIS
// prescribes (Lin et al. 2022, "Generalized Resampled Importance Sampling"). The n camera samples
// of a batch (256, the last one fewer) share one pool of M light paths drawn from q = p(x).
// Round 0 is `ris` with K = 1 for every sample t, with target p̂_t(x) = p̂(x, y_t): a reservoir
// Y_t and W_t = Σ_j w_tj / (M p̂_t(Y_t)), w_tj = p̂_t(x_j) / q(x_j). Each of `rounds` rounds then
// gives sample c the sources S_c = {c, c+1, .., c+k} (mod n, k = min(N, n - 1)) and resamples
// their reservoirs of the round before with c's target:
//     ω_s = m_s(Y_s) p̂_c(Y_s) W_s,   Y ∝ ω (one more streaming reservoir),
//     W_c = (1 / p̂_c(Y)) Σ_s ω_s,    <I> = f(Y, y_c) W_c / p(y_c),
// with m_s(x) computed from every source's target at x (estimators/reuse_weights.h: weights =
// balance, pairwise or count). p̂_c in ω and in W_c makes W_c a contribution weight for the
// sample that receives Y, whatever the target of the source it came from.
//
// Why it is unbiased. W_s is an unbiased contribution weight for p̂_s: E[g(Y_s) W_s] sums g over
// the pool points where p̂_s > 0 as (1/M) Σ_j g(x_j) / q(x_j) does. Given the camera paths and the
// pool, E[f(Y) W_c] = Σ_s E[m_s(Y_s) f(Y_s) W_s] (the linearity of the reservoir's choice, with no
// independence between the sources needed: here they share the pool, and after a round they share
// reservoirs), = (1/M) Σ_j f(x_j, y_c) / q(x_j) Σ_{s: p̂_s(x_j) > 0} m_s(x_j): the pool's
// connect-to-all estimate, exactly, when (1) the weights of the sources that can produce x sum to
// 1 wherever p̂_c(x) > 0 (each form does when its T_s is the source's own target, visibility
// included) and (2) p̂_c > 0 wherever f(., y_c) != 0 (each target). Later rounds repeat the
// argument with the previous round's W, whose support is again {p̂_s > 0}. `verify --exact`
// checks exactly this equality case by case (harness/verify/exact_check.h). The estimates of a
// batch are correlated (one pool, shared reservoirs): the replicate, not the sample, is the unit.
//
// Parameters: M (default 16, 1..4096: a batch's 256 × M candidate pairs are held at once), N
// (neighbours, 4, 1..32), rounds (1, 1..4), target (approx, f, uniform: as ris), weights
// (balance, pairwise, count). The biased forms are negative controls (estimators/
// negative_controls.h): ctl-naive-reuse (m = 1/(k+1), Bitterli et al. 2020's biased 1/ΣM) and
// ctl-reuse-unshadowed (balance with the neighbours' targets without their visibility).
#pragma once

#include "estimators/registry.h"

namespace pcbench {

EstimatorEntry restir_entry();

}  // namespace pcbench
