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

}  // namespace

void write_scene_images(std::vector<RunRecord>& records, const fs::path& folder,
                        const ReferenceCache* cache, bool replicate_images, std::ostream& warn) {
  // The best-converged honest images per scene (smallest mean standard error first): a run's
  // reference where there is no exact one is the best of the others.
  std::map<const IntegrandEntry*, std::vector<std::pair<double, const RunRecord*>>> converged;
  std::map<const RunRecord*, PixelStatistics> stats;
  for (const RunRecord& r : records) {
    const SceneIntegrand* scene = scene_of(r);
    if (!scene) continue;
    PixelStatistics s = pixel_statistics(r.result.images);
    double se = 0.0;
    for (double v : s.standard_error.values) se += v;
    se /= static_cast<double>(s.standard_error.values.size());
    if (!r.plan->estimator->biased && samples_all_paths(r, scene->scene())) {
      converged[r.plan->integrand].emplace_back(se, &r);
    }
    stats.emplace(&r, std::move(s));
  }
  for (auto& [integrand, runs] : converged) std::sort(runs.begin(), runs.end());
  // Cached converged images, looked up (and copied beside the report) once per scene.
  std::map<const scene::Scene*, std::optional<CachedCopy>> cached;
  const auto cached_reference = [&](const scene::Scene& s) -> const CachedCopy* {
    auto [it, inserted] = cached.try_emplace(&s);
    if (inserted && cache) {
      if (auto found = cache->find(s.description(), warn)) {
        const std::string name =
            fmt::format("images/reference_{}.exr", reference_key(s.description()));
        write_exr_rgb(folder / name, found->mean);
        it->second = CachedCopy{std::move(*found), name};
      }
    }
    return it->second ? &*it->second : nullptr;
  };
  for (RunRecord& r : records) {
    const SceneIntegrand* scene = scene_of(r);
    if (!scene) continue;
    const PixelStatistics& s = stats.at(&r);
    fs::create_directories(folder / "images");
    const std::string stem = r.plan->id;
    nlohmann::ordered_json files;
    // Writes one image of this run and names it in `files`.
    const auto write_image = [&](const char* kind, const Image& image) {
      const std::string name = image_file(stem, kind);
      write_exr_rgb(folder / name, image);
      files[kind] = name;
    };
    write_image("mean", s.mean);
    write_image("stderr", s.standard_error);
    if (replicate_images) {
      nlohmann::ordered_json names = nlohmann::ordered_json::array();
      for (std::size_t k = 0; k < r.result.images.size(); ++k) {
        const std::string name = image_file(stem, fmt::format("rep{}", k).c_str());
        write_exr_rgb(folder / name, r.result.images[k]);
        names.push_back(name);
      }
      files["replicates"] = std::move(names);
    }
    nlohmann::ordered_json image = {{"width", s.mean.width}, {"height", s.mean.height}};
    image["rays_per_cpu_second"] = rays_per_cpu_second(r);

    // The pixel test: against the exact image, or else the best other honest run of this
    // session (never the cache: verification trusts no stored image).
    const std::optional<Image> exact = exact_image(*scene);
    const RunRecord* other = exact ? nullptr : best_other(converged[r.plan->integrand], &r);
    if (exact || other) {
      const Image z = other ? z_map(s, stats.at(other)) : z_map(s, *exact);
      const PixelTestSummary pixels =
          summarize_z(z, r.result.images,
                      other ? std::span<const Image>(other->result.images) : std::span(&*exact, 1));
      image["pixel_test"] = {{"test", "pixel-z"},
                             {"against", other ? "run " + other->plan->id : "exact"},
                             {"statistic", pixels.max_abs_z},
                             {"pixels_beyond_4_sigma", pixels.pixels_beyond_4_sigma},
                             {"expected_beyond_4_sigma_at_most", pixels.expected_beyond_4_sigma},
                             {"low_count_pixels", pixels.low_count_pixels}};
      write_image("zmap", z);
    }

    // The errors: against the exact image, else a cached converged image, else the best other
    // run. Its file is named so that plots show it without recomputing it.
    const CachedCopy* copy = exact ? nullptr : cached_reference(scene->scene());
    const Image* reference = nullptr;
    const Image* reference_stderr = nullptr;
    if (exact) {
      reference = &*exact;
      image["reference"] = "exact";
      write_image("reference", *exact);
    } else if (copy) {
      reference = &copy->image.mean;
      reference_stderr = &copy->image.standard_error;
      image["reference"] = "cache";
      image["reference_cache"] = copy->image.provenance;
      files["reference"] = copy->file;
    } else if (other) {
      reference = &stats.at(other).mean;
      reference_stderr = &stats.at(other).standard_error;
      image["reference"] = "run " + other->plan->id;
      files["reference"] = image_file(other->plan->id, "mean");
    } else {
      image["reference"] = "none";
    }
    if (reference) {
      image.update(image_error_fields(r.result.images, r.result.replicates, s.mean, *reference,
                                      reference_stderr));
    }
    if (r.result.strategy_images) {
      const std::string name = image_file(stem, "strategies");
      write_strategy_exr(folder / name, *r.result.strategy_images);
      files["strategies"] = name;
      image["strategies"] = strategy_shares_json(*r.result.strategy_images, s.mean);
    }
    image["files"] = files;
    r.image = std::move(image);
  }
}

}  // namespace pcbench
