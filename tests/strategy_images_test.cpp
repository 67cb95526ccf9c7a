// --strategy-images: the image of each (s, t) connection strategy of a scene run. The layers
// must add up to the run's mean image, never change it, not depend on the thread count or on how
// the replicates were taken, and reach the run folder as one multi-layer EXR file the report
// describes.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "harness/commands/cli.h"
#include "harness/run/runner.h"
#include "harness/verify/image_statistics.h"
#include "results/exr_file.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kEstimators = {"plain", "pt", "lt", "vc-all", "lvc", "pcbpt"};
const std::vector<std::string> kScenes = {"furnace", "cornell"};

RunPlan small_scene_plan(const std::string& estimator, const std::string& scene) {
  return plan_single(estimator, scene, {{"resolution", {"16"}}}, 4, 2);
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The layers are the contributions the mean image sums, summed again grouped by strategy: all
// non-negative, so regrouping changes each pixel by at most (terms per pixel) × 2^-53 of its
// value, some 1e-14 here. 1e-12 allows for that and would catch a contribution counted twice or
// lost (always far larger than this).
constexpr double kRegroupingTolerance = 1e-12;

TEST(SceneRenderStrategyImages, SumToTheMeanImage) {
  for (const std::string& scene : kScenes) {
    for (const std::string& estimator : kEstimators) {
      SCOPED_TRACE(estimator + " on " + scene);
      const RunResult run =
          execute_run(small_scene_plan(estimator, scene), {.seed = 3, .strategy_images = true});
      ASSERT_EQ(run.status, RunStatus::kOk) << run.error;
      ASSERT_TRUE(run.strategy_images.has_value());
      const StrategyImages& strategies = *run.strategy_images;
      EXPECT_EQ(strategies.replicates, 2u);
      const Image mean = pixel_statistics(run.images).mean;
      std::vector<double> sum(mean.values.size(), 0.0);
      for (std::size_t i = 0; i < strategies.layers.size(); ++i) {
        const Image layer = strategies.mean(i);
        for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += layer.values[k];
      }
      std::size_t worse = 0;
      for (std::size_t k = 0; k < sum.size(); ++k) {
        if (std::fabs(sum[k] - mean.values[k]) > kRegroupingTolerance * mean.values[k]) ++worse;
      }
      EXPECT_EQ(worse, 0u) << "values whose strategies do not add up to the mean image";
      for (const StrategyLayer& layer : strategies.layers) {
        // Light tracing has only t = 1; path tracing never splats (t = 1) and connects s ≤ 1.
        if (estimator == "lt") {
          EXPECT_EQ(layer.t, 1u);
        }
        if (estimator == "pt") {
          EXPECT_NE(layer.t, 1u);
          EXPECT_LE(layer.s, 1u);
        }
      }
    }
  }
}

TEST(SceneRenderStrategyImages, LeaveTheImageAloneAndDoNotDependOnTheThreadCount) {
  for (const std::string& estimator : kEstimators) {
    SCOPED_TRACE(estimator);
    const RunPlan plan = small_scene_plan(estimator, "cornell");
    const RunResult without = execute_run(plan, {.seed = 5});
    EXPECT_FALSE(without.strategy_images.has_value());
    std::optional<RunResult> with[2];
    for (int threads : {1, 2}) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(threads));
      with[threads - 1] = execute_run(plan, {.seed = 5, .strategy_images = true});
    }
    ASSERT_EQ(with[0]->images.size(), without.images.size());
    for (std::size_t r = 0; r < without.images.size(); ++r) {
      EXPECT_TRUE(same_bits(with[0]->images[r].values, without.images[r].values)) << r;
    }
    const auto& one = with[0]->strategy_images->layers;
    const auto& two = with[1]->strategy_images->layers;
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t i = 0; i < one.size(); ++i) {
      EXPECT_TRUE(same_bits(one[i].image.values, two[i].image.values))
          << strategy_layer_name(one[i].s, one[i].t);
    }
  }
}

// Interleaved runs take their replicates one at a time (harness/run/interleaved_runs.h).
TEST(SceneRenderStrategyImages, ARunTakenInPartsAddsUpToTheRunTakenWhole) {
  const RunPlan plan = plan_single("pcbpt", "cornell", {{"resolution", {"16"}}}, 2, 3);
  const RunResult whole = execute_run(plan, {.seed = 2, .strategy_images = true});
  RunResult parts;
  for (std::uint32_t r = 0; r < 3; ++r) {
    RunResult part = execute_run(
        plan, {.seed = 2, .first_replicate = r, .replicate_count = 1, .strategy_images = true});
    if (r == 0) {
      parts = std::move(part);
    } else {
      append_part(parts, std::move(part));
    }
  }
  ASSERT_TRUE(parts.strategy_images.has_value());
  EXPECT_EQ(parts.strategy_images->replicates, 3u);
  ASSERT_EQ(parts.strategy_images->layers.size(), whole.strategy_images->layers.size());
  for (std::size_t i = 0; i < whole.strategy_images->layers.size(); ++i) {
    EXPECT_TRUE(same_bits(parts.strategy_images->layers[i].image.values,
                          whole.strategy_images->layers[i].image.values));
  }
}

TEST(SceneRenderStrategyImages, LayersOfAnotherRunAreRefused) {
  StrategyImages a, b;
  a.layers.push_back({.s = 0, .t = 2, .image = Image(2, 2)});
  b.layers.push_back({.s = 1, .t = 1, .image = Image(2, 2)});
  EXPECT_THROW(a.add(b), std::invalid_argument);
  b.layers.push_back({.s = 0, .t = 3, .image = Image(2, 2)});
  EXPECT_THROW(a.add(b), std::invalid_argument);
}

class CliStrategyImages : public InTemporaryFolder {};

// A channel by name, as read_exr returned them.
const std::vector<float>& channel(const std::vector<ExrChannel>& channels,
                                  const std::string& name) {
  for (const ExrChannel& c : channels) {
    if (c.name == name) return c.values;
  }
  throw std::runtime_error("no channel " + name);
}

// The files hold floats: each layer and the mean are rounded to 2^-24 of their value, so the
// layers' sum of up to ~20 strategies differs from the rounded mean by up to ~20 × 2^-24 ≈ 1.2e-6
// of it. 1e-5 allows for that; a lost or doubled layer is a difference of its whole share.
constexpr double kFloatFileTolerance = 1e-5;

TEST_F(CliStrategyImages, OneLayeredFileWhoseLayersSumToTheMeanImage) {
  const std::vector<std::string> common = {
      "run", "-e", "plain,pt,lt", "-i", "furnace,cornell", "-p", "resolution=16",
      "-n",  "4",  "-r",          "2",  "--quiet"};
  auto with = common, without = common;
  with.insert(with.end(), {"--strategy-images", "--out", "with"});
  without.insert(without.end(), {"--out", "without"});
  // Two replicates are too few for the tile test's self-check to flag its injected bias, so the
  // session may exit 1; with or without the flag it must come to the same verdicts.
  const CliResult a = cli(with);
  ASSERT_TRUE(a.status == 0 || a.status == 1) << a.err;
  EXPECT_EQ(cli(without).status, a.status);
  const nlohmann::json report = report_at("with");
  const nlohmann::json plain_report = report_at("without");
  ASSERT_EQ(report["runs"].size(), 6u);
  for (std::size_t i = 0; i < report["runs"].size(); ++i) {
    const nlohmann::json& run = report["runs"][i];
    const std::string estimator = run["estimator"];
    SCOPED_TRACE(estimator + " on " + run["integrand"].get<std::string>());
    const nlohmann::json& image = run["image"];
    const std::string file = image["files"]["strategies"];
    EXPECT_EQ(file, "images/" + run["id"].get<std::string>() + "_strategies.exr");

    // The layers the report lists, and nothing else, each as R, G, B.
    std::uint32_t width = 0, height = 0;
    const std::vector<ExrChannel> layers = read_exr(fs::path("with") / file, width, height);
    EXPECT_EQ(width, 16u);
    EXPECT_EQ(height, 16u);
    std::set<std::string> expected, found;
    double shares = 0.0;
    for (const nlohmann::json& strategy : image["strategies"]) {
      const std::string layer = strategy["layer"];
      EXPECT_EQ(layer, "s" + std::to_string(strategy["s"].get<int>()) + "_t" +
                           std::to_string(strategy["t"].get<int>()));
      for (const char* c : {".R", ".G", ".B"}) expected.insert(layer + c);
      shares += strategy["share"].get<double>();
      const int t = strategy["t"];
      if (estimator == "lt") {
        EXPECT_EQ(t, 1);
      }
      if (estimator == "pt") {
        EXPECT_NE(t, 1);
      }
    }
    for (const ExrChannel& c : layers) found.insert(c.name);
    EXPECT_EQ(found, expected);
    EXPECT_NEAR(shares, 1.0, 1e-9);

    std::uint32_t w = 0, h = 0;
    const std::vector<ExrChannel> mean =
        read_exr(fs::path("with") / image["files"]["mean"].get<std::string>(), w, h);
    for (const char* c : {"R", "G", "B"}) {
      const std::vector<float>& total = channel(mean, c);
      for (std::size_t k = 0; k < total.size(); ++k) {
        double sum = 0.0;
        for (const std::string& name : expected) {
          if (name.ends_with(std::string(".") + c)) sum += channel(layers, name)[k];
        }
        ASSERT_NEAR(sum, total[k], kFloatFileTolerance * total[k]) << c << " pixel " << k;
      }
    }

    // Without the flag: no file, no list, and the very same mean image.
    const nlohmann::json& plain_image = plain_report["runs"][i]["image"];
    EXPECT_FALSE(plain_image["files"].contains("strategies"));
    EXPECT_FALSE(plain_image.contains("strategies"));
    EXPECT_EQ(read_text(fs::path("with") / image["files"]["mean"].get<std::string>()),
              read_text(fs::path("without") / plain_image["files"]["mean"].get<std::string>()));
  }
  EXPECT_FALSE(fs::exists(fs::path("without") / "images" /
                          (report["runs"][0]["id"].get<std::string>() + "_strategies.exr")));
}

TEST_F(CliStrategyImages, TheSuiteKeyAsksForThemAndABadValueIsBadInput) {
  std::ofstream("bad.json") << R"({"strategy_images": "yes",
      "runs": [{"estimator": "pt", "integrand": "furnace", "params": {"resolution": 8}}]})";
  const std::vector<std::string> before = files_under(folder());
  const CliResult bad = cli({"run", "bad.json", "-n", "2", "-r", "2", "--out", "bad"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("bad.json: /strategy_images: must be true or false"), std::string::npos)
      << bad.err;
  EXPECT_EQ(files_under(folder()), before) << "bad input wrote something";

  std::ofstream("good.json") << R"({"strategy_images": true,
      "runs": [{"estimator": "pt", "integrand": "furnace", "params": {"resolution": 8}}]})";
  ASSERT_EQ(cli({"verify", "good.json", "-n", "2", "-r", "2", "--quiet", "--out", "good"}).status,
            0);
  const nlohmann::json image = report_at("good")["runs"][0]["image"];
  EXPECT_TRUE(fs::exists(fs::path("good") / image["files"]["strategies"].get<std::string>()));
  EXPECT_FALSE(image["strategies"].empty());
}

}  // namespace
}  // namespace pcbench
