// ris: resampled importance sampling (Talbot et al. 2005) with a streaming weighted reservoir, as
// ReSTIR keeps it. Each camera sample y draws M candidates x_1 .. x_M from the light sampling
// density q = p(x) (its own pool, or the batch's with pool=shared), streams them once through K
// independent reservoirs with weights w_j = p̂(x_j, y) / q(x_j), and each reservoir keeps one,
// Y_k, with probability w / Σ w (estimators/reservoir.h). Its contribution weight and the
// estimate are
//     W_k = (1 / p̂(Y_k, y)) (1/M) Σ_j w_j,
//     <I> = (1/K) Σ_k f(Y_k, y) W_k / p(y).
// Given the pool, E[f(Y) W] = Σ_j (w_j / Σ w) f(x_j) Σ w / (M p̂(x_j)) = (1/M) Σ_{j: p̂ > 0}
// f(x_j) / q(x_j): unbiased when p̂ > 0 wherever f != 0 (true of every target below).
//
// It is the family's pcbpt with uniform_mix = 0, importance w = p̂ / q and K independent draws,
// since f / (q M K P_j) with P_j = w_j / Σ w is f Σ w / (M K p̂): the same estimate of the same
// draw (tests/reservoir_test.cpp enumerates both). K independent reservoirs over one candidate
// set are K draws with replacement from P = w / Σ w, pcbpt's independent draws, each kept in one
// streaming pass as a renderer keeps a reservoir per pixel; they consume their own uniforms
// (reservoir k of sample s reads the kResampling stream of s, path k).
//
// Parameters: M (default 16, 1..2^20), K (reservoirs, 1, 1..2^16), target (approx: the
// integrand's approximation, the importance pcbpt's importance=approx uses; f: |f|; uniform: 1),
// pool (fresh, shared).
#pragma once

#include "estimators/registry.h"

namespace pcbench {

EstimatorEntry ris_entry();

}  // namespace pcbench
