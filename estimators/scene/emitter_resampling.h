// Resampled next-event estimation at a camera vertex (Talbot et al. 2005), the step the scene
// forms of ris and restir share: M emitter points X_1 .. X_M from the emitters' own density q
// (power × area, integrands/scenes/emitters.h) stream through a weighted reservoir
// (estimators/reservoir.h) with weights w_i = p̂(X_i) / q(X_i), a batch of up to 64 at a time
// (Reservoir::offer_batch: Y ∝ w from one uniform a batch); the one kept, Y, carries the
// unbiased contribution weight
//     W = Σ_i w_i / (M p̂(Y)),   so that   E[f(Y) W] = ∫ f(x) dx   wherever p̂ > 0 where f > 0.
// f is the next-event strategy's MIS-weighted contribution (RenderServices::connect, strategy
// (1, t)), in the area measure of the emitter point x. The target p̂ is the contribution's
// largest channel without its MIS weight (a balance heuristic per candidate would cost more than
// the rest of it), without the shadow ray (unshadowed) or with it (visible); both are > 0
// wherever f is, so W is unbiased for either. A target defined alike at every pixel is what
// spatial reuse needs to compare samples between pixels: p̂_c(x) of camera vertex c is a
// function of c's prefix and x alone.
#pragma once

#include <cstdint>
#include <span>

#include "estimators/scene/scene_estimator.h"

namespace pcbench::scene {

enum class EmitterTarget {
  kUnshadowed,  // the contribution without visibility: M connections, no shadow ray
  kVisible,     // with visibility: a shadow ray per candidate, p̂ ∝ f exactly
};

// p̂(x) at a camera prefix, and the connection value it was taken from.
struct EmitterTargetValue {
  Rgb value;             // RenderServices::connect at x, unweighted, with the target's visibility
  double density = 0.0;  // p̂(x) = value's largest channel × q(x)
};

// p̂ at `camera` of x, a vertex emitter_vertex made (as every EmitterSample's point is):
// NextEventValues' value with the target's visibility.
EmitterTargetValue emitter_target(const RenderServices& services, const PathVertex& x,
                                  std::span<const PathVertex> camera, EmitterTarget target,
                                  TraceCounters& counters);
// emitter_target of each of xs (at most EmitterPoints::kCapacity) at one camera prefix, into
// out[j]: the same values and counters, the points weighed together (restir's reuse weighs
// every source's sample at each source's prefix: one call per prefix, not per pair).
void emitter_targets(const RenderServices& services, std::span<const PathVertex* const> xs,
                     std::span<const PathVertex> camera, EmitterTarget target,
                     std::span<EmitterTargetValue> out, TraceCounters& counters);

// One reservoir's outcome: the emitter point kept, its target at the reservoir's own camera
// prefix, and its contribution weight W (0 when no candidate had p̂ > 0).
struct EmitterSample {
  PathVertex point;
  EmitterTargetValue at_owner;
  double contribution_weight = 0.0;

  bool empty() const { return contribution_weight == 0.0; }
};

// RIS at `prefix` over `candidates` emitter points from the prefix's camera stream (where its
// walk left it; each candidate reads three uniforms, as path tracing's one emitter sample does),
// the reservoir's choices from its resampling stream.
EmitterSample resample_emitters(const RenderServices& services, CameraPrefix& prefix,
                                std::uint32_t candidates, EmitterTarget target);

// f(Y) W at camera prefix `camera` for a sample whose target there is `at_camera`: a shadow ray
// unless the target had one.
Rgb shade_emitter_sample(const RenderServices& services, const PathVertex& point,
                         const EmitterTargetValue& at_camera, double contribution_weight,
                         std::span<const PathVertex> camera, EmitterTarget target,
                         TraceCounters& counters);
// The unshadowed target's f(Y) W at `prefix`, its own reservoir's sample, asked of `queue`
// (ConnectionQueue::connect) instead: the renderer resolves a row's together, their values and
// weights in SIMD lanes and their shadow rays in packets, with shade_emitter_sample's value and
// counters. Nothing is asked when W = 0.
void queue_emitter_sample(const EmitterSample& y, const CameraPrefix& prefix,
                          ConnectionQueue& queue);

}  // namespace pcbench::scene
