#include "estimators/scene/emitter_resampling.h"

#include <algorithm>

#include "estimators/reservoir.h"
#include "integrands/scenes/next_event_values.h"

namespace pcbench::scene {

namespace {

// The visible target: the values whose shadow rays are blocked set to zero, the rays traced as
// packets (Scene::occluded_many) a packet's width at a time (a local array of a whole batch's
// rays was zeroed on every call), counted as connect() counts them; none traced in a convex
// enclosure, where nothing blocks a nonzero value.
void occlude(const Scene& scene, const NextEventValues& values, const EmitterPoints& points,
             NextEventValueLanes& at, TraceCounters& counters) {
  constexpr std::uint32_t kChunk = 16;
  const bool traces = !scene.traits().convex_enclosure;
  for (std::uint32_t first = 0; first < points.size; first += kChunk) {
    const std::uint32_t end = std::min<std::uint32_t>(first + kChunk, points.size);
    Scene::ShadowRay rays[kChunk];
    std::uint32_t ray_of[kChunk];
    std::uint8_t blocked[kChunk];
    std::uint32_t shadowed = 0;
    for (std::uint32_t j = first; j < end; ++j) {
      if (at[j].value.is_black()) continue;
      if (!traces) {
        ++counters.skipped_convex;
        continue;
      }
      rays[shadowed] = scene.shadow_ray(points[j].position, values.camera_end().position,
                                        at.distance_squared[j], at.distance[j]);
      ray_of[shadowed++] = j;
    }
    if (shadowed == 0) continue;
    if (shadowed == 1) {
      blocked[0] = scene.occluded(rays[0]) ? 1 : 0;
    } else {
      scene.occluded_many(std::span(rays, shadowed), std::span(blocked, shadowed));
    }
    counters.shadow_rays += shadowed;
    for (std::uint32_t k = 0; k < shadowed; ++k) {
      if (!blocked[k]) continue;
      ++counters.occluded;
      at.red[ray_of[k]] = at.green[ray_of[k]] = at.blue[ray_of[k]] = 0.0;
    }
  }
}

}  // namespace

EmitterTargetValue emitter_target(const RenderServices& services, const PathVertex& x,
                                  std::span<const PathVertex> camera, EmitterTarget target,
                                  TraceCounters& counters) {
  const PathVertex* const xs[] = {&x};
  EmitterTargetValue out[1];
  emitter_targets(services, xs, camera, target, out, counters);
  return out[0];
}

void emitter_targets(const RenderServices& services, std::span<const PathVertex* const> xs,
                     std::span<const PathVertex> camera, EmitterTarget target,
                     std::span<EmitterTargetValue> out, TraceCounters& counters) {
  // Without the MIS weight: a balance heuristic per candidate would cost more than the rest of
  // the candidate, and p̂ only needs to be > 0 wherever the weighted f is.
  if (xs.empty()) return;
  const Scene& scene = services.scene();
  const NextEventValues values(scene, camera, services.counts());
  EmitterPoints points;
  points.size = xs.size();
  for (std::size_t j = 0; j < xs.size(); ++j) points.set(j, emitter_point(scene, *xs[j]));
  NextEventValueLanes at;
  values.values(points, at, counters);
  if (target == EmitterTarget::kVisible) occlude(scene, values, points, at, counters);
  for (std::size_t j = 0; j < xs.size(); ++j) {
    const Rgb value = at[j].value;
    out[j] = {value, value.max_channel() * xs[j]->pdf_fwd};
  }
}

EmitterSample resample_emitters(const RenderServices& services, CameraPrefix& prefix,
                                std::uint32_t candidates, EmitterTarget target) {
  const Scene& scene = services.scene();
  const Emitters& emitters = scene.emitters();
  const NextEventValues values(scene, prefix.vertices, services.counts());
  // Candidates a batch at a time: their uniforms drawn together, their points and values in
  // structure-of-arrays form (the values in SIMD lanes), the visible target's shadow rays
  // traced as packets, the reservoir's choice one uniform a batch (Reservoir::offer_batch). The
  // same values and counters as the candidates one by one through connect().
  constexpr std::uint32_t kBatch = EmitterPoints::kCapacity;
  static_assert(kBatch <= Reservoir::kBatch);
  double u[3 * kBatch];
  EmitterPoints points;
  NextEventValueLanes at;
  double weights[kBatch];
  Reservoir reservoir;
  // The kept candidate's slot in its batch, its uniforms and its target; the sample made of them
  // once, at the end (a sample built first and filled in was zeroed whole, 176 bytes by rep stos,
  // at every step, and so was a point kept aside).
  std::uint32_t kept_slot = 0;
  double kept_u[3] = {};
  EmitterTargetValue kept_at;
  for (std::uint32_t first = 0; first < candidates; first += kBatch) {
    const std::uint32_t n = std::min(kBatch, candidates - first);
    prefix.camera.uniforms(std::span(u, 3 * n));
    emitters.sample_many(std::span(u, 3 * n), points);
    values.values(points, at, prefix.counters);
    if (target == EmitterTarget::kVisible) occlude(scene, values, points, at, prefix.counters);
    // w = p̂ / q: the value's largest channel, the connection already divided by q.
    for (std::uint32_t j = 0; j < n; ++j) weights[j] = at[j].value.max_channel();
    const std::uint32_t before = reservoir.kept();
    reservoir.offer_batch(first, std::span(weights, n), prefix.draws);
    if (reservoir.kept() != before) {
      kept_slot = reservoir.kept() - first;
      std::copy_n(u + 3 * kept_slot, 3, kept_u);
      kept_at = {at[kept_slot].value, weights[kept_slot] * points.pdf_area[kept_slot]};
    }
  }
  if (reservoir.empty()) return {};
  // In the last batch, its point is still in `points`; an earlier batch's is made again from its
  // uniforms (Emitters::sample, the same point as sample_many's).
  const bool in_last_batch = reservoir.kept() >= (candidates - 1) / kBatch * kBatch;
  return {.point = emitter_vertex(in_last_batch ? points[kept_slot]
                                                : emitters.sample(kept_u[0], kept_u[1], kept_u[2])),
          .at_owner = kept_at,
          .contribution_weight =
              reservoir.weight_sum() / (static_cast<double>(candidates) * kept_at.density)};
}

namespace {

// Whether a sample with target `at_camera` and weight W adds anything: f(Y) W with W = 0, or with
// a target of density 0 (no candidate had p̂ > 0), is 0 without a connection.
bool shades(const EmitterTargetValue& at_camera, double contribution_weight) {
  return contribution_weight != 0.0 && at_camera.density != 0.0;
}

}  // namespace

Rgb shade_emitter_sample(const RenderServices& services, const PathVertex& point,
                         const EmitterTargetValue& at_camera, double contribution_weight,
                         std::span<const PathVertex> camera, EmitterTarget target,
                         TraceCounters& counters) {
  if (!shades(at_camera, contribution_weight)) return {};
  // f(Y) in the area measure is the MIS-weighted connection × q(Y), q = the point's own density.
  // A visible target has already traced the shadow ray: only the weight is missing.
  const std::span<const PathVertex> light(&point, 1);
  const Rgb f_over_q =
      target == EmitterTarget::kVisible
          ? at_camera.value * mis_weight(services.scene(), light, camera, services.counts())
          : services.connect(light, camera, {}, counters);
  return f_over_q * (point.pdf_fwd * contribution_weight);
}

void queue_emitter_sample(const EmitterSample& y, const CameraPrefix& prefix,
                          ConnectionQueue& queue) {
  if (!shades(y.at_owner, y.contribution_weight)) return;
  queue.connect(y.point, prefix, y.point.pdf_fwd * y.contribution_weight);
}

}  // namespace pcbench::scene
