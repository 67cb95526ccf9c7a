#include "integrands/linear_emitter.h"

namespace pcbench {

LinearEmitter::LinearEmitter(const ResolvedParams& params) : distance_(params.real("distance")) {}

Reference LinearEmitter::reference() const {
  return {.value = parallel::square_form_factor(distance_), .kind = ReferenceKind::kExact};
}

}  // namespace pcbench
