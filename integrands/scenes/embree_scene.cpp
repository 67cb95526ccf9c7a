#include "integrands/scenes/embree_scene.h"

#include <stdexcept>

namespace pcbench::scene {
namespace {

// One device for the process, never released. A device per scene ran out after about a thousand
// (a suite over many resolutions keeps a scene per resolution; found by the suite fuzz target),
// and rtcNewDevice failing there aborted pcbench instead of running it.
RTCDevice shared_device() {
  static const RTCDevice device = [] {
    RTCDevice created = rtcNewDevice(nullptr);
    if (!created) throw std::runtime_error("Embree: rtcNewDevice failed");
    return created;
  }();
  return device;
}

}  // namespace

EmbreeScene::EmbreeScene(const std::vector<Triangle>& triangles) {
  RTCDevice device = shared_device();
  scene_ = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const std::size_t n = triangles.size();
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3* corners[3] = {&triangles[i].p0, &triangles[i].p1, &triangles[i].p2};
    for (int c = 0; c < 3; ++c) {
      vertices[9 * i + 3 * c + 0] = static_cast<float>(corners[c]->x);
      vertices[9 * i + 3 * c + 1] = static_cast<float>(corners[c]->y);
      vertices[9 * i + 3 * c + 2] = static_cast<float>(corners[c]->z);
      indices[3 * i + c] = static_cast<unsigned>(3 * i + c);
    }
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene_);
}

std::uint32_t EmbreeScene::native_packet_width() {
  static const std::uint32_t width = [] {
    const RTCDevice device = shared_device();
    if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) return 16u;
    if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) return 8u;
    return 4u;
  }();
  return width;
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
}

}  // namespace pcbench::scene
