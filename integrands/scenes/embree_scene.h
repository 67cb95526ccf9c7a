// An Embree 3 committed triangle scene built from a scene's triangles (float copies, one vertex
// triple per triangle) on the process's one Embree device, released on destruction. Scene traces
// through it; the benchmarks call Embree on it directly to measure the raw rate.
#pragma once

#include <embree3/rtcore.h>
#include <emmintrin.h>

#include <bit>
#include <cstdint>
#include <vector>

#include "integrands/scenes/scene_description.h"

namespace pcbench::scene {

// Fills an Embree ray from a double origin and direction in three 16-byte stores. Embree reads
// the ray back with 16-byte loads; a ray written float by float makes each of those loads wait
// for the scalar stores to retire (a failed store-to-load forwarding), which cost about a third
// of a closest-hit query (bench_scenes.cpp: BM_EmbreeRawClosestHitFilled against
// BM_EmbreeRawClosestHit).
inline void fill_ray(RTCRay& ray, const Vec3& origin, const Vec3& direction, float tnear,
                     float tfar) {
  static_assert(sizeof(RTCRay) == 48 && alignof(RTCRay) == 16);
  const __m128 org_xy = _mm_cvtpd_ps(_mm_set_pd(origin.y, origin.x));
  const __m128 org_z_tnear = _mm_cvtpd_ps(_mm_set_pd(tnear, origin.z));
  const __m128 dir_xy = _mm_cvtpd_ps(_mm_set_pd(direction.y, direction.x));
  const __m128 dir_z_time = _mm_cvtpd_ps(_mm_set_pd(0.0, direction.z));
  const __m128i far_mask_id_flags = _mm_setr_epi32(std::bit_cast<int>(tfar), -1, 0, 0);
  _mm_store_ps(&ray.org_x, _mm_movelh_ps(org_xy, org_z_tnear));
  _mm_store_ps(&ray.dir_x, _mm_movelh_ps(dir_xy, dir_z_time));
  _mm_store_ps(&ray.tfar, _mm_castsi128_ps(far_mask_id_flags));  // mask: every bit; id, flags 0
}

class EmbreeScene {
 public:
  explicit EmbreeScene(const std::vector<Triangle>& triangles);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene handle() const { return scene_; }
  // 16, 8 or 4: the widest ray packet this Embree build traces natively on this machine.
  static std::uint32_t native_packet_width();

 private:
  RTCScene scene_ = nullptr;
};

}  // namespace pcbench::scene
