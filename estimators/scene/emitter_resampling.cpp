#include "estimators/scene/emitter_resampling.h"

#include "estimators/reservoir.h"

namespace pcbench::scene {

EmitterTargetValue emitter_target(const RenderServices& services, const PathVertex& x,
                                  std::span<const PathVertex> camera, EmitterTarget target,
                                  TraceCounters& counters) {
  // Without the MIS weight: a balance heuristic per candidate would cost more than the rest of
  // the candidate, and p̂ only needs to be > 0 wherever the weighted f is.
  const Rgb value = services.connect(
      std::span(&x, 1), camera,
      {.visibility = target == EmitterTarget::kVisible, .weighted = false}, counters);
  return {value, value.max_channel() * x.pdf_fwd};
}

EmitterSample resample_emitters(const RenderServices& services, CameraPrefix& prefix,
                                std::uint32_t candidates, EmitterTarget target) {
  Reservoir reservoir;
  EmitterSample kept;
  for (std::uint32_t i = 0; i < candidates; ++i) {
    const PathVertex x = sample_emitter_vertex(services.scene(), prefix.camera);
    const EmitterTargetValue at_x =
        emitter_target(services, x, prefix.vertices, target, prefix.counters);
    // w = p̂ / q: the value's largest channel, the connection already divided by q.
    reservoir.offer(i, at_x.value.max_channel(), prefix.draws);
    if (reservoir.kept() == i) {
      kept.point = x;
      kept.at_owner = at_x;
    }
  }
  if (!reservoir.empty()) {
    kept.contribution_weight =
        reservoir.weight_sum() / (static_cast<double>(candidates) * kept.at_owner.density);
  }
  return kept;
}

Rgb shade_emitter_sample(const RenderServices& services, const PathVertex& point,
                         const EmitterTargetValue& at_camera, double contribution_weight,
                         std::span<const PathVertex> camera, EmitterTarget target,
                         TraceCounters& counters) {
  if (contribution_weight == 0.0 || at_camera.density == 0.0) return {};
  // f(Y) in the area measure is the MIS-weighted connection × q(Y), q = the point's own density.
  // A visible target has already traced the shadow ray: only the weight is missing.
  const std::span<const PathVertex> light(&point, 1);
  const Rgb f_over_q =
      target == EmitterTarget::kVisible
          ? at_camera.value * mis_weight(services.scene(), light, camera, services.counts())
          : services.connect(light, camera, {}, counters);
  return f_over_q * (point.pdf_fwd * contribution_weight);
}

}  // namespace pcbench::scene
