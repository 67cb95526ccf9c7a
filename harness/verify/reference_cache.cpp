#include "harness/verify/reference_cache.h"

#include <fmt/format.h>

#include <exception>

#include "base/atomic_file.h"
#include "base/text_file.h"
#include "base/text_hash.h"
#include "harness/verify/image_statistics.h"
#include "results/exr_file.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFormat = "pcbench-reference-1";

// Exact text of every number ("%a": no rounding), so equal scenes hash equal on every machine.
std::string exact(double v) {
  return fmt::format("{:a}", v);
}
std::string exact(const scene::Vec3& v) {
  return fmt::format("{:a},{:a},{:a}", v.x, v.y, v.z);
}
std::string exact(const scene::Rgb& v) {
  return fmt::format("{:a},{:a},{:a}", v.r, v.g, v.b);
}

std::string stem(const scene::SceneDescription& scene) {
  // The name only makes the folder readable; characters a file name cannot hold become '_'.
  std::string name = scene.name.empty() ? "scene" : scene.name;
  for (char& c : name) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '-' || c == '_';
    if (!plain) c = '_';
  }
  return name + "-" + reference_key(scene);
}

const char* const kChannels[kImageChannels] = {"R", "G", "B"};
constexpr const char* kStderrLayer = "stderr";

}  // namespace

std::string reference_key(const scene::SceneDescription& scene) {
  std::uint64_t hash = fnv1a(kFnvOffset, kFormat);
  for (const scene::Material& m : scene.materials) {
    hash = fnv1a(hash, fmt::format("material {} {} {}", static_cast<int>(m.kind), exact(m.albedo),
                                   exact(m.exponent)));
  }
  for (const scene::Triangle& t : scene.triangles) {
    hash = fnv1a(hash, fmt::format("triangle {} {} {} {} {}", exact(t.p0), exact(t.p1), exact(t.p2),
                                   t.material, exact(t.emission)));
  }
  for (const scene::PointLight& l : scene.point_lights) {
    hash = fnv1a(hash, fmt::format("point {} {}", exact(l.position), exact(l.intensity)));
  }
  const scene::Camera& c = scene.camera;
  hash = fnv1a(hash, fmt::format("camera {} {} {} {}", exact(c.position), exact(c.look_at),
                                 exact(c.up), exact(c.fov_degrees)));
  hash = fnv1a(hash, fmt::format("image {}x{} L={}", scene.width, scene.height, scene.max_length));
  return fmt::format("{:016x}", hash);
}

fs::path ReferenceCache::image_path(const scene::SceneDescription& scene) const {
  return folder_ / (stem(scene) + ".exr");
}

std::optional<ReferenceImage> ReferenceCache::find(const scene::SceneDescription& scene,
                                                   std::ostream& warn) const {
  const fs::path image_file = image_path(scene);
  const fs::path json_file = fs::path(image_file).replace_extension(".json");
  if (!fs::exists(json_file) || !fs::exists(image_file)) return std::nullopt;
  try {
    ReferenceImage out;
    out.provenance =
        nlohmann::ordered_json::parse(read_text_file(json_file, "the reference's provenance"));
    const nlohmann::ordered_json& meta = out.provenance;
    if (meta.value("format", "") != kFormat || meta.value("key", "") != reference_key(scene)) {
      throw std::runtime_error("its format or key is not this scene's");
    }
    std::uint32_t width = 0, height = 0;
    const std::vector<ExrChannel> channels = read_exr(image_file, width, height);
    if (width != scene.width || height != scene.height) {
      throw std::runtime_error(
          fmt::format("it is {}x{}, the scene {}x{}", width, height, scene.width, scene.height));
    }
    out.mean = Image(width, height);
    out.standard_error = Image(width, height);
    std::uint32_t found = 0;
    for (const ExrChannel& ch : channels) {
      for (std::uint32_t c = 0; c < kImageChannels; ++c) {
        Image* target = ch.name == kChannels[c] ? &out.mean
                        : ch.name == std::string(kStderrLayer) + "." + kChannels[c]
                            ? &out.standard_error
                            : nullptr;
        if (!target) continue;
        ++found;
        for (std::size_t i = 0; i < ch.values.size(); ++i) {
          target->values[i * kImageChannels + c] = ch.values[i];
        }
      }
    }
    if (found != 2 * kImageChannels) {
      throw std::runtime_error(
          "it lacks some of the channels R, G, B, stderr.R, stderr.G, stderr.B");
    }
    return out;
  } catch (const std::exception& e) {
    warn << fmt::format("pcbench: warning: ignoring the cached reference {}: {}\n",
                        image_file.string(), e.what());
    return std::nullopt;
  }
}

bool ReferenceCache::store(const scene::SceneDescription& scene, const ReferenceImage& image,
                           std::ostream& warn) const {
  const double quality = relative_variance(image.mean, image.standard_error);
  if (const auto cached = find(scene, warn)) {
    if (relative_variance(cached->mean, cached->standard_error) <= quality) return false;
  }
  std::vector<ExrChannel> channels = rgb_channels(image.mean);
  for (ExrChannel& c : rgb_channels(image.standard_error, kStderrLayer)) {
    channels.push_back(std::move(c));
  }
  const fs::path image_file = image_path(scene);
  fs::create_directories(folder_);
  write_exr(image_file, scene.width, scene.height, channels);
  nlohmann::ordered_json meta = {{"format", kFormat},
                                 {"key", reference_key(scene)},
                                 {"scene", scene.name},
                                 {"source", scene.source},
                                 {"width", scene.width},
                                 {"height", scene.height},
                                 {"max_length", scene.max_length},
                                 {"relative_variance", quality}};
  for (const auto& [k, v] : image.provenance.items()) meta[k] = v;
  write_file_atomically(fs::path(image_file).replace_extension(".json"), meta.dump(2) + "\n");
  return true;
}

}  // namespace pcbench
