// Scene text to a traced-ready Scene (fuzz/fuzz_inputs.h).
#include <fstream>
#include <string>

#include "base/errors.h"
#include "fuzz/fuzz_inputs.h"
#include "integrands/scenes/scene.h"
#include "integrands/scenes/scene_file.h"
#include "integrands/scenes/scene_integrand.h"

namespace pcbench::fuzz {
namespace {

constexpr std::string_view kObjMarker = "\n#obj\n";

// Writes the OBJ part of the input (if any) where the scene's "file": "mesh.obj" finds it;
// returns the scene part.
std::string_view split_obj(std::string_view text, const std::filesystem::path& scratch) {
  const std::filesystem::path mesh = scratch / "mesh.obj";
  const std::size_t marker = text.find(kObjMarker);
  if (marker == std::string_view::npos) {
    std::filesystem::remove(mesh);
    return text;
  }
  const std::string_view obj = text.substr(marker + kObjMarker.size());
  std::ofstream(mesh, std::ios::binary | std::ios::trunc)
      .write(obj.data(), static_cast<std::streamsize>(obj.size()));
  return text.substr(0, marker);
}

}  // namespace

Outcome check_scene_text(std::string_view text, const std::filesystem::path& scratch) {
  const std::string_view scene_text = split_obj(text, scratch);
  try {
    scene::SceneDescription description = scene::parse_scene_json(scene_text, "fuzz.json", scratch);
    // Building the BVH costs far more than parsing; a large mesh says nothing new about it.
    if (description.triangles.size() <= kMaxFuzzTriangles) {
      static_cast<void>(furnace_value(description));
      const scene::Scene traced(std::move(description));
      static_cast<void>(traced.traits());
    }
  } catch (const InputError&) {
    return Outcome::kRejected;
  }
  return Outcome::kAccepted;
}

}  // namespace pcbench::fuzz
