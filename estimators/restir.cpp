#include "estimators/restir.h"

#include "estimators/family_params.h"
#include "estimators/reservoir_params.h"

namespace pcbench {

EstimatorEntry restir_entry() {
  return reservoir_entry(
      "restir",
      "RIS with spatial reuse from N camera samples of the batch sharing one pool, "
      "weights balance, pairwise or count (generalized RIS)",
      {pool_size_spec(16, 1, kReuseMaxM), neighbours_spec(), rounds_spec(), target_spec(),
       reuse_weights_spec()},
      {.pool = PoolMode::kShared, .neighbours = 4, .rounds = 1});
}

}  // namespace pcbench
