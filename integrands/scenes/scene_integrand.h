// Scenes as integrands: the table entries for the built-in scenes and for scene files, and the
// Integrand that holds a traced-ready Scene.
//
// Runs of the same scene with the same resolution and maximum length share one Scene, so its
// BVH is built once per invocation whatever the number of runs (`scene_builds()` counts them).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "integrands/integrand.h"
#include "integrands/registry.h"
#include "integrands/scenes/scene.h"

namespace pcbench {

class SceneIntegrand : public Integrand {
 public:
  explicit SceneIntegrand(std::shared_ptr<const scene::Scene> scene);
  std::unique_ptr<PathWorkspace> make_workspace() const override;  // throws: scenes render
  Reference reference() const override;

  const scene::Scene& scene() const { return *scene_; }
  // The exact image value per channel where the scene has one (a furnace), else nothing.
  const std::optional<scene::Rgb>& exact_radiance() const { return exact_; }

 private:
  std::shared_ptr<const scene::Scene> scene_;
  std::optional<scene::Rgb> exact_;
};

// The entries of the built-in scenes (tag "scene").
std::vector<IntegrandEntry> scene_integrand_entries();

// An entry for the scene file at `path` (read and checked now: InputError on any problem).
IntegrandEntry scene_file_entry(const std::string& path);

// How many Scenes (BVHs) were built so far in this process.
std::uint64_t scene_builds();

// Le · Σ_{k<L} ρ^k when every triangle emits the same Le and has the same diffuse albedo ρ, there
// is no point light and the triangles close a convex enclosure: then every path of length
// k <= L carries exactly Le ρ^(k-1), in every pixel.
std::optional<scene::Rgb> furnace_value(const scene::SceneDescription& scene);

}  // namespace pcbench
