#include "harness/run/saved_run.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace pcbench {

nlohmann::ordered_json exact_number(double value) {
  if (std::isfinite(value)) return value;
  if (std::isnan(value)) return "nan";
  return value > 0.0 ? "inf" : "-inf";
}

namespace {

using Json = nlohmann::ordered_json;

double read_number(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string text = j.get<std::string>();
  if (text == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (text == "inf") return std::numeric_limits<double>::infinity();
  if (text == "-inf") return -std::numeric_limits<double>::infinity();
  throw std::runtime_error("'" + text + "' is not a number");
}

Json numbers_json(const std::vector<double>& values) {
  Json out = Json::array();
  for (double v : values) out.push_back(exact_number(v));
  return out;
}

std::vector<double> read_numbers(const nlohmann::json& j) {
  std::vector<double> out;
  out.reserve(j.size());
  for (const auto& v : j) out.push_back(read_number(v));
  return out;
}

// Inverse of a to_string over an enum's values.
template <typename Enum, std::size_t N>
Enum enum_from(const std::string& text, const Enum (&values)[N], const char* what) {
  for (Enum value : values) {
    if (text == to_string(value)) return value;
  }
  throw std::runtime_error("unknown " + std::string(what) + " '" + text + "'");
}

constexpr RunStatus kStatuses[] = {RunStatus::kOk, RunStatus::kInvalid, RunStatus::kError,
                                   RunStatus::kNotRun};
constexpr ReferenceKind kReferenceKinds[] = {ReferenceKind::kExact, ReferenceKind::kNumerical,
                                             ReferenceKind::kRendered, ReferenceKind::kNone};

Json replicate_json(const ReplicateResult& r) {
  Json checkpoints = Json::array();
  for (const Checkpoint& c : r.checkpoints) {
    checkpoints.push_back({c.samples, exact_number(c.estimate), exact_number(c.cpu_seconds),
                           exact_number(c.seconds)});
  }
  return Json{{"estimate", exact_number(r.estimate)},
              {"variance", exact_number(r.variance)},
              {"mean_abs", exact_number(r.mean_abs)},
              {"n", r.n},
              {"nonfinite", r.nonfinite},
              {"first_nonfinite_sample",
               r.first_nonfinite_sample ? Json(*r.first_nonfinite_sample) : Json(nullptr)},
              {"seconds", exact_number(r.seconds)},
              {"cpu_seconds", exact_number(r.cpu_seconds)},
              {"largest", numbers_json(r.largest)},
              {"nonzero", r.nonzero},
              {"effective_samples", exact_number(r.effective_samples)},
              {"largest_square_share", exact_number(r.largest_square_share)},
              {"checkpoints", checkpoints}};
}

ReplicateResult read_replicate(const nlohmann::json& j) {
  ReplicateResult r;
  r.estimate = read_number(j.at("estimate"));
  r.variance = read_number(j.at("variance"));
  r.mean_abs = read_number(j.at("mean_abs"));
  r.n = j.at("n").get<std::uint64_t>();
  r.nonfinite = j.at("nonfinite").get<std::uint64_t>();
  if (!j.at("first_nonfinite_sample").is_null()) {
    r.first_nonfinite_sample = j.at("first_nonfinite_sample").get<std::uint64_t>();
  }
  r.seconds = read_number(j.at("seconds"));
  r.cpu_seconds = read_number(j.at("cpu_seconds"));
  r.largest = read_numbers(j.at("largest"));
  r.nonzero = j.at("nonzero").get<std::uint64_t>();
  r.effective_samples = read_number(j.at("effective_samples"));
  r.largest_square_share = read_number(j.at("largest_square_share"));
  for (const auto& c : j.at("checkpoints")) {
    r.checkpoints.push_back({.samples = c.at(0).get<std::uint64_t>(),
                             .estimate = read_number(c.at(1)),
                             .cpu_seconds = read_number(c.at(2)),
                             .seconds = read_number(c.at(3))});
  }
  return r;
}

Json image_json(const Image& image) {
  return {{"width", image.width}, {"height", image.height}, {"values", numbers_json(image.values)}};
}

Image read_image(const nlohmann::json& j) {
  Image restored(j.at("width").get<std::uint32_t>(), j.at("height").get<std::uint32_t>());
  restored.values = read_numbers(j.at("values"));
  if (restored.values.size() != restored.pixel_count() * kImageChannels) {
    throw std::runtime_error("an image's values do not match its width and height");
  }
  return restored;
}

Json strategy_images_json(const StrategyImages& images) {
  Json layers = Json::array();
  for (const StrategyLayer& layer : images.layers) {
    layers.push_back({{"s", layer.s}, {"t", layer.t}, {"image", image_json(layer.image)}});
  }
  return Json{{"replicates", images.replicates}, {"layers", layers}};
}

StrategyImages read_strategy_images(const nlohmann::json& j) {
  StrategyImages images;
  images.replicates = j.at("replicates").get<std::uint32_t>();
  for (const auto& layer : j.at("layers")) {
    images.layers.push_back({.s = layer.at("s").get<std::uint32_t>(),
                             .t = layer.at("t").get<std::uint32_t>(),
                             .image = read_image(layer.at("image"))});
  }
  return images;
}

Json result_json(const RunResult& r) {
  Json replicates = Json::array();
  for (const ReplicateResult& rep : r.replicates) replicates.push_back(replicate_json(rep));
  Json images = Json::array();
  for (const Image& image : r.images) images.push_back(image_json(image));
  Json scene_counters = Json::array();
  for (const auto& [name, count] : r.scene_counters) scene_counters.push_back({name, count});
  Json first_nonfinite = nullptr;
  if (r.first_nonfinite) {
    first_nonfinite = {{"seed", r.first_nonfinite->seed},
                       {"replicate", r.first_nonfinite->replicate},
                       {"sample", r.first_nonfinite->sample}};
  }
  Json out{{"status", to_string(r.status)},
           {"error", r.error},
           {"reference",
            {{"value", exact_number(r.reference.value)},
             {"kind", to_string(r.reference.kind)},
             {"uncertainty", exact_number(r.reference.uncertainty)},
             {"dof", exact_number(r.reference.dof)},
             {"magnitude", exact_number(r.reference.magnitude)}}},
           {"counters",
            {{"camera_paths", r.counters.camera_paths},
             {"light_paths", r.counters.light_paths},
             {"connections", r.counters.connections},
             {"importance_evaluations", r.counters.importance_evaluations}}},
           {"wall_seconds", exact_number(r.wall_seconds)},
           {"first_nonfinite", first_nonfinite},
           {"independent_samples", r.independent_samples},
           {"replicates", replicates},
           {"images", images},
           {"scene_counters", scene_counters}};
  // Only a run that gathered them has the key: journals without it read as before.
  if (r.strategy_images) out["strategy_images"] = strategy_images_json(*r.strategy_images);
  return out;
}

RunResult read_result(const nlohmann::json& j) {
  RunResult r;
  r.status = enum_from(j.at("status").get<std::string>(), kStatuses, "status");
  r.error = j.at("error").get<std::string>();
  const auto& ref = j.at("reference");
  r.reference.value = read_number(ref.at("value"));
  r.reference.kind = enum_from(ref.at("kind").get<std::string>(), kReferenceKinds, "reference");
  r.reference.uncertainty = read_number(ref.at("uncertainty"));
  r.reference.dof = read_number(ref.at("dof"));
  r.reference.magnitude = read_number(ref.at("magnitude"));
  const auto& c = j.at("counters");
  r.counters.camera_paths = c.at("camera_paths").get<std::uint64_t>();
  r.counters.light_paths = c.at("light_paths").get<std::uint64_t>();
  r.counters.connections = c.at("connections").get<std::uint64_t>();
  r.counters.importance_evaluations = c.at("importance_evaluations").get<std::uint64_t>();
  r.wall_seconds = read_number(j.at("wall_seconds"));
  if (const auto& f = j.at("first_nonfinite"); !f.is_null()) {
    r.first_nonfinite = NonfiniteLocation{.seed = f.at("seed").get<std::uint64_t>(),
                                          .replicate = f.at("replicate").get<std::uint32_t>(),
                                          .sample = f.at("sample").get<std::uint64_t>()};
  }
  r.independent_samples = j.at("independent_samples").get<bool>();
  for (const auto& rep : j.at("replicates")) r.replicates.push_back(read_replicate(rep));
  for (const auto& image : j.at("images")) r.images.push_back(read_image(image));
  if (j.contains("strategy_images")) {
    r.strategy_images = read_strategy_images(j.at("strategy_images"));
  }
  for (const auto& counter : j.at("scene_counters")) {
    r.scene_counters.emplace_back(counter.at(0).get<std::string>(),
                                  counter.at(1).get<std::uint64_t>());
  }
  return r;
}

}  // namespace

std::string saved_run_text(const SavedRun& run) {
  const Json out{{"format", kSavedRunFormat},
                 {"version", kSavedRunVersion},
                 {"id", run.id},
                 {"seed", run.seed},
                 {"samples", run.samples},
                 {"replicates", run.replicates},
                 {"pilot_samples", run.pilot_samples},
                 {"pilot_cpu_per_sample", exact_number(run.pilot_cpu_per_sample)},
                 {"result", result_json(run.result)}};
  return out.dump() + "\n";
}

SavedRun read_saved_run(const std::string& text) {
  const nlohmann::json json = nlohmann::json::parse(text);
  if (json.at("format") != kSavedRunFormat || json.at("version") != kSavedRunVersion) {
    throw std::runtime_error(fmt::format("not a saved run of this pcbench (format {} version {})",
                                         kSavedRunFormat, kSavedRunVersion));
  }
  SavedRun run;
  run.id = json.at("id").get<std::string>();
  run.seed = json.at("seed").get<std::uint64_t>();
  run.samples = json.at("samples").get<std::uint64_t>();
  run.replicates = json.at("replicates").get<std::uint32_t>();
  run.pilot_samples = json.at("pilot_samples").get<std::uint64_t>();
  run.pilot_cpu_per_sample = read_number(json.at("pilot_cpu_per_sample"));
  run.result = read_result(json.at("result"));
  return run;
}

}  // namespace pcbench
