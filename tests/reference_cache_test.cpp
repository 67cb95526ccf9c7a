// The reference cache: its key follows the traced scene and nothing else, entries round-trip,
// only a better-converged image replaces one, and broken entries are ignored with a warning.
// Then the errors against a noisy reference, and `pcbench reference` end to end.
#include "harness/verify/reference_cache.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "harness/commands/cli.h"
#include "harness/verify/image_errors.h"
#include "harness/verify/image_statistics.h"
#include "integrands/scenes/built_in_scenes.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

scene::SceneDescription cornell() {
  return *scene::built_in_scene("cornell");
}

// A small image with distinct values, and a standard error of `share` of each.
ReferenceImage image_with(double scale, double share) {
  ReferenceImage out{.mean = Image(4, 3), .standard_error = Image(4, 3), .provenance = {}};
  for (std::size_t i = 0; i < out.mean.values.size(); ++i) {
    out.mean.values[i] = scale * (1.0 + static_cast<double>(i));
    out.standard_error.values[i] = share * out.mean.values[i];
  }
  out.provenance = {{"estimator", "plain"}, {"samples_per_pixel", 7}};
  return out;
}

scene::SceneDescription small(scene::SceneDescription d) {
  d.width = 4;
  d.height = 3;
  return d;
}

TEST(ReferenceCache, KeyFollowsTheTracedSceneOnly) {
  const scene::SceneDescription base = cornell();
  scene::SceneDescription renamed = base;
  renamed.name = "my-box";
  renamed.source = "elsewhere.json";
  EXPECT_EQ(reference_key(base), reference_key(renamed));
  EXPECT_EQ(reference_key(base).size(), 16u);

  scene::SceneDescription moved = base;
  moved.triangles[3].p1.x = std::nextafter(moved.triangles[3].p1.x, 2.0);  // one ulp
  scene::SceneDescription wider = base;
  wider.width += 1;
  scene::SceneDescription longer = base;
  longer.max_length += 1;
  scene::SceneDescription duller = base;
  duller.materials[0].albedo.g *= 0.5;
  scene::SceneDescription turned = base;
  turned.camera.fov_degrees += 1.0;
  for (const auto* other : {&moved, &wider, &longer, &duller, &turned}) {
    EXPECT_NE(reference_key(base), reference_key(*other));
  }
}

TEST(ReferenceCache, StoresFindsAndKeepsTheBetterImage) {
  TemporaryFolder folder;
  const ReferenceCache cache(folder.path() / "refs");
  const scene::SceneDescription scene = small(cornell());
  std::ostringstream warn;
  EXPECT_FALSE(cache.find(scene, warn).has_value());

  ASSERT_TRUE(cache.store(scene, image_with(1.0, 0.02), warn));
  auto found = cache.find(scene, warn);
  ASSERT_TRUE(found.has_value());
  for (std::size_t i = 0; i < found->mean.values.size(); ++i) {
    // Stored as 32-bit floats: equal to float rounding.
    EXPECT_NEAR(found->mean.values[i], 1.0 + static_cast<double>(i), 1e-6 * (1.0 + i));
    EXPECT_NEAR(found->standard_error.values[i], 0.02 * (1.0 + i), 1e-7 * (1.0 + i));
  }
  EXPECT_EQ(found->provenance["estimator"], "plain");
  EXPECT_EQ(found->provenance["key"], reference_key(scene));
  EXPECT_NEAR(found->provenance["relative_variance"].get<double>(),
              relative_variance(found->mean, found->standard_error), 1e-9);

  // A noisier image does not replace it; a better-converged one does.
  EXPECT_FALSE(cache.store(scene, image_with(2.0, 0.05), warn));
  EXPECT_NEAR(cache.find(scene, warn)->mean.values[0], 1.0, 1e-6);
  EXPECT_TRUE(cache.store(scene, image_with(3.0, 0.01), warn));
  EXPECT_NEAR(cache.find(scene, warn)->mean.values[0], 3.0, 1e-6);
  EXPECT_EQ(warn.str(), "");
  // Another resolution is another scene.
  scene::SceneDescription other = scene;
  other.width = 5;
  EXPECT_FALSE(cache.find(other, warn).has_value());
}

TEST(ReferenceCache, BrokenEntriesAreIgnoredWithAWarning) {
  TemporaryFolder folder;
  const ReferenceCache cache(folder.path());
  const scene::SceneDescription scene = small(cornell());
  std::ostringstream warn;
  ASSERT_TRUE(cache.store(scene, image_with(1.0, 0.02), warn));
  const fs::path exr = cache.image_path(scene);
  const fs::path json = fs::path(exr).replace_extension(".json");

  const std::string good_json = read_text(json);
  write_text(json, "{\"format\": \"pcbench-reference-1\", \"key\": \"0000000000000000\"}");
  EXPECT_FALSE(cache.find(scene, warn).has_value());
  EXPECT_NE(warn.str().find("key is not this scene's"), std::string::npos) << warn.str();
  EXPECT_NE(warn.str().find(exr.string()), std::string::npos) << warn.str();

  write_text(json, good_json);
  write_text(exr, "not an EXR file");
  warn.str("");
  EXPECT_FALSE(cache.find(scene, warn).has_value());
  EXPECT_NE(warn.str().find("warning: ignoring the cached reference"), std::string::npos);
  // A broken entry is replaced by the next image stored.
  EXPECT_TRUE(cache.store(scene, image_with(1.0, 0.02), warn));
  EXPECT_TRUE(cache.find(scene, warn).has_value());

  // An image without its JSON is no entry (a store cut short between the two files), silently.
  fs::remove(json);
  warn.str("");
  EXPECT_FALSE(cache.find(scene, warn).has_value());
  EXPECT_EQ(warn.str(), "");
}

// Replicates equal to the truth, measured against a reference off by exactly its standard error
// everywhere: the raw squared error is all the reference's, so the run's errors are 0.
TEST(ImageErrors, SubtractTheReferencesOwnVariance) {
  const ReferenceImage truth = image_with(1.0, 0.0);
  Image reference = truth.mean, stderr_image(4, 3);
  for (std::size_t i = 0; i < reference.values.size(); ++i) {
    stderr_image.values[i] = 0.1 * truth.mean.values[i];
    reference.values[i] += (i % 2 ? 1.0 : -1.0) * stderr_image.values[i];
  }
  const std::vector<Image> replicates(3, truth.mean);
  const std::vector<ReplicateResult> results(3, ReplicateResult{.cpu_seconds = 2.0});
  const auto noisy = image_error_fields(replicates, results, truth.mean, reference, &stderr_image);
  EXPECT_NEAR(noisy["rel_mse"].get<double>(), 0.0, 1e-15);
  EXPECT_NEAR(noisy["rmse"].get<double>(), 0.0, 1e-7);
  EXPECT_GT(noisy["reference_rel_variance"].get<double>(), 5e-3);
  EXPECT_DOUBLE_EQ(noisy["cpu_seconds_per_replicate"].get<double>(), 2.0);
  // Without the standard error (an exact reference) the same difference is all error.
  const auto exact = image_error_fields(replicates, results, truth.mean, reference, nullptr);
  EXPECT_NEAR(exact["rel_mse"].get<double>(), noisy["reference_rel_variance"].get<double>(), 1e-15);
  EXPECT_DOUBLE_EQ(exact["rel_mse_at_1_cpu_second"].get<double>(),
                   2.0 * exact["rel_mse_per_replicate"].get<double>());
}

TEST(CliReference, LaterRunsMeasureTheirErrorsAgainstTheCache) {
  TemporaryFolder folder;
  const std::string cache = (folder.path() / "refs").string();
  const std::vector<std::string> scene = {"-i", "cornell", "-p", "resolution=8"};
  std::vector<std::string> make = {"reference", "-n", "16", "-r", "4", "--reference-cache", cache};
  make.insert(make.end(), scene.begin(), scene.end());
  const CliResult made = cli(make);
  ASSERT_EQ(made.status, 0) << made.err;
  EXPECT_NE(made.out.find("cornell 8x8 L=5 with plain: 16 spp × 4 replicates"), std::string::npos)
      << made.out;
  // The same request again keeps the entry (not better converged).
  const CliResult again = cli(make);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NE(again.out.find("kept the cached image"), std::string::npos) << again.out;

  // plain and pcbpt on the scene, with `cache_folder` as the reference cache, into `out`.
  const auto run_into = [&](const fs::path& out, const std::string& cache_folder) {
    std::vector<std::string> run = {
        "run",   "-e",         "plain,pcbpt",       "-n",        "2", "-r", "2", "-q",
        "--out", out.string(), "--reference-cache", cache_folder};
    run.insert(run.end(), scene.begin(), scene.end());
    const CliResult ran = cli(run);
    EXPECT_EQ(ran.status, 0) << ran.err;
    return nlohmann::json::parse(read_text(out / "report.json"));
  };
  const auto report = run_into(folder.path() / "run", cache);
  for (const auto& r : report["runs"]) {
    const auto& image = r["image"];
    EXPECT_EQ(image["reference"], "cache");
    EXPECT_EQ(image["reference_cache"]["samples_per_pixel"], 16);
    EXPECT_GT(image["reference_rel_variance"].get<double>(), 0.0);
    // The pixel test stays with the session's own other run.
    EXPECT_EQ(image["pixel_test"]["against"].get<std::string>().rfind("run ", 0), 0u);
    EXPECT_TRUE(fs::exists(folder.path() / "run" / image["files"]["reference"].get<std::string>()));
  }
  // Without a cached image the reference is the best other run, as before.
  const auto uncached = run_into(folder.path() / "run2", (folder.path() / "empty").string());
  EXPECT_EQ(uncached["runs"][0]["image"]["reference"].get<std::string>().rfind("run ", 0), 0u);
}

TEST(CliReference, BadRequestsExitTwoAndWriteNothing) {
  TemporaryFolder folder;
  const std::string cache = (folder.path() / "refs").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"reference", "-i", "genz-gaussian"}, "a reference image is made of a scene only"},
      {{"reference", "-i", "cornell", "-e", "ctl-scene-lvc-per-vertex"}, "negative control"},
      {{"reference"}, "--integrand is required"},
      {{"reference", "-i", "cornell", "-r", "1"}, "replicates"},
      {{"reference", "-i", "cornell", "-p", "resolution=0"}, "resolution"},
  };
  for (const auto& [args, message] : cases) {
    std::vector<std::string> full = args;
    full.insert(full.end(), {"--reference-cache", cache});
    const CliResult r = cli(full);
    EXPECT_EQ(r.status, 2) << args.back();
    EXPECT_NE((r.err + r.out).find(message), std::string::npos) << r.err << r.out;
  }
  EXPECT_FALSE(fs::exists(cache));
}

}  // namespace
}  // namespace pcbench
