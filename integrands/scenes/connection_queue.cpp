#include "integrands/scenes/connection_queue.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "integrands/scenes/connection_lanes.h"
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

void ConnectionQueue::connect_emitter_sample(RandomStream& rng, const CameraPrefix& prefix,
                                             double scale) {
  check_current(prefixes_.back(), prefix);
  // sample_emitter_vertex's three uniforms, in its order.
  const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
  requests_.push_back(
      {nullptr, 1, static_cast<std::uint32_t>(emitter_uniforms_.size() / 3), scale, true});
  emitter_uniforms_.insert(emitter_uniforms_.end(), {u0, u1, u2});
  ++sampled_;
  ++prefixes_.back().end;
}

void ConnectionQueue::begin_subtotal(const CameraPrefix& prefix) {
  Prefix& current = prefixes_.back();
  check_current(current, prefix);
  if (current.has_subtotal) {
    throw std::logic_error("ConnectionQueue: a second subtotal for one prefix");
  }
  current.has_subtotal = true;
  current.subtotal = current.end;
}

Rgb ConnectionQueue::sum(const Prefix& p) const {
  Rgb total, group;
  for (std::uint32_t i = p.first; i < p.end; ++i) {
    (p.has_subtotal && i >= p.subtotal ? group : total) += values_[i];
  }
  if (p.has_subtotal) total += group;
  return total;
}

void ConnectionQueue::clear() {
  prefixes_.clear();
  requests_.clear();
  owned_.clear();
  emitter_uniforms_.clear();
  sampled_ = 0;
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

template <class Value, class Ends, class Weigh>
void ConnectionBatch::trace_and_weigh_each(const Scene& scene, const Value& value, const Ends& ends,
                                           const Weigh& weigh, std::span<Rgb> values,
                                           TraceCounters& counters) {
  shadows_.clear();
  shadowed_.clear();
  unblocked_.clear();
  for (std::uint32_t i = 0; i < values.size(); ++i) {
    value(i);
    if (values[i].is_black()) continue;
    if (scene.traits().convex_enclosure) {
      ++counters.skipped_convex;
      unblocked_.push_back(i);
      continue;
    }
    const auto [light_end, camera_end] = ends(i);
    shadows_.push_back(scene.shadow_ray(light_end, camera_end));
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
    unblocked_.push_back(i);
  }
  unblocked_weights_.resize(unblocked_.size());
  weigh(std::span<const std::uint32_t>(unblocked_), std::span<double>(unblocked_weights_));
  for (std::size_t k = 0; k < unblocked_.size(); ++k) {
    values[unblocked_[k]] = values[unblocked_[k]] * unblocked_weights_[k];
  }
}

void ConnectionBatch::trace_and_weigh(const Scene& scene, std::span<const Vec3> light_ends,
                                      std::span<const Vec3> camera_ends,
                                      std::span<const double> weights, std::span<Rgb> values,
                                      TraceCounters& counters) {
  trace_and_weigh_each(
      scene, [](std::uint32_t) {},
      [&](std::uint32_t i) { return std::pair(light_ends[i], camera_ends[i]); },
      [&](std::span<const std::uint32_t> which, std::span<double> out) {
        for (std::size_t k = 0; k < which.size(); ++k) out[k] = weights[which[k]];
      },
      values, counters);
}

void ConnectionBatch::connect_all(const Scene& scene, const StrategyCounts& counts,
                                  std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                                  TraceCounters& counters,
                                  std::span<std::optional<PixelPosition>> pixels) {
  // The unweighted, unoccluded values in lanes (connection_lanes.h): next-event connections
  // under counts with nothing else (pt) value and weight together; a batch of other
  // connections with t >= 2 (a row's) or of light tracing's (t = 1, a chunk of pool paths' splats)
  // the values, mis_weight() for those not blocked. A batch that mixes them (none does) one at a
  // time through connect().
  const bool next_events = pixels.empty() && next_event_only(counts) && all_next_events(pairs);
  const bool camera_side = pixels.empty() && all_camera_surface_ends(pairs);
  const bool lens = !pixels.empty() && all_light_tracing(pairs);
  const bool in_lanes = next_events || camera_side || lens;
  if (next_events) {
    weights_.resize(pairs.size());
    next_event_values_and_weights(scene, counts, pairs, values, weights_, counters);
  } else if (camera_side) {
    connection_values(scene, counts, pairs, values, counters);
  } else if (lens) {
    light_tracing_values(scene, counts, pairs, values, pixels, counters);
  }
  trace_and_weigh_each(
      scene,
      [&](std::uint32_t i) {  // each value just before its shadow ray, while its ends are at hand
        if (in_lanes) return;
        std::optional<PixelPosition>* pixel = pixels.empty() ? nullptr : &pixels[i];
        values[i] = scene::connect(scene, pairs[i].light, pairs[i].camera, counts,
                                   {.visibility = false, .weighted = false}, counters, pixel);
      },
      [&](std::uint32_t i) {
        return std::pair(pairs[i].light.back().position, pairs[i].camera.back().position);
      },
      [&](std::span<const std::uint32_t> which, std::span<double> out) {
        if (next_events) {  // weighed with their values
          for (std::size_t k = 0; k < which.size(); ++k) out[k] = weights_[which[k]];
        } else if (camera_side) {
          connection_weights(scene, counts, pairs, which, out);
        } else {
          for (std::size_t k = 0; k < which.size(); ++k) {
            const ConnectionPair& pair = pairs[which[k]];
            out[k] = mis_weight(scene, pair.light, pair.camera, counts);
          }
        }
      },
      values, counters);
}

void ConnectionQueue::make_sampled_vertices(const Scene& scene) {
  if (sampled_ == 0) return;
  for (Request& r : requests_) {
    if (!r.sampled) continue;
    const double* u = &emitter_uniforms_[3 * std::size_t{r.owned}];
    r.owned = static_cast<std::uint32_t>(owned_.size());
    r.sampled = false;
    owned_.push_back(emitter_vertex(scene.emitters().sample(u[0], u[1], u[2])));
  }
  sampled_ = 0;
}

void ConnectionQueue::resolve_sampled_next_events(const Scene& scene, const StrategyCounts& counts,
                                                  TraceCounters& counters) {
  const std::size_t n = requests_.size();
  camera_end_of_.resize(n);
  for (const Prefix& p : prefixes_) {
    for (std::uint32_t i = p.first; i < p.end; ++i) camera_end_of_[i] = &p.camera.back();
  }
  light_ends_.resize(n);
  camera_ends_.resize(n);
  weights_.resize(n);
  EmitterPoints points;
  for (std::size_t first = 0; first < n; first += EmitterPoints::kCapacity) {
    const std::size_t size = std::min(EmitterPoints::kCapacity, n - first);
    // The requests were queued in order, so their uniforms are the chunk's, in order.
    scene.emitters().sample_many(std::span(emitter_uniforms_).subspan(3 * first, 3 * size), points);
    next_event_values_and_weights(scene, counts, points,
                                  std::span(camera_end_of_).subspan(first, size),
                                  std::span(values_).subspan(first, size),
                                  std::span(weights_).subspan(first, size), counters);
    for (std::size_t j = 0; j < size; ++j) {
      light_ends_[first + j] = {points.x[j], points.y[j], points.z[j]};
      camera_ends_[first + j] = camera_end_of_[first + j]->position;
    }
  }
  batch_.trace_and_weigh(scene, light_ends_, camera_ends_, weights_, values_, counters);
}

void ConnectionQueue::resolve(const Scene& scene, const StrategyCounts& counts,
                              TraceCounters& counters) {
  values_.resize(requests_.size());
  if (sampled_ > 0 && sampled_ == requests_.size() && next_event_only(counts)) {
    resolve_sampled_next_events(scene, counts, counters);
  } else {
    make_sampled_vertices(scene);
    pairs_.resize(requests_.size());
    for (const Prefix& p : prefixes_) {
      for (std::uint32_t i = p.first; i < p.end; ++i) {
        pairs_[i] = {light_of(requests_[i]), p.camera};
      }
    }
    batch_.connect_all(scene, counts, pairs_, values_, counters);
  }
  for (std::size_t i = 0; i < requests_.size(); ++i) {
    values_[i] = requests_[i].scale * values_[i];
  }
}

}  // namespace pcbench::scene
