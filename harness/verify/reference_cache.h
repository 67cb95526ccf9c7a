// Converged reference images of scenes, kept across sessions in a folder (by default
// results/references/, git-ignored) and keyed by a hash of the scene as it is traced: every
// material, triangle, point light, the camera, the resolution and the maximum path length L.
// The scene's name and file do not enter the key, so the same scene read from two files shares
// its reference, and any edit to a scene or its settings makes a new one.
//
// What a cached image is for: the RMSE and relative MSE of scene runs where there is no exact
// image. Equal-time comparisons need a reference whose own noise is far below the runs' noise;
// the best other run of the same session is only as converged as the runs it measures.
// What it is not for: verification. The tile and pixel tests compare the session's own
// independent estimators, so a stale or wrong cache entry can never make a run pass.
//
// An entry is two files: <scene>-<key>.exr (channels R, G, B: the mean; stderr.R, stderr.G,
// stderr.B: its standard error) and <scene>-<key>.json (how it was made). Both are written
// atomically, the image first: an image without its JSON is no entry.
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "integrands/scenes/scene_description.h"
#include "results/image.h"

namespace pcbench {

inline constexpr const char* kDefaultReferenceCache = "results/references";

struct ReferenceImage {
  Image mean;
  Image standard_error;
  // How it was made: estimator, params, samples, replicates, seed, version, relative variance.
  nlohmann::ordered_json provenance;
};

// 16 hex digits of the hash over the scene's traced content (see above).
std::string reference_key(const scene::SceneDescription& scene);

class ReferenceCache {
 public:
  explicit ReferenceCache(std::filesystem::path folder) : folder_(std::move(folder)) {}

  const std::filesystem::path& folder() const { return folder_; }
  // <folder>/<scene>-<key>.exr
  std::filesystem::path image_path(const scene::SceneDescription& scene) const;

  // The entry for this scene, or nothing. An entry that cannot be read, or whose key or size do
  // not match, is derived data gone bad: it is reported on `warn` and treated as absent.
  std::optional<ReferenceImage> find(const scene::SceneDescription& scene,
                                     std::ostream& warn) const;

  // Stores `image` unless the cached entry is at least as converged (relative variance); returns
  // whether it stored. Throws std::runtime_error when the files cannot be written.
  bool store(const scene::SceneDescription& scene, const ReferenceImage& image,
             std::ostream& warn) const;

 private:
  std::filesystem::path folder_;
};

}  // namespace pcbench
