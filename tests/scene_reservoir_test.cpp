// The scene forms of ris and restir (estimators/scene/ris.cpp, restir.cpp) and the scene reuse
// controls (ctl_scene_reuse.cpp), exactly where an equality holds. Their unbiasedness in the
// furnace is SceneRenderFurnace's (their entries' renders), on scenes with shadow edges
// scenes.small's, and the controls' bias scenes.family's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "estimators/registry.h"
#include "estimators/scene/render_replicate.h"
#include "integrands/scenes/built_in_scenes.h"

namespace pcbench::scene {
namespace {

Scene small_cornell(std::uint32_t width, std::uint32_t height) {
  SceneDescription d = *built_in_scene("cornell");
  d.width = width;
  d.height = height;
  d.max_length = 3;
  return Scene(d);
}

ReplicateImage render(const Scene& scene, const std::string& estimator, const ParamText& params) {
  return render_replicate(scene, *make_scene_estimator(estimator, params), 55, 2, 3, nullptr, true);
}

// Every value of `b` equals `a`'s to `relative` (0: bit for bit), strategy layers included.
void expect_same_images(const ReplicateImage& a, const ReplicateImage& b, double relative) {
  ASSERT_EQ(a.image.values.size(), b.image.values.size());
  double total = 0.0;
  for (std::size_t i = 0; i < a.image.values.size(); ++i) {
    EXPECT_NEAR(b.image.values[i], a.image.values[i], relative * std::abs(a.image.values[i]))
        << "value " << i;
    total += a.image.values[i];
  }
  EXPECT_GT(total, 0.0);
  ASSERT_TRUE(a.strategies && b.strategies);
  ASSERT_EQ(a.strategies->layers.size(), b.strategies->layers.size());
  for (std::size_t l = 0; l < a.strategies->layers.size(); ++l) {
    const auto& x = a.strategies->layers[l].image.values;
    const auto& y = b.strategies->layers[l].image.values;
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_NEAR(y[i], x[i], relative * std::abs(x[i])) << "layer " << l << " value " << i;
    }
  }
}

// With one candidate the reservoir keeps it and W = 1/q: ris is pt from the same streams (the
// candidate reads pt's three uniforms), up to the rounding of f/p̂ × p̂/q.
TEST(SceneReservoir, RisWithOneCandidateIsPt) {
  const Scene scene = small_cornell(8, 8);
  expect_same_images(render(scene, "pt", {}), render(scene, "ris", {{"M", "1"}}), 1e-12);
  expect_same_images(render(scene, "pt", {}),
                     render(scene, "ris", {{"M", "1"}, {"target", "visible"}}), 1e-12);
}

// More candidates change the image: the same streams, a different estimate.
TEST(SceneReservoir, RisWithManyCandidatesIsNotPt) {
  const Scene scene = small_cornell(8, 8);
  const ReplicateImage pt = render(scene, "pt", {});
  const ReplicateImage ris = render(scene, "ris", {{"M", "8"}});
  double differs = 0.0;
  for (std::size_t i = 0; i < pt.image.values.size(); ++i) {
    differs += std::abs(ris.image.values[i] - pt.image.values[i]);
  }
  EXPECT_GT(differs, 1e-6);
}

// On a one-pixel image no neighbour lies in the disk: each round resamples the pixel's own
// reservoir alone, m = 1 and W' = p̂(Y) W / p̂(Y), so restir is ris, whatever its weights.
TEST(SceneReservoir, RestirWithoutNeighboursIsRis) {
  const Scene scene = small_cornell(1, 1);
  for (const char* weights : {"balance", "pairwise", "count"}) {
    SCOPED_TRACE(weights);
    for (std::uint32_t r = 0; r < 8; ++r) {
      const auto ris =
          render_replicate(scene, *make_scene_estimator("ris"), 9, r, 4, nullptr, true);
      const auto restir = render_replicate(
          scene, *make_scene_estimator("restir", {{"weights", weights}, {"rounds", "3"}}), 9, r, 4,
          nullptr, true);
      expect_same_images(ris, restir, 1e-12);
    }
  }
}

// The naive control at severity 0 is the honest 1/Z weighting with visible targets, bit for bit;
// its bias at severity 1 is scenes.family's to find (the shares lost change which sample each
// reservoir keeps, so no single render orders the two).
TEST(SceneReservoir, NaiveReuseControlAtSeverityZeroIsCountWeights) {
  const Scene scene = small_cornell(16, 16);
  const ParamText honest = {{"weights", "count"}, {"target", "visible"}};
  const ReplicateImage count = render(scene, "restir", honest);
  expect_same_images(count, render(scene, "ctl-scene-naive-reuse", {{"severity", "0"}}), 0.0);
  const ReplicateImage naive = render(scene, "ctl-scene-naive-reuse", {});
  double differs = 0.0;
  for (std::size_t i = 0; i < count.image.values.size(); ++i) {
    differs += std::abs(naive.image.values[i] - count.image.values[i]);
  }
  EXPECT_GT(differs, 0.0);
}

}  // namespace
}  // namespace pcbench::scene
