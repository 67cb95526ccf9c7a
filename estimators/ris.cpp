#include "estimators/ris.h"

#include "estimators/family_params.h"
#include "estimators/reservoir_params.h"

namespace pcbench {

EstimatorEntry ris_entry() {
  ParamSpec reservoirs = draws_spec(1);
  reservoirs.description = "independent reservoirs per camera sample (draws with replacement)";
  return reservoir_entry("ris",
                         "resampled importance sampling: M candidates from q streamed through a "
                         "reservoir, w = p̂/q, W = Σw / (M p̂)",
                         {pool_size_spec(), reservoirs, target_spec(), pool_mode_spec()}, {});
}

}  // namespace pcbench
