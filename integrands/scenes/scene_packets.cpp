// Scene::intersect_many and occluded_many: rays in Embree packets (rtcIntersect16/8/4,
// rtcOccluded16/8/4 by Scene::packet_width), each ray set up exactly as intersect() and occluded()
// set up one (the same floats), so that a packet's answers are the single rays' answers as far as
// Embree's kernels agree. They do not always: of pcbpt's importance rays in one run (32²,
// cornell and door-ajar, 4 spp × 2), 8 were blocked for rtcOccluded1 and free in a packet, the
// 8th at ray 59,386; so moving rays from one to the other can change an image's numbers.
#include <embree3/rtcore.h>

#include <algorithm>
#include <limits>

#include "integrands/scenes/embree_scene.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {
namespace {

// Embree's packet types and calls of one width.
template <std::uint32_t W>
struct Packets;
template <>
struct Packets<16> {
  using RayHit = RTCRayHit16;
  using Ray = RTCRay16;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect16(v, s, c, r);
  }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded16(v, s, c, r);
  }
};
template <>
struct Packets<8> {
  using RayHit = RTCRayHit8;
  using Ray = RTCRay8;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect8(v, s, c, r);
  }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded8(v, s, c, r);
  }
};
template <>
struct Packets<4> {
  using RayHit = RTCRayHit4;
  using Ray = RTCRay4;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect4(v, s, c, r);
  }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded4(v, s, c, r);
  }
};

// Lane k of a packet: the floats fill_ray (embree_scene.h) gives a single ray.
template <typename Ray>
void set_lane(Ray& ray, std::uint32_t k, const Vec3& origin, const Vec3& direction, float tnear,
              float tfar) {
  ray.org_x[k] = static_cast<float>(origin.x);
  ray.org_y[k] = static_cast<float>(origin.y);
  ray.org_z[k] = static_cast<float>(origin.z);
  ray.tnear[k] = tnear;
  ray.dir_x[k] = static_cast<float>(direction.x);
  ray.dir_y[k] = static_cast<float>(direction.y);
  ray.dir_z[k] = static_cast<float>(direction.z);
  ray.time[k] = 0.0f;
  ray.tfar[k] = tfar;
  ray.mask[k] = ~0u;
  ray.id[k] = 0;
  ray.flags[k] = 0;
}

template <typename Ray>
LoggedRay logged(const Ray& ray, std::uint32_t k, bool occlusion) {
  return {.origin = {ray.org_x[k], ray.org_y[k], ray.org_z[k]},
          .direction = {ray.dir_x[k], ray.dir_y[k], ray.dir_z[k]},
          .tnear = ray.tnear[k],
          .tfar = ray.tfar[k],
          .occlusion = occlusion};
}

}  // namespace

template <std::uint32_t W>
void Scene::intersect_packets(std::span<const Vec3> origins, std::span<const Vec3> directions,
                              std::span<Hit> hits, std::span<std::uint8_t> found) const {
  using P = Packets<W>;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  const float tnear = static_cast<float>(epsilon_);
  const float tfar = static_cast<float>(1e30);
  for (std::size_t first = 0; first < origins.size(); first += W) {
    const std::uint32_t count =
        static_cast<std::uint32_t>(std::min<std::size_t>(W, origins.size() - first));
    alignas(64) typename P::RayHit packet;
    alignas(64) int valid[W];
    for (std::uint32_t k = 0; k < W; ++k) {
      valid[k] = k < count ? -1 : 0;
      const std::size_t i = first + std::min(k, count - 1);  // masked lanes repeat the last ray
      set_lane(packet.ray, k, origins[i], directions[i], tnear, tfar);
      packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    if (ray_log_ != nullptr) [[unlikely]] {
      for (std::uint32_t k = 0; k < count; ++k) ray_log_->push_back(logged(packet.ray, k, false));
    }
    P::intersect(valid, embree_->handle(), &context, &packet);
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::size_t i = first + k;
      found[i] = packet.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
      if (found[i])
        hits[i] = hit_of(packet.hit.primID[k], packet.ray.tfar[k], origins[i], directions[i]);
    }
  }
}

template <std::uint32_t W>
void Scene::occluded_packets(std::span<const ShadowRay> rays,
                             std::span<std::uint8_t> blocked) const {
  using P = Packets<W>;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::size_t next = 0;
  while (next < rays.size()) {
    // The next W rays that are not empty (an empty one is never blocked, as in occluded()).
    alignas(64) typename P::Ray packet;
    alignas(64) int valid[W];
    std::size_t index[W];
    std::uint32_t count = 0;
    for (; next < rays.size() && count < W; ++next) {
      blocked[next] = 0;
      if (rays[next].empty) continue;
      const ShadowRay& r = rays[next];
      set_lane(packet, count, r.origin, r.d, static_cast<float>(r.margin),
               static_cast<float>(1.0 - r.margin));
      index[count++] = next;
    }
    if (count == 0) break;
    for (std::uint32_t k = 0; k < W; ++k) {
      valid[k] = k < count ? -1 : 0;
      if (k >= count) {
        const ShadowRay& r = rays[index[count - 1]];
        set_lane(packet, k, r.origin, r.d, 0.0f, 0.0f);
      }
    }
    if (ray_log_ != nullptr) [[unlikely]] {
      for (std::uint32_t k = 0; k < count; ++k) ray_log_->push_back(logged(packet, k, true));
    }
    P::occluded(valid, embree_->handle(), &context, &packet);
    for (std::uint32_t k = 0; k < count; ++k) {
      blocked[index[k]] = packet.tfar[k] == -std::numeric_limits<float>::infinity();
    }
  }
}

void Scene::intersect_many(std::span<const Vec3> origins, std::span<const Vec3> directions,
                           std::span<Hit> hits, std::span<std::uint8_t> found) const {
  if (packet_width_ == 16) return intersect_packets<16>(origins, directions, hits, found);
  if (packet_width_ == 8) return intersect_packets<8>(origins, directions, hits, found);
  intersect_packets<4>(origins, directions, hits, found);
}

void Scene::occluded_many(std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked) const {
  if (packet_width_ == 16) return occluded_packets<16>(rays, blocked);
  if (packet_width_ == 8) return occluded_packets<8>(rays, blocked);
  occluded_packets<4>(rays, blocked);
}

}  // namespace pcbench::scene
