#include "harness/verify/scene_verification.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <span>

#include "harness/verify/block_checks.h"
#include "harness/verify/block_verdicts.h"
#include "harness/verify/image_errors.h"
#include "harness/verify/image_statistics.h"
#include "harness/verify/strategy_image_file.h"
#include "integrands/scenes/scene_integrand.h"
#include "results/exr_file.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

const SceneIntegrand* scene_of(const RunRecord& r) {
  if (!r.plan->render || r.result.status != RunStatus::kOk || r.result.images.size() < 2) {
    return nullptr;
  }
  return dynamic_cast<const SceneIntegrand*>(r.plan->made_integrand.get());
}

bool same_scene(const RunRecord& a, const RunRecord& b) {
  return a.plan->integrand == b.plan->integrand &&
         a.plan->integrand_params.values() == b.plan->integrand_params.values();
}

bool samples_all_paths(const RunRecord& r, const scene::Scene& s) {
  return r.plan->render->samples_all_paths(s);
}

}  // namespace

namespace {

Comparison block_comparison(const RunRecord& a, std::string b_id, std::string b_name,
                            const PyramidResult& t, const ScaleRequirements& requirements,
                            std::string expect) {
  return pyramid_comparison(t, requirements, a.plan->id, std::move(b_id),
                            a.plan->estimator->name + " vs " + b_name, a.plan->integrand->name,
                            a.result.images.size(), std::move(expect));
}

// Closest-hit and shadow rays per CPU second over the run (all threads' CPU time).
double rays_per_cpu_second(const RunRecord& r) {
  std::uint64_t rays = 0;
  for (const auto& [name, count] : r.result.scene_counters) {
    if (name == "camera_rays" || name == "light_rays" || name == "shadow_rays") rays += count;
  }
  double cpu = 0.0;
  for (const ReplicateResult& rep : r.result.replicates) cpu += rep.cpu_seconds;
  return cpu > 0.0 ? static_cast<double>(rays) / cpu : 0.0;
}

// The first run of `sorted` (best-converged first) other than `self`.
const RunRecord* best_other(const std::vector<std::pair<double, const RunRecord*>>& sorted,
                            const RunRecord* self) {
  for (const auto& [se, run] : sorted) {
    if (run != self) return run;
  }
  return nullptr;
}

}  // namespace

namespace {

// One pyramid a session's scene runs call for: run a against run b, or against the exact image
// (b null); `inject` marks the pair that also carries the scene's self-checks.
struct PlannedPyramid {
  const RunRecord* a = nullptr;
  const RunRecord* b = nullptr;
  bool inject = false;
};

// Every pyramid of the session's scene runs, in report order, before any is computed: the count
// fixes the family size that every detectable bias is computed at.
std::vector<PlannedPyramid> plan_pyramids(const std::vector<RunRecord>& records) {
  std::vector<PlannedPyramid> planned;
  std::map<const IntegrandEntry*, bool> injected;  // one set of self-checks per scene
  for (std::size_t i = 0; i < records.size(); ++i) {
    const RunRecord& a = records[i];
    const SceneIntegrand* scene = scene_of(a);
    if (!scene) continue;
    if (scene->exact_radiance()) planned.push_back({.a = &a});
    if (!samples_all_paths(a, scene->scene())) continue;
    for (std::size_t j = i + 1; j < records.size(); ++j) {
      const RunRecord& b = records[j];
      if (!scene_of(b) || !same_scene(a, b) || !samples_all_paths(b, scene->scene())) continue;
      const int biased = a.plan->estimator->biased + b.plan->estimator->biased;
      if (biased == 2) continue;
      const bool inject = biased == 0 && !injected[a.plan->integrand];
      if (inject) injected[a.plan->integrand] = true;
      planned.push_back({.a = &a, .b = &b, .inject = inject});
    }
  }
  return planned;
}

// The pyramids and the self-checks, one per scale of the scene's images.
std::size_t family_members(const std::vector<PlannedPyramid>& planned) {
  std::size_t members = planned.size();
  for (const PlannedPyramid& p : planned) {
    if (!p.inject) continue;
    const Image& like = p.a->result.images.front();
    members += pyramid_block_sizes(like.width, like.height, PyramidOptions{}.tile).size();
  }
  return members;
}

}  // namespace

std::vector<std::pair<Comparison, Verdict>> scene_block_comparisons(
    const std::vector<RunRecord>& records, double alpha, std::size_t other_tested,
    const ScaleRequirements& requirements) {
  const std::vector<PlannedPyramid> planned = plan_pyramids(records);
  const PyramidOptions options{
      .family_size = static_cast<std::uint32_t>(other_tested + family_members(planned))};
  std::vector<std::pair<Comparison, Verdict>> out;
  for (const PlannedPyramid& p : planned) {
    const RunRecord& a = *p.a;
    const SceneIntegrand& scene = *scene_of(a);
    if (p.b == nullptr) {
      const PyramidResult t =
          test_blocks_against_exact(a.result.images, *exact_image(scene), alpha, options);
      const std::string expect = a.plan->estimator->biased ? "biased" : "consistent";
      out.emplace_back(block_comparison(a, "exact", "exact", t, requirements, expect),
                       pyramid_verdict(t, requirements, expect));
      continue;
    }
    const RunRecord& b = *p.b;
    PyramidOptions pair_options = options;
    pair_options.paired = share_streams(*a.plan, *b.plan);
    const auto test = [&](const std::vector<Image>& images) {
      return compare_blocks(images, b.result.images, alpha, pair_options);
    };
    const PyramidResult t = test(a.result.images);
    const bool biased = a.plan->estimator->biased || b.plan->estimator->biased;
    const std::string expect = biased ? "biased" : "consistent";
    out.emplace_back(
        block_comparison(a, b.plan->id, b.plan->estimator->name, t, requirements, expect),
        pyramid_verdict(t, requirements, expect));
    if (!p.inject) continue;
    // The verifier's own checks: at every scale, a bias of twice the reported detectable size
    // (at the family's threshold), put into the brightest block of one honest run, must be
    // flagged.
    for (const BlockSelfCheck& check : pyramid_self_checks(t, a.result.images, test)) {
      Comparison c = block_comparison(a, b.plan->id, b.plan->estimator->name + check.label(),
                                      check.result, requirements, "biased");
      c.a += "+injected";
      out.emplace_back(std::move(c), pyramid_verdict(check.result, requirements, "biased"));
    }
  }
  return out;
}

namespace {

// A cached converged image and its copy beside the report (relative to the report folder).
struct CachedCopy {
  ReferenceImage image;
  std::string file;
};

// A run's image file of one kind (mean, stderr, zmap, reference, strategies), relative to the
// report folder.
std::string image_file(const std::string& run_id, const char* kind) {
  return fmt::format("images/{}_{}.exr", run_id, kind);
}

// The session's scene runs, measured once: each one's pixel statistics, and per scene the honest
// runs that sample every path, best converged (smallest mean standard error) first. A run's
// reference where there is no exact image is the best of the others.
struct SceneRuns {
  std::map<const IntegrandEntry*, std::vector<std::pair<double, const RunRecord*>>> converged;
  std::map<const RunRecord*, PixelStatistics> stats;

  // The best-converged honest run of r's scene other than r; null when there is none.
  const RunRecord* best_other_than(const RunRecord& r) const {
    const auto runs = converged.find(r.plan->integrand);
    return runs == converged.end() ? nullptr : best_other(runs->second, &r);
  }
};

SceneRuns measure_scene_runs(const std::vector<RunRecord>& records) {
  SceneRuns out;
  for (const RunRecord& r : records) {
    const SceneIntegrand* scene = scene_of(r);
    if (!scene) continue;
    PixelStatistics s = pixel_statistics(r.result.images);
    double se = 0.0;
    for (double v : s.standard_error.values) se += v;
    se /= static_cast<double>(s.standard_error.values.size());
    if (!r.plan->estimator->biased && samples_all_paths(r, scene->scene())) {
      out.converged[r.plan->integrand].emplace_back(se, &r);
    }
    out.stats.emplace(&r, std::move(s));
  }
  for (auto& [integrand, runs] : out.converged) std::sort(runs.begin(), runs.end());
  return out;
}

// The cache's converged image of each scene, looked up (and copied beside the report) once per
// scene, when a run first asks for it: an unreadable entry is reported on `warn` once.
class CachedReferences {
 public:
  CachedReferences(const fs::path& folder, const ReferenceCache* cache, std::ostream& warn)
      : folder_(folder), cache_(cache), warn_(warn) {}

  const CachedCopy* find(const scene::Scene& s) {
    auto [it, inserted] = copies_.try_emplace(&s);
    if (inserted && cache_) {
      if (auto found = cache_->find(s.description(), warn_)) {
        const std::string name =
            fmt::format("images/reference_{}.exr", reference_key(s.description()));
        write_exr_rgb(folder_ / name, found->mean);
        it->second = CachedCopy{std::move(*found), name};
      }
    }
    return it->second ? &*it->second : nullptr;
  }

 private:
  const fs::path& folder_;
  const ReferenceCache* cache_;
  std::ostream& warn_;
  std::map<const scene::Scene*, std::optional<CachedCopy>> copies_;
};

// One run's image section as it is written: the section, and its `files` member that names each
// image written (relative to the report folder).
struct ImageSection {
  const fs::path& folder;
  const std::string& stem;  // the run's id
  nlohmann::ordered_json image;
  nlohmann::ordered_json files;

  void write(const char* kind, const Image& picture) {
    const std::string name = image_file(stem, kind);
    write_exr_rgb(folder / name, picture);
    files[kind] = name;
  }
};

// Each replicate image (for other tools and `verify --images`), named in files.replicates.
void write_replicate_images(ImageSection& section, const RunRecord& r) {
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < r.result.images.size(); ++k) {
    const std::string name = image_file(section.stem, fmt::format("rep{}", k).c_str());
    write_exr_rgb(section.folder / name, r.result.images[k]);
    names.push_back(name);
  }
  section.files["replicates"] = std::move(names);
}

// The pixel test, with its z map: against the exact image, or else the best other honest run of
// this session (never the cache: verification trusts no stored image). Nothing without either.
void add_pixel_test(ImageSection& section, const RunRecord& r, const PixelStatistics& s,
                    const std::optional<Image>& exact, const RunRecord* other,
                    const SceneRuns& runs) {
  if (!exact && !other) return;
  const Image z = other ? z_map(s, runs.stats.at(other)) : z_map(s, *exact);
  const PixelTestSummary pixels =
      summarize_z(z, r.result.images,
                  other ? std::span<const Image>(other->result.images) : std::span(&*exact, 1));
  section.image["pixel_test"] = {
      {"test", "pixel-z"},
      {"against", other ? "run " + other->plan->id : "exact"},
      {"statistic", pixels.max_abs_z},
      {"pixels_beyond_4_sigma", pixels.pixels_beyond_4_sigma},
      {"expected_beyond_4_sigma_at_most", pixels.expected_beyond_4_sigma},
      {"low_count_pixels", pixels.low_count_pixels}};
  section.write("zmap", z);
}

// The errors: against the exact image, else a cached converged image, else the best other run.
// The reference's file is named so that plots show it without recomputing it.
void add_errors(ImageSection& section, const RunRecord& r, const PixelStatistics& s,
                const std::optional<Image>& exact, const CachedCopy* copy, const RunRecord* other,
                const SceneRuns& runs) {
  const Image* reference = nullptr;
  const Image* reference_stderr = nullptr;
  if (exact) {
    reference = &*exact;
    section.image["reference"] = "exact";
    section.write("reference", *exact);
  } else if (copy) {
    reference = &copy->image.mean;
    reference_stderr = &copy->image.standard_error;
    section.image["reference"] = "cache";
    section.image["reference_cache"] = copy->image.provenance;
    section.files["reference"] = copy->file;
  } else if (other) {
    reference = &runs.stats.at(other).mean;
    reference_stderr = &runs.stats.at(other).standard_error;
    section.image["reference"] = "run " + other->plan->id;
    section.files["reference"] = image_file(other->plan->id, "mean");
  } else {
    section.image["reference"] = "none";
  }
  if (reference) {
    section.image.update(image_error_fields(r.result.images, r.result.replicates, s.mean,
                                            *reference, reference_stderr));
  }
}

// One scene run's images under folder/images/ and its image section.
nlohmann::ordered_json scene_image_section(const RunRecord& r, const SceneIntegrand& scene,
                                           const SceneRuns& runs, CachedReferences& cached,
                                           const fs::path& folder, bool replicate_images) {
  const PixelStatistics& s = runs.stats.at(&r);
  fs::create_directories(folder / "images");
  ImageSection section{.folder = folder, .stem = r.plan->id, .image = {}, .files = {}};
  section.write("mean", s.mean);
  section.write("stderr", s.standard_error);
  if (replicate_images) write_replicate_images(section, r);
  section.image = {{"width", s.mean.width}, {"height", s.mean.height}};
  section.image["rays_per_cpu_second"] = rays_per_cpu_second(r);

  const std::optional<Image> exact = exact_image(scene);
  const RunRecord* other = exact ? nullptr : runs.best_other_than(r);
  add_pixel_test(section, r, s, exact, other, runs);
  const CachedCopy* copy = exact ? nullptr : cached.find(scene.scene());
  add_errors(section, r, s, exact, copy, other, runs);
  if (r.result.strategy_images) {
    const std::string name = image_file(section.stem, "strategies");
    write_strategy_exr(folder / name, *r.result.strategy_images);
    section.files["strategies"] = name;
    section.image["strategies"] = strategy_shares_json(*r.result.strategy_images, s.mean);
  }
  section.image["files"] = section.files;
  return std::move(section.image);
}

}  // namespace

void write_scene_images(std::vector<RunRecord>& records, const fs::path& folder,
                        const ReferenceCache* cache, bool replicate_images, std::ostream& warn) {
  const SceneRuns runs = measure_scene_runs(records);
  CachedReferences cached(folder, cache, warn);
  for (RunRecord& r : records) {
    const SceneIntegrand* scene = scene_of(r);
    if (!scene) continue;
    r.image = scene_image_section(r, *scene, runs, cached, folder, replicate_images);
  }
}

}  // namespace pcbench
