// plain: the seed's estimator with M = K = 1 (P = 1): one fresh light path per camera sample,
// connected once. <I> = f(x, y) / (p(x) p(y)). Plain bidirectional path tracing on a scene.
// Parameters: none.
#pragma once

#include "estimators/estimator.h"

namespace pcbench {

class PlainEstimator final : public Estimator {
 public:
  void estimate_batch(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                      std::span<double> estimates) const override;
};

}  // namespace pcbench
