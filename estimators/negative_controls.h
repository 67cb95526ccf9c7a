// Negative controls: estimators that are biased on purpose, each by one mistake seen in
// practice, so that the verifier can show it catches them. Each has a `severity` in [0, 1] (0
// makes it unbiased, or nearly for ctl-cached-visibility; 1 is the full mistake) and declares
// the integrand and budget on which it must be flagged.
//
//   ctl-cached-visibility  (a) importance = |f| at the cache point of the camera sample's cell,
//                          with no uniform mixing: where the cache point is occluded and the
//                          camera path is not, P = 0 while f != 0. Cells of width `severity`.
//   ctl-cull-small         (b) importances below severity × the pool's largest are set to 0,
//                          no mixing.
//   ctl-wrong-count        (c) the estimate is divided by M - severity instead of M.
//   ctl-best-draw          (d) outcome-selected reuse: a share `severity` of the estimate is the
//                          draw that contributed most, weighted as if it were the only draw.
//   ctl-renormalise-kept   (e) candidates below severity × the largest importance are dropped,
//                          and the estimate is divided by the number kept instead of M.
//   ctl-foreign-normaliser (f) the draws follow P built on this pool, but the weight's Σ w mixes
//                          in (by `severity`) the total of another, independent pool.
//   ctl-without-replacement (g) draws without replacement weighted by the with-replacement
//                          formula 1 / (M K P); P mixes the importance with uniform by
//                          1 - severity (uniform P would make it unbiased).
//   ctl-naive-reuse        restir (estimators/restir.h) with target |f| whose reuse weights
//                          every source 1/(k+1) (Bitterli et al. 2020's biased 1/ΣM), blended
//                          with the honest 1/Z by 1 - severity: where a neighbour's target is 0
//                          (occluded) and the sample's is not, the weights of the sources that can
//                          produce x sum to less than 1.
//   ctl-reuse-unshadowed   restir with target |f| and balance weights whose neighbours' targets
//                          are (1 - severity) p̂ + severity × the unoccluded approximation: the
//                          weights forget that an occluded neighbour cannot produce x, and sum to
//                          less than 1 over the sources that can.
//                          Both are declared on blocker, whose neighbours' supports differ.
#pragma once

#include <vector>

#include "estimators/registry.h"

namespace pcbench {

std::vector<EstimatorEntry> negative_control_entries();

}  // namespace pcbench
