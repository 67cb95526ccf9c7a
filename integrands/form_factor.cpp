#include "integrands/form_factor.h"

namespace pcbench {

FormFactor::FormFactor(const ResolvedParams& params) : distance_(params.real("distance")) {}

Reference FormFactor::reference() const {
  return {.value = parallel::square_form_factor(distance_), .kind = ReferenceKind::kExact};
}

}  // namespace pcbench
