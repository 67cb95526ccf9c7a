#include "integrands/scenes/connection_queue.h"

#include <stdexcept>

#include "integrands/scenes/next_event_batch.h"
#include "integrands/scenes/render_services.h"

namespace pcbench::scene {

namespace {

// A request belongs to the prefix begun last: a pass that queues for another one (one kept from
// an earlier call) would connect the wrong camera vertices.
void check_current(const ConnectionQueue::Prefix& current, const CameraPrefix& prefix) {
  if (current.camera.data() != prefix.vertices.data() ||
      current.camera.size() != prefix.vertices.size()) {
    throw std::logic_error(
        "ConnectionQueue: a connection queued for a prefix other than the current one");
  }
}

}  // namespace

void ConnectionQueue::connect(std::span<const PathVertex> light, const CameraPrefix& prefix,
                              double scale) {
  check_current(prefixes_.back(), prefix);
  requests_.push_back({light.data(), static_cast<std::uint32_t>(light.size()), 0, scale});
  ++prefixes_.back().end;
}

void ConnectionQueue::connect(const PathVertex& light_vertex, const CameraPrefix& prefix,
                              double scale) {
  check_current(prefixes_.back(), prefix);
  requests_.push_back({nullptr, 1, static_cast<std::uint32_t>(owned_.size()), scale});
  owned_.push_back(light_vertex);
  ++prefixes_.back().end;
}

void ConnectionQueue::clear() {
  prefixes_.clear();
  requests_.clear();
  owned_.clear();
}

void ConnectionQueue::begin_prefix(const CameraPrefix& prefix, bool adds_emitter_hit,
                                   const Rgb& emitter_hit) {
  const std::uint32_t first = static_cast<std::uint32_t>(requests_.size());
  prefixes_.push_back({.camera = prefix.vertices,
                       .pixel = prefix.pixel,
                       .adds_emitter_hit = adds_emitter_hit,
                       .connects = prefix.max_s > 0,
                       .emitter_hit = emitter_hit,
                       .first = first,
                       .end = first});
}

void ConnectionBatch::connect_all(const Scene& scene, const StrategyCounts& counts,
                                  std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                                  TraceCounters& counters,
                                  std::span<std::optional<PixelPosition>> pixels) {
  shadows_.clear();
  shadowed_.clear();
  // Next-event connections under counts with nothing else (pt) in lanes, value and weight
  // together (next_event_batch.h); any others one at a time through connect() and mis_weight().
  const bool next_events = pixels.empty() && next_event_only(counts) && all_next_events(pairs);
  if (next_events) {
    weights_.resize(pairs.size());
    next_event_values_and_weights(scene, counts, pairs, values, weights_, counters);
  }
  const auto weight = [&](std::uint32_t i) {
    return next_events ? weights_[i] : mis_weight(scene, pairs[i].light, pairs[i].camera, counts);
  };
  // The unweighted, unoccluded values; the shadow rays of those that are not black.
  for (std::uint32_t i = 0; i < pairs.size(); ++i) {
    const ConnectionPair& pair = pairs[i];
    if (!next_events) {
      std::optional<PixelPosition>* pixel = pixels.empty() ? nullptr : &pixels[i];
      values[i] = scene::connect(scene, pair.light, pair.camera, counts,
                                 {.visibility = false, .weighted = false}, counters, pixel);
    }
    if (values[i].is_black()) continue;
    if (scene.traits().convex_enclosure) {
      ++counters.skipped_convex;
      values[i] = values[i] * weight(i);
      continue;
    }
    shadows_.push_back(scene.shadow_ray(pair.light.back().position, pair.camera.back().position));
    shadowed_.push_back(i);
  }
  blocked_.resize(shadows_.size());
  scene.occluded_many(shadows_, blocked_);
  counters.shadow_rays += shadows_.size();
  for (std::size_t k = 0; k < shadowed_.size(); ++k) {
    const std::uint32_t i = shadowed_[k];
    if (blocked_[k]) {
      ++counters.occluded;
      values[i] = {};
      continue;
    }
    values[i] = values[i] * weight(i);
  }
}

void ConnectionQueue::resolve(const Scene& scene, const StrategyCounts& counts,
                              TraceCounters& counters) {
  pairs_.resize(requests_.size());
  for (const Prefix& p : prefixes_) {
    for (std::uint32_t i = p.first; i < p.end; ++i) pairs_[i] = {light_of(requests_[i]), p.camera};
  }
  values_.resize(requests_.size());
  batch_.connect_all(scene, counts, pairs_, values_, counters);
  for (std::size_t i = 0; i < requests_.size(); ++i) {
    values_[i] = requests_[i].scale * values_[i];
  }
}

}  // namespace pcbench::scene
