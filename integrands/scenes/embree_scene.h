// An Embree 3 committed triangle scene built from a scene's triangles (float copies, one vertex
// triple per triangle) on the process's one Embree device, released on destruction. Scene traces
// through it; the benchmarks call Embree on it directly to measure the raw rate.
#pragma once

#include <embree3/rtcore.h>

#include <vector>

#include "integrands/scenes/scene_description.h"

namespace pcbench::scene {

class EmbreeScene {
 public:
  explicit EmbreeScene(const std::vector<Triangle>& triangles);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene handle() const { return scene_; }

 private:
  RTCScene scene_ = nullptr;
};

}  // namespace pcbench::scene
